"""Configuration maps and their products (book 5.2, 5.2.1).

A configuration map M(theta_i, theta_f) says which final orientations theta_f are possible
from each initial orientation theta_i. The maps of fences are unions of rectangles
K_j x B_j (5.3): bands B_j of final orientations and their kernels K_j (5.2), kept here
symbolically as :class:`~models.feeder.arcs.Arcs`; :meth:`ConfigurationMap.matrix` gives
the boolean matrix on a grid, on which a product is the boolean matrix product (5.1).

The symbolic product (5.4): operation M1 followed by M2 is

    M2 M1 = U_j  2B_j x ( U_{k in 2C_j} 1K_k ),   2C_j = { k : 1B_k meets 2K_j }.

The book prints the code set as { k : 2B_j meets 1K_k }, which pairs a final band of the
second operation with an initial kernel of the first; the orientations handed from M1 to
M2 are M1's final bands, and they must meet M2's kernels (docs/mechanics.md, "Where
the book is wrong"; tests/models/feeder/test_maps.py proves the printed rule misses
outcomes of the matrix product (5.1)). Further products use the code sets only (5.5).

Orientations a map cannot follow are kept as sets of initial orientations carried through
products: ``jam`` (a part that jams on a fence and never leaves it, 6.4) and ``unaligned``
(a fence that may be too short for an edge to come flush, 1.8.6: any final orientation is
possible, so the matrix holds the whole column).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from models.feeder.arcs import Arcs


@dataclass(frozen=True)
class ConfigurationMap:
    """U_j kernels[j] x bands[j] (5.3), the initial orientations that may jam, and those
    the map does not bound (``unaligned``: every final orientation may follow).

    ``code_sets``, when the map is a product, holds for each band j the indices of the
    first operation's kernels whose union is kernel j (5.4)."""

    bands: tuple[Arcs, ...]
    kernels: tuple[Arcs, ...]
    jam: Arcs = Arcs.empty()
    unaligned: Arcs = Arcs.empty()
    code_sets: tuple[frozenset[int], ...] | None = None

    def __post_init__(self) -> None:
        if len(self.bands) != len(self.kernels):
            raise ValueError("a configuration map needs one kernel per band")

    def matrix(self, n: int) -> np.ndarray:
        """M[f, i] on ``n`` orientation cells (rows: final, columns: initial): True where a
        cell pair meets some K_j x B_j (a cell touching a band or kernel counts)."""
        m = np.zeros((n, n), dtype=bool)
        for band, kernel in zip(self.bands, self.kernels):
            m |= np.outer(band.cells(n), kernel.cells(n))
        m[:, self.unaligned.cells(n)] = True
        return m

    def jam_cells(self, n: int) -> np.ndarray:
        return self.jam.cells(n)

    def then(self, second: ConfigurationMap) -> ConfigurationMap:
        """This operation followed by ``second``: the product second x self (5.4)."""
        codes = tuple(
            frozenset(k for k, band in enumerate(self.bands) if band.intersects(kernel))
            for kernel in second.kernels
        )
        kernels = tuple(Arcs.union_of(self.kernels[k] for k in sorted(c)) for c in codes)
        jam = self.jam.union(Arcs.union_of(self.kernels[k] for k, band in enumerate(self.bands)
                                    if band.intersects(second.jam)))
        # an unaligned part may leave the first fence in any orientation: it may then meet
        # anything the second does
        unaligned = self.unaligned.union(Arcs.union_of(self.kernels[k] for k, band in enumerate(self.bands)
                                                if band.intersects(second.unaligned)))
        if not second.jam.is_empty:
            jam = jam.union(self.unaligned)
        return ConfigurationMap(bands=second.bands, kernels=kernels, jam=jam, unaligned=unaligned, code_sets=codes)

    def allows(self, theta_initial: float, theta_final: float, slack: float = 0.0) -> bool:
        """True when the map holds (theta_initial, theta_final): a band within ``slack``
        of theta_final whose kernel holds theta_initial, or an initial orientation the map
        does not bound (``unaligned``)."""
        return self.unaligned.contains(theta_initial) or any(
            k.contains(theta_initial) and b.contains(theta_final, slack) for b, k in zip(self.bands, self.kernels))

    def final_bands(self) -> tuple[Arcs, ...]:
        """The bands reached from some initial orientation (non-empty kernel)."""
        return tuple(b for b, k in zip(self.bands, self.kernels) if not k.is_empty)


def sequence(maps: list[ConfigurationMap]) -> ConfigurationMap:
    """The map of the operations in order (first applied first): (5.4), (5.5)."""
    if not maps:
        raise ValueError("a sequence needs at least one map")
    out = maps[0]
    for m in maps[1:]:
        out = out.then(m)
    return out


def matrix_product(second: np.ndarray, first: np.ndarray) -> np.ndarray:
    """(5.1): (M2 M1)(theta_i, theta_f) = OR over alpha of M2(alpha, theta_f) AND
    M1(theta_i, alpha), as boolean matrices M[f, i]."""
    return (second.astype(np.int64) @ first.astype(np.int64)) > 0
