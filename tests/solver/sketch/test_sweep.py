"""The compiled disk loci (solver/kernels/disk.py) and the compiled sticking sweep
(solver/sketch/sweep.py) against their references in models: the boundary polygon of the
analytic disk locus (3.30, 3.35; models/locus/cor_disk.py, boundary_locals) and the sweep
of 4.1.4 (models/sketch/disk_sketch.py, sticking_spans), on seeded scenes and the hard
ones: the force line through the CM (alpha . c -> 0, loci growing like a^2 / |alpha . c|),
the outer dipods reaching the disk (mu = 1/sqrt 2) and no outer piece at all (mu >= 1),
very large moment arms, odd and small point counts, every scale. Both must give the same
points and spans to rounding, and the same refusals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from models.core.scene import PushScene
from models.core.tolerances import DEFAULT, Tolerances
from models.locus.cor_disk import BoundaryNotConverged, boundary_locals
from models.push import gross_bounds as gb
from models.sketch import disk_sketch as ds
from solver.kernels.disk import ring_size, rings
from solver.sketch.sweep import sticking_spans
from tests.scenes import SEED

AGREE = 1e-12
"""Largest difference of a boundary point, relative to the locus's scale."""
AGREE_SPAN = 1e-9
"""Largest difference of a span's end, relative to its distance from the contact: where the
sticking line meets a boundary edge at a shallow angle, a last-bit difference of the edge's
points moves the crossing by that much over the sine of the angle (2.8e-10 at worst over the
seeded cases; the boundary's own resolution error is about 1e-4 at 64 points)."""


def _rings(mus, n_points, tol=DEFAULT):
    mus = np.asarray(mus, dtype=float)
    out = np.empty((mus.size, ring_size(n_points), 2))
    residual, iterations = np.empty(mus.size), np.empty(mus.size, dtype=np.int64)
    converged = np.empty(mus.size, dtype=np.bool_)
    rings(mus, n_points, tol.root_rtol, tol.root_max_iter, out, residual, iterations, converged)
    return out, residual, converged


MUS = [1e-9, 1e-3, 0.2, 0.5, 1.0 / math.sqrt(2.0), 0.70710678, 0.7072, 0.9, 0.999999, 1.0, 1.5, 40.0, 1e6]


@pytest.mark.parametrize("n_points", [8, 9, 64, 256, 1025])
def test_the_compiled_boundary_is_the_reference_point_for_point(n_points):
    """(3.30), (3.35) and the perimeter arcs: every piece layout (outer + inner, outer + arc +
    inner at mu >= 1/sqrt 2, arc + inner at mu >= 1), the same points in the same order."""
    got, residual, converged = _rings(MUS, n_points)
    for k, (ref, ref_res, _) in enumerate(boundary_locals(MUS, n_points)):
        assert converged[k]
        assert got[k].shape == ref.shape
        scale = float(np.max(np.abs(ref)))
        assert np.max(np.abs(got[k] - ref)) <= AGREE * scale, MUS[k]
        assert residual[k] <= DEFAULT.boundary_residual_rel and abs(residual[k] - ref_res) <= 1e-12


def _scene(rng, a):
    contact = a * rng.uniform(-1.5, 1.5, 2)
    edge = rng.uniform(-math.pi, math.pi)
    return PushScene.create(a, contact, edge, edge + math.pi / 2 + rng.uniform(-1.2, 1.2),
                            a * rng.uniform(-0.3, 0.3, 2))


def _same_spans(scene, phis, n_points):
    got = sticking_spans(scene, phis, n_points)
    ref = ds.sticking_spans(scene, phis, n_points)
    scale = scene.disk_radius * (1.0 + float(np.max(np.abs([*scene.contact_point, *scene.center_of_mass]))) /
                                 scene.disk_radius)
    for g, r, phi in zip(got, ref, phis):
        assert (g is None) == (r is None), phi
        if g is not None:
            # a span's far end lies up to a^2 / |alpha . c| away: compare relative to it
            far = max(scale, abs(r[0]), abs(r[1]))
            assert abs(g[0] - r[0]) <= AGREE_SPAN * far and abs(g[1] - r[1]) <= AGREE_SPAN * far, (phi, g, r)
    return got


@pytest.mark.parametrize("a", [1e-6, 1.0, 1e6])
def test_the_compiled_sweep_is_the_reference_at_every_angle(a):
    """4.1.4 at 40 seeded scenes, each at its own sweep's angles (uniform over the cone and
    crowding towards the force line through the CM) at 64 and 257 points: the same spans."""
    rng = np.random.default_rng(SEED)
    found = 0
    for _ in range(40):
        scene = _scene(rng, a)
        nu = math.atan(rng.uniform(0.05, 2.0))
        phis = [float(p) for p in ds.sweep_angles(scene, nu)]
        for n_points in (64, 257):
            found += sum(s is not None for s in _same_spans(scene, phis, n_points))
    assert found > 500  # the cases compared include many spans, not only empty ones


def test_the_force_line_through_the_cm_is_a_translation_both_ways():
    """alpha . c -> 0 (3.3.11.1): at the angle where the turned force passes through the CM
    both give no span (a translation), and the same spans as it is approached."""
    scene = gb.encounter_scene(1.0, 0.4)
    c = scene.contact_rel
    n = scene.normal
    phi0 = math.atan2(n[0] * c[1] - n[1] * c[0], float(n @ c))
    offsets = [0.0, 1e-15, -1e-15, 1e-12, -1e-9, 1e-6, -1e-3]
    got = _same_spans(scene, [phi0 + o for o in offsets], 256)
    assert got[0] is None


def test_a_boundary_off_its_tolerance_is_refused_as_the_reference_refuses_it():
    """An iteration cap the outer root solve (3.35) cannot meet: the compiled sweep hands the
    angle back and the reference raises its error, the same as without the kernel."""
    tight = Tolerances(root_max_iter=1)
    scene = PushScene.create(1.0, [-0.5, -0.3], 1.5707963267948966, 0.0, tolerances=tight)
    with pytest.raises(BoundaryNotConverged):
        ds.sticking_spans(scene, [0.1], 256)
    with pytest.raises(BoundaryNotConverged):
        sticking_spans(scene, [0.1], 256)


def test_the_bounds_of_4_3_and_4_4_are_the_same_on_the_compiled_sweep():
    """The gross-motion bounds built on the sweep (4.3 fence alignment, 4.4 disk encounter):
    the same integrals to rounding whichever sweep answers."""
    args = (1.0, 1.2, 0.9, 0.3, 1.2, 0.4)
    ref = gb.fence_bounds_exact(*args, n_nodes=8, n_points=128)
    got = gb.fence_bounds_exact(*args, n_nodes=8, n_points=128, spans=sticking_spans)
    for key in ref:
        assert got[key].value == pytest.approx(ref[key].value, rel=1e-10, abs=1e-12), key
    ref = gb.encounter_bounds_exact(1.0, math.pi / 4, 0.5, n_nodes=8, n_points=128)
    got = gb.encounter_bounds_exact(1.0, math.pi / 4, 0.5, n_nodes=8, n_points=128, spans=sticking_spans)
    for key in ref:
        assert got[key].value == pytest.approx(ref[key].value, rel=1e-10, abs=1e-12), key
