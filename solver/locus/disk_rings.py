"""The boundaries of many analytic disk loci (3.30, 3.35) on the compiled kernel: the twin
of :func:`models.locus.cor_disk.disk_boundaries` that the solver passes to the fence maps
(models/feeder/fence.py: the slip paths' thousands of small loci, book 5.1 and 7.5) as
their ``boundaries``.

Every locus of a call is built by one compiled call (:func:`solver.kernels.disk.rings`) and
put in the world by array arithmetic, in the same order of operations as
``PushScene.to_world``; a call with a locus off its residual tolerance, or a scene the
reference refuses, is answered by the reference, which raises what it raises. Tested
against the reference (tests/solver/locus/test_disk_rings.py)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from models.core.mpp import perp
from models.core.scene import PushScene
from models.core.tolerances import Tolerances
from models.locus.cor_disk import disk_boundaries as reference_boundaries


def disk_boundaries(scenes: Sequence[PushScene], n_points: int = 256, tol: Tolerances | None = None) -> list[np.ndarray]:
    """:func:`models.locus.cor_disk.disk_boundaries`, compiled: the world boundary of each
    bounded scene's disk locus with ``n_points`` points."""
    from solver.kernels import disk

    if not scenes:
        return []
    if n_points < 8 or any(s.is_translation for s in scenes):
        return reference_boundaries(scenes, n_points, tol)  # the reference says why not
    tol = tol or scenes[0].tolerances
    mus = np.array([s.relative_moment_arm for s in scenes])
    local = np.empty((mus.size, int(disk.ring_size(n_points)), 2))
    residual = np.empty(mus.size)
    iterations = np.empty(mus.size, dtype=np.int64)
    converged = np.empty(mus.size, dtype=np.bool_)
    disk.rings(mus, n_points, tol.root_rtol, tol.root_max_iter, local, residual, iterations, converged)
    if not (np.all(converged) and np.all(residual <= tol.boundary_residual_rel)):
        return reference_boundaries(scenes, n_points, tol)
    a = np.array([s.disk_radius for s in scenes])[:, None, None]
    cm = np.array([s.center_of_mass for s in scenes])[:, None, :]
    e1 = np.array([s.axis for s in scenes])[:, None, :]
    e2 = perp(e1)
    local = local * a
    world = cm + local[..., :1] * e1 + local[..., 1:2] * e2
    return list(world)
