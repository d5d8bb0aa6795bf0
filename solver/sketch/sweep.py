"""The sticking sweep of the disk sketch (book 4.1.4) on the compiled disk loci: the twin of
:func:`models.sketch.disk_sketch.sticking_spans` that the solver passes to the sketches,
the gross-motion bounds (4.3, 4.4) and the spiral's sweeps (4.5), as their ``spans``.

All the force angles of a call are answered by one compiled call
(:func:`solver.kernels.disk.sticking_spans`: each angle's boundary built, put in the world
and cut by the sticking line, without a Python object per locus); an angle the kernel
hands back (a scene the reference refuses, a boundary off its residual tolerance) is
answered by the reference, which raises what it raises. Tested against the reference
(tests/solver/sketch/test_sweep.py)."""

from __future__ import annotations

import threading
from collections.abc import Sequence

import numpy as np

from models.core.mpp import perp
from models.core.scene import PushScene
from models.sketch.disk_sketch import sticking_spans as reference_spans
from solver.kernels.codes import SPAN_FOUND, SPAN_REFERENCE

_scratch = threading.local()


def _buffers(size: int) -> tuple[np.ndarray, np.ndarray]:
    """This thread's work arrays for rings of ``size`` points (reused between calls)."""
    have = getattr(_scratch, "arrays", None)
    if have is None or have[1].shape[0] < size:
        have = (np.empty((size, 2)), np.empty(size))
        _scratch.arrays = have
    return have


def sticking_spans(scene: PushScene, phis: Sequence[float], n_points: int) -> list[tuple[float, float] | None]:
    """:func:`models.sketch.disk_sketch.sticking_spans`, compiled: at each force angle, the
    sticking line's span inside {COR}_phi where sticking agrees with its sense, or None."""
    from solver.kernels import disk

    phi = np.ascontiguousarray(phis, dtype=float)
    if phi.size == 0:
        return []
    if n_points < 8:
        return reference_spans(scene, phis, n_points)  # the reference says why not
    t = scene.tolerances
    geometry = np.array([scene.disk_radius, *scene.center_of_mass, *scene.contact_point, *scene.normal,
                         scene.edge_angle])
    tol = np.array([t.root_rtol, float(t.root_max_iter), t.translation_rel, t.max_relative_moment_arm,
                    t.boundary_residual_rel, t.grazing_sin])
    size = int(disk.ring_size(n_points))
    work, ts = _buffers(size)
    lo, hi = np.empty(phi.size), np.empty(phi.size)
    status = np.empty(phi.size, dtype=np.int8)
    disk.sticking_spans(phi, n_points, geometry, np.ascontiguousarray(perp(scene.push_hat)), tol, lo, hi, work, ts,
                        status)
    out: list[tuple[float, float] | None] = [None] * phi.size
    for i in np.flatnonzero(status == SPAN_FOUND):
        out[i] = (float(lo[i]), float(hi[i]))
    for i in np.flatnonzero(status == SPAN_REFERENCE):
        out[i] = reference_spans(scene, [float(phi[i])], n_points)[0]
    return out
