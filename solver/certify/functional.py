"""The dual functional of a certified COR problem, its values on the outline and sound
lower bounds of it over intervals of the outline.

The form
--------
Every column of the problems in :mod:`solver.locus` is built from 1, w, rho = |w - r| and
u = (w - r)/rho (membership (3.8)-(3.10): g_r(w) = rho alpha - s u; the sticking locus
(4.1.4): the moment (w - c) . u and the cone rows k . u). So is a dual functional of their
columns:

    phi(w) = a + b . w + (beta (w - c) - q) . (u - d0)                               (*)

with an anchor point c, a unit reference direction d0 (or zero) and scalars/vectors
a, b, beta, q. Expanding (w - c) . u = rho + (r - c) . u gives the *near form*

    phi(w) = a_o + b_o . w + beta rho + q_o . u,
    a_o = a + (beta c + q) . d0,  b_o = b - beta d0,  q_o = beta (r - c) - q.

Boundary reduction. On a ray w = r + rho u (rho > 0) u is constant, so phi is AFFINE in
rho: its minimum over the footprint lies on the outline, or at rho -> 0 when r is in the
footprint, where the point mass at r (subgradient zeta, |zeta| <= 1, in place of u) gives
the *point-mass value* a_o + b_o . r - |q_o| (:meth:`RayFunctional.point_mass_value`).
Hence pricing and the dual bound are 1-D problems over the outline
(:mod:`solver.certify.outline`, :mod:`solver.certify.pricing`).

The *far form* is (*) itself with c the contact point and d0 = (c - r)/|c - r|: for a
candidate far from the footprint (|r| >> L) u - d0 = Delta is of order L/|r|, computed
without cancellation from a = w - r, b = c - r:

    Delta = ((w - c)|b| - b ((w - c) . (a + b))/(|a| + |b|)) / (|a| |b|),

and the coefficients stay of order 1 on the conditioned rows of the problems, where the
near form's beta rho and q_o . u are both of order |r| and cancel.

Lower bounds (:meth:`RayFunctional.lower_bounds`), on an interval [t0, t1] of length l of
a piece with the derivative bounds V, A, R1, R2, U1, U2 of :class:`Pieces`:

* near form: |phi'| <= K = |b_o| V + |beta| R1 + |q_o| U1, |phi''| <= M = |b_o| A +
  |beta| R2 + |q_o| U2; zeroth order min(a_o + b_o . w at the ends) - |b_o| sagitta +
  min(beta rho at the ends) - |q_o|;
* far form (when d0 is not zero): with |Delta'| = |u'| <= U1, |Delta''| <= U2,
  |w - c| <= W and |Delta| <= Dm on the interval,
  |phi'| <= |b| V + |beta| V Dm + (|beta| W + |q|) U1,
  |phi''| <= |b| A + |beta| A Dm + 2 |beta| V U1 + (|beta| W + |q|) U2,
  phi >= min(a + b . w at the ends) - |b| sagitta - (|beta| W + |q|) Dm;
* from K: Piyavskii's (f0 + f1 - K l)/2; from M: the chord minus (M/2) tau (l - tau) at its
  minimiser.

The largest of these, less a rounding allowance of ``ROUNDING_ALLOWANCE`` times the
magnitudes involved (those of the near form for its zeroth-order bound, of the far form for
its own and, when there is one, for the bounds built on the values f0, f1), is the bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Protocol

import numpy as np

from solver.certify.outline import Pieces

ROUNDING_ALLOWANCE = 32.0 * np.finfo(float).eps
"""Relative rounding allowance subtracted from every lower bound. The outline is evaluated
in coordinates centred on r (edge coordinates, or the circle turned to r), where w - r,
rho and u carry relative rounding errors only."""

DELTA_BOUND = 2.0
"""|u - d0| <= 2 for unit vectors: the cap of the far form's Dm."""


class DualFunctional(Protocol):
    """What pricing and the branch and bound need of a dual functional."""

    def evaluate(self, pieces: Pieces, piece: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(phi (k,), ext (k, 4)) at outline points; ``ext`` columns w_x, w_y, rho, |u - d0|."""
        ...

    def values(self, pieces: Pieces, piece: np.ndarray, t: np.ndarray) -> np.ndarray:
        """phi (k,) alone (the same numbers as :meth:`evaluate`'s first)."""
        ...

    def lower_bounds(
        self, pieces: Pieces, piece: np.ndarray, t0: np.ndarray, t1: np.ndarray,
        f0: np.ndarray, f1: np.ndarray, e0: np.ndarray, e1: np.ndarray,
    ) -> np.ndarray:
        """Sound lower bounds of phi on the intervals [t0, t1] (values and ext at the ends)."""
        ...

    def point_mass_value(self) -> float:
        """min of phi over the point-mass set at r (w -> r, u -> any unit vector)."""
        ...


def far_delta(w: np.ndarray, u: np.ndarray, rho: np.ndarray, r: np.ndarray, anchor: np.ndarray) -> np.ndarray:
    """u - d0 for points w (u = (w - r)/rho, d0 = (anchor - r)/|anchor - r|) without
    cancellation (module docstring)."""
    wc = w - anchor
    bvec = anchor - r
    bn = float(np.hypot(bvec[0], bvec[1]))
    a_plus_b = (w - r) + bvec
    proj = np.einsum("ij,ij->i", wc, a_plus_b) / (rho + bn)
    return (wc * bn - proj[:, None] * bvec[None, :]) / (rho * bn)[:, None]


@dataclass(frozen=True)
class RayFunctional:
    """phi(w) = a + b . w + (beta (w - anchor) - q) . (u - d0) at the candidate r (module
    docstring). ``far``: evaluate u - d0 without cancellation (d0 must then be the unit
    direction from r to ``anchor``); else u - d0 directly, and phi in its near form."""

    r: np.ndarray
    a: float
    b: np.ndarray
    beta: float
    q: np.ndarray
    anchor: np.ndarray
    d0: np.ndarray
    far: bool = False

    @property
    def has_far_form(self) -> bool:
        return bool(self.d0[0] != 0.0 or self.d0[1] != 0.0)

    @cached_property
    def _near(self) -> tuple[float, np.ndarray, np.ndarray]:
        a_o = self.a + float((self.beta * self.anchor + self.q) @ self.d0)
        b_o = self.b - self.beta * self.d0
        q_o = self.beta * (self.r - self.anchor) - self.q
        return a_o, b_o, q_o

    def near_coefficients(self) -> tuple[float, np.ndarray, np.ndarray]:
        """(a_o, b_o, q_o) of the near form a_o + b_o . w + beta rho + q_o . u."""
        return self._near

    def _delta(self, w: np.ndarray, u: np.ndarray, rho: np.ndarray) -> np.ndarray:
        if self.far:
            return far_delta(w, u, rho, self.r, self.anchor)
        return u - self.d0

    def _phi(self, w: np.ndarray, rho: np.ndarray, u: np.ndarray, dl: np.ndarray | None) -> np.ndarray:
        if self.far:
            coef = self.beta * (w - self.anchor) - self.q
            return np.asarray(self.a + w @ self.b + np.einsum("ij,ij->i", coef, self._delta(w, u, rho) if dl is None else dl))
        a_o, b_o, q_o = self.near_coefficients()
        return np.asarray(a_o + w @ b_o + self.beta * rho + u @ q_o)

    def evaluate(self, pieces: Pieces, piece: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        w, rho, u = pieces.geom(piece, t)
        dl = self._delta(w, u, rho)
        return self._phi(w, rho, u, dl), np.column_stack([w, rho, np.hypot(dl[:, 0], dl[:, 1])])

    def values(self, pieces: Pieces, piece: np.ndarray, t: np.ndarray) -> np.ndarray:
        w, rho, u = pieces.geom(piece, t)
        return self._phi(w, rho, u, None)

    def point_mass_value(self) -> float:
        a_o, b_o, q_o = self.near_coefficients()
        return float(a_o + b_o @ self.r - math.hypot(q_o[0], q_o[1]))

    def lower_bounds(
        self, pieces: Pieces, piece: np.ndarray, t0: np.ndarray, t1: np.ndarray,
        f0: np.ndarray, f1: np.ndarray, e0: np.ndarray, e1: np.ndarray,
    ) -> np.ndarray:
        w0, w1 = e0[:, :2], e1[:, :2]
        rho0, rho1 = e0[:, 2], e1[:, 2]
        ell = t1 - t0
        v, acc, r1, r2, u1, u2 = pieces.derivative_bounds(piece, t0, t1, rho0, rho1)
        sag = pieces.sagitta(piece, ell)
        beta = self.beta
        eps = ROUNDING_ALLOWANCE
        r_norm = float(np.hypot(self.r[0], self.r[1]))
        w_max = 1.0 + r_norm
        # near form
        a_o, b_o, q_o = self.near_coefficients()
        bon = float(np.hypot(b_o[0], b_o[1]))
        qon = float(np.hypot(q_o[0], q_o[1]))
        rho_max = np.maximum(rho0, rho1)
        allow = eps * (abs(a_o) + bon * w_max + abs(beta) * (rho_max + w_max + r_norm) + qon)
        lb0 = np.minimum(a_o + w0 @ b_o, a_o + w1 @ b_o) - bon * sag + np.minimum(beta * rho0, beta * rho1) - qon
        lbs = [lb0 - allow]
        gradients = [(bon * v + abs(beta) * r1 + qon * u1, bon * acc + abs(beta) * r2 + qon * u2)]
        if self.has_far_form:
            bn = float(np.hypot(self.b[0], self.b[1]))
            qn = float(np.hypot(self.q[0], self.q[1]))
            half = 0.5 * ell * v
            wc0 = np.hypot(w0[:, 0] - self.anchor[0], w0[:, 1] - self.anchor[1])
            wc1 = np.hypot(w1[:, 0] - self.anchor[0], w1[:, 1] - self.anchor[1])
            wc = np.maximum(wc0, wc1) + half
            with np.errstate(invalid="ignore", over="ignore"):
                dm = np.minimum(DELTA_BOUND, np.maximum(e0[:, 3], e1[:, 3]) + u1 * half)
                cn = abs(beta) * wc + qn
                k_n = bn * v + abs(beta) * v * dm + cn * u1
                m_n = bn * acc + abs(beta) * acc * dm + 2.0 * abs(beta) * v * u1 + cn * u2
            qd = abs(float(self.q @ self.d0))
            allow_n = eps * (abs(self.a) + qd + bn * w_max + 2.0 * abs(beta) * wc + 2.0 * qn)
            lb0_n = np.minimum(self.a + w0 @ self.b, self.a + w1 @ self.b) - bn * sag - cn * dm
            lbs.append(lb0_n - allow_n)
            allow = allow_n  # the values f0, f1 carry the far form's rounding
            gradients.append((k_n, m_n))
        for k, m in gradients:
            with np.errstate(invalid="ignore", over="ignore"):
                lb_lip = 0.5 * (f0 + f1 - k * ell)
            with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
                tau = np.where(m > 0.0, 0.5 * ell - (f1 - f0) / (m * ell), np.where(f1 < f0, ell, 0.0))
            tau = np.clip(np.nan_to_num(tau, nan=0.0), 0.0, ell)
            with np.errstate(invalid="ignore", over="ignore"):
                chord = f0 + (f1 - f0) * np.where(ell > 0.0, tau / np.where(ell > 0.0, ell, 1.0), 0.0)
                lb_2 = np.where(np.isfinite(m), chord - 0.5 * m * tau * (ell - tau), -np.inf)
                slack = allow + eps * (np.nan_to_num(k * ell, nan=np.inf, posinf=np.inf) + np.abs(f0) + np.abs(f1))
            lbs.append(np.nan_to_num(lb_lip, nan=-np.inf) - slack)
            lbs.append(np.nan_to_num(lb_2, nan=-np.inf) - slack)
        return np.asarray(np.maximum.reduce(lbs))
