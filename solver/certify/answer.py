"""What a certified query answers about one candidate point, in the world frame: the fields
every problem of :mod:`solver.locus` reports (membership, 3.2-3.3; the sticking locus,
4.1.4), and their conversion from a :class:`solver.certify.colgen.Decision`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from solver.certify.colgen import Decision
from solver.certify.outline import Outline


@dataclass(frozen=True)
class CertifiedPoint:
    """The decision on one candidate, in the world frame.

    * ``status``: "inside" | "outside" | "undecided"; ``complete`` unless undecided.
    * ``cor``: the point decided (moved onto the footprint's outline when within
      ``ON_BOUNDARY_REL`` L of it).
    * ``certificate_kind``: "witness" (inside), "dual" (outside, sound), or "none" (the
      problems may add their own kinds).
    * ``witness_points`` (k, 2), ``witness_weights`` (k,), ``point_mass_at_cor`` P0 and
      ``point_mass_subgradient`` z (|z| <= P0): the witness support (inside), or the last
      restricted master's support (others).
    * ``witness_residual``: the support's residual in the problem's rows (dimensionless);
      for an "outside" result the master's optimum.
    * ``witness_forward_cor_error``: |COR of the witness by a forward solve - cor| / L, or
      None when not re-verified.
    * ``dual``: the separating functional on the problem's reported columns,
      ``dual_lower_bound`` its lower bound over the footprint and point-mass set,
      ``dual_margin`` = lower bound - y . b (> 0 proves ``cor`` outside with
      ``lower_bound_method`` "branch_and_bound"; "grid" is no certificate).
    * ``iterations``, ``n_columns``, ``bnb_intervals``: the work done; ``in_footprint``:
      a point mass at ``cor`` was allowed; ``length_scale`` L.
    """

    status: str
    cor: np.ndarray
    certificate_kind: str
    witness_points: np.ndarray
    witness_weights: np.ndarray
    point_mass_at_cor: float
    point_mass_subgradient: np.ndarray
    witness_residual: float
    witness_forward_cor_error: float | None
    dual: np.ndarray | None
    dual_lower_bound: float | None
    dual_margin: float | None
    lower_bound_method: str | None
    iterations: int
    n_columns: int
    bnb_intervals: int
    in_footprint: bool
    length_scale: float
    message: str
    solve_time_s: float

    @property
    def complete(self) -> bool:
        return self.status != "undecided"


def answer_fields(
    dec: Decision, outline: Outline, r_local: np.ndarray, in_footprint: bool, dual: np.ndarray | None,
    forward_error: float | None, solve_time_s: float,
) -> dict[str, Any]:
    """The :class:`CertifiedPoint` fields of ``dec`` (local frame of ``outline``) in the
    world frame; ``dual`` already converted to the problem's reported columns."""
    return dict(
        status=dec.status,
        cor=outline.to_world(r_local),
        certificate_kind=dec.certificate_kind,
        witness_points=outline.to_world(dec.points),
        witness_weights=dec.weights,
        point_mass_at_cor=float(dec.point_mass[0]) if in_footprint else 0.0,
        point_mass_subgradient=outline.vector_to_world(dec.point_mass[1:3]) if in_footprint else np.zeros(2),
        witness_residual=dec.residual,
        witness_forward_cor_error=forward_error,
        dual=dual,
        dual_lower_bound=dec.lower_bound,
        dual_margin=dec.margin,
        lower_bound_method=dec.lower_bound_method,
        iterations=dec.iterations,
        n_columns=dec.n_columns,
        bnb_intervals=dec.bnb_intervals,
        in_footprint=in_footprint,
        length_scale=outline.length,
        message=dec.message,
        solve_time_s=solve_time_s,
    )
