"""Configuration maps and their products (book 5.2, (5.1)-(5.5))."""

import numpy as np

from models.feeder.arcs import TWO_PI, Arcs
from models.feeder.maps import ConfigurationMap, matrix_product, sequence

N = 360


def random_map(rng, bands=4):
    """A rectangular map: random disjoint bands, each with a random kernel of 1-2 arcs."""
    starts = np.sort(rng.uniform(0, TWO_PI, bands))
    gaps = np.diff(np.r_[starts, starts[0] + TWO_PI])
    b = tuple(Arcs.of([(s, rng.uniform(0.05, 0.8) * g)]) for s, g in zip(starts, gaps))
    k = tuple(Arcs.of([(rng.uniform(0, TWO_PI), rng.uniform(0.1, 2.0)) for _ in range(rng.integers(1, 3))])
              for _ in range(bands))
    return ConfigurationMap(bands=b, kernels=k)


def point_in(arcs, rng):
    s, w = arcs.arcs[rng.integers(len(arcs.arcs))]
    return s + rng.uniform(0.0, w)


def composed_outcomes(m1, m2, rng, n):
    """(theta_i, theta_f) pairs of the exact product (5.1): theta_i in a kernel of m1, an
    intermediate alpha in that kernel's band and in a kernel of m2, theta_f in its band."""
    out = []
    while len(out) < n:
        k = rng.integers(len(m1.bands))
        alpha = point_in(m1.bands[k], rng)
        js = [j for j, kern in enumerate(m2.kernels) if kern.contains(alpha)]
        if js:
            j = js[rng.integers(len(js))]
            out.append((point_in(m1.kernels[k], rng), point_in(m2.bands[j], rng)))
    return out


def holds(cmap, theta_i, theta_f):
    return any(b.contains(theta_f) and k.contains(theta_i) for b, k in zip(cmap.bands, cmap.kernels))


def test_symbolic_product_contains_every_composed_outcome_5_1_5_4():
    """(5.4) with the code sets 2C_j = {k : 1B_k meets 2K_j} is a rectangularized product
    (5.3): it holds every outcome of the exact product (5.1)."""
    rng = np.random.default_rng(11)
    for _ in range(30):
        m1, m2 = random_map(rng), random_map(rng)
        prod = m1.then(m2)
        assert all(holds(prod, ti, tf) for ti, tf in composed_outcomes(m1, m2, rng, 200))
        # and it is no wider than the rectangles the bands and kernels allow
        rows = np.any([b.cells(N) for b in m2.bands], axis=0)
        cols = np.any([k.cells(N) for k in m1.kernels], axis=0)
        assert np.all(prod.matrix(N) <= np.outer(rows, cols))
        # the boolean matrix product (5.1) on a grid holds every composed outcome's cell
        grid = matrix_product(m2.matrix(N), m1.matrix(N))
        cell = TWO_PI / N
        for ti, tf in composed_outcomes(m1, m2, rng, 50):
            assert grid[int((tf % TWO_PI) // cell) % N, int((ti % TWO_PI) // cell) % N]


def test_book_printed_code_set_loses_outcomes_5_4():
    """The book prints 2C_j = {k : 2B_j meets 1K_k}. Built that way the product misses
    outcomes of the exact product (5.1): the printed rule is a misprint
    (docs/mechanics.md, "Where the book is wrong")."""
    rng = np.random.default_rng(12)
    missed = 0
    for _ in range(30):
        m1, m2 = random_map(rng), random_map(rng)
        printed = tuple(frozenset(k for k, kern in enumerate(m1.kernels) if band.intersects(kern))
                        for band in m2.bands)
        kernels = tuple(Arcs.of([a for k in c for a in m1.kernels[k].arcs]) for c in printed)
        book = ConfigurationMap(bands=m2.bands, kernels=kernels)
        missed += int(not all(holds(book, ti, tf) for ti, tf in composed_outcomes(m1, m2, rng, 200)))
    assert missed >= 10


def test_code_sets_compose_5_5():
    """Products of three maps from code sets only (5.5) equal the step-by-step product and
    contain the matrix product."""
    rng = np.random.default_rng(13)
    for _ in range(20):
        m1, m2, m3 = (random_map(rng) for _ in range(3))
        left = m1.then(m2).then(m3)
        right = sequence([m1, m2, m3])
        assert left == right
        # (5.5): the triple product's code set of band j is the union of the pair's code sets
        pair = m2.then(m3)
        for j, codes in enumerate(pair.code_sets):
            via = set().union(*[m1.then(m2).code_sets[k] for k in codes]) if codes else set()
            want = Arcs.of([a for k in sorted(via) for a in m1.kernels[k].arcs])
            np.testing.assert_allclose(np.array(left.kernels[j].arcs).reshape(-1, 2), np.array(want.arcs).reshape(-1, 2),
                                       atol=1e-12)


def test_jams_carry_through_products():
    stuck = ConfigurationMap(bands=(), kernels=(), jam=Arcs.circle())
    m1 = ConfigurationMap(bands=(Arcs.of([(1.0, 0.2)]),), kernels=(Arcs.of([(2.0, 0.5)]),))
    prod = m1.then(stuck)
    assert prod.jam == Arcs.of([(2.0, 0.5)])
    assert prod.bands == ()
