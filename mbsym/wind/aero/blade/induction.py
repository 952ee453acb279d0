"""Quasi-steady induction of blade elements as SX expressions: Ning's residual, fixed-count Newton.

The equations are AeroDyn 15's ``inductionFactors0`` (``BEM_Mod = 1``), the same as
:mod:`mbsym.wind.aero._induction` (numpy) solves by bracketing:

* ``cx = cl cos φ (+ cd sin φ if AIDrag)``, ``cy = cl sin φ (- cd cos φ if TIDrag)``;
* Prandtl ``F = Ftip Fhub``, ``F* = (2/π) acos(exp(-f*/|sin φ|))`` with AeroDyn's constants
  ``f_tip = B (z_tip - z)/(2 z)``, ``f_hub = B (z - z_hub)/(2 z_hub)``; ``F >= 1e-4``;
* ``k = σ cx / (4 F sin²φ)`` with ``σ = B c / (2 π r)``; momentum region (``φ > 0`` and
  ``Vx >= 0``, or both negative): ``a = k / (1 + k)`` up to ``k = 2/3`` (``a = 0.4``), Buhl's
  empirical line beyond; propeller brake: ``a = k / (k - 1)``; valid only for ``k >= -1``
  (momentum) or ``k > 1`` (brake), else ``a = a' = 0`` (AeroDyn's "invalid solution");
* ``kp = σ cy / (4 F sin φ cos φ)`` (sign flipped if ``Vx < 0``), ``a' = kp / (1 - kp)``
  (TanInd), else 0;
* residual ``R(φ) = sin φ / (1 - a) - cos φ (Vx / Vy)(1 - kp)`` (momentum) or
  ``sin φ (1 - k) - cos φ (Vx / Vy)(1 - kp)`` (brake).

**Solve in the graph.** ``n_newton`` Newton steps ``φ ← φ - R/R'`` with the exact derivative
``R'`` (forward AD of the residual, which is C¹ in φ with the spline polars), each iterate
clamped into AeroDyn's first bracket ``[ε, π/2 - ε]`` (ε = 1e-6), starting from a guess
(the inflow angle of the dynamic-wake states, or of ``a = 1/3`` without them). The cost is
fixed and the result is an ordinary differentiable expression; its error against a converged
solution is measured in the tests and docs/blade_aero.md. Elements whose root lies outside
``(0, π/2)`` (reverse flow, the propeller-brake and windmill-reversal brackets of AeroDyn's
solver) are not solved there: see docs/blade_aero.md, "Limits".
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

__all__ = ["ElementData", "induction", "solve_phi", "PHI_EPS", "F_MIN", "A_LIMITS", "AP_LIMITS"]

PHI_EPS = 1e-6  # distance of the Newton clamp from 0 and π/2 [rad] (AeroDyn's bracket)
F_MIN = 1e-4  # lower bound of the Prandtl factor (AeroDyn)
A_LIMITS = (-1.0, 1.5)  # AeroDyn's BEMT_MinInduction / BEMT_MaxInduction, axial
AP_LIMITS = (-1.0, 1.0)  # ... tangential


@dataclass(frozen=True)
class ElementData:
    """The inputs of the free (not tip/hub-fixed) elements, as SX columns or numpy arrays.

    ``vx``, ``vy`` [m/s], ``sigma`` (local solidity), ``tip_const``, ``hub_const`` (Prandtl
    constants, numpy), ``nodes`` (blade node of each element, for the airfoil), and the
    options ``tip_loss``, ``hub_loss``, ``tangential_induction``, ``axial_drag``,
    ``tangential_drag``.
    """

    vx: Any
    vy: Any
    sigma: Any
    tip_const: np.ndarray
    hub_const: np.ndarray
    nodes: np.ndarray
    tip_loss: bool
    hub_loss: bool
    tangential_induction: bool
    axial_drag: bool
    tangential_drag: bool


#: A loss constant ``f*`` at or above which ``(2/π) acos(exp(-f*/|sin φ|))`` is 1 in double precision for
#: every φ (``|sin φ| <= 1``, ``exp(-40) = 4e-18`` below half an ulp of 1): that factor is left out of the graph.
LOSS_CONST_ONE = 40.0


def _loss_factor(const: np.ndarray, s: Any, clamp: bool) -> Any:
    """``(2/π) acos(exp(-const / s))`` per element, exactly 1 (no instructions) where ``const >=``
    :data:`LOSS_CONST_ONE` (hub loss beyond ~40 hub radii of span, tip loss near the root)."""
    const = np.asarray(const, dtype=float).reshape(-1)
    active = np.flatnonzero(const < LOSS_CONST_ONE).tolist()
    out = ca.SX.ones(const.size, 1)
    if active:
        e = ca.exp(-ca.DM(const[active]) / s[active])
        out[active] = (2.0 / math.pi) * ca.acos(ca.fmin(1.0, e) if clamp else e)
    return out


def prandtl(sin_phi: Any, e: ElementData) -> Any:
    """AeroDyn's tip and hub loss factor ``F`` (floored at :data:`F_MIN`)."""
    s = ca.fmax(ca.fabs(sin_phi), 1e-12)
    f = 1.0
    if e.tip_loss:
        f = f * _loss_factor(e.tip_const, s, True)
    if e.hub_loss:
        f = f * _loss_factor(e.hub_const, s, True)
    return ca.fmax(f, F_MIN)


def induction(phi: Any, cl: Any, cd: Any, e: ElementData) -> dict[str, Any]:
    """Induction factors and Ning's residual at ``phi`` (see the module docstring).

    ``cd`` is used only with AIDrag/TIDrag (pass None otherwise).
    """
    sin_phi, cos_phi = ca.sin(phi), ca.cos(phi)
    cx = cl * cos_phi + cd * sin_phi if e.axial_drag else cl * cos_phi
    cy = cl * sin_phi - cd * cos_phi if e.tangential_drag else cl * sin_phi
    f = prandtl(sin_phi, e)
    k = e.sigma * cx / (4.0 * f * sin_phi**2)
    momentum = ca.logic_or(ca.logic_and(phi > 0, e.vx >= 0), ca.logic_and(phi < 0, e.vx < 0))
    two_fk = 2.0 * f * k
    g1, g2 = two_fk - (10.0 / 9.0 - f), two_fk - (4.0 / 3.0 - f) * f
    g3 = two_fk - (25.0 / 9.0 - 2.0 * f)
    g3 = ca.if_else(ca.fabs(g3) < 1e-6, 1e-6, g3)  # AeroDyn's singular branch, O(1e-6) apart
    buhl = (g1 - ca.sqrt(ca.fabs(g2))) / g3
    a_momentum = ca.if_else(k <= 2.0 / 3.0, k / (1.0 + k), buhl)
    a = ca.if_else(momentum, a_momentum, k / (k - 1.0))
    valid = ca.if_else(momentum, k >= -1.0, k > 1.0)
    if e.tangential_induction:
        kp = e.sigma * cy / (4.0 * f * sin_phi * cos_phi)
        kp = ca.if_else(e.vx < 0, -kp, kp)
        ap = kp / (1.0 - kp)
    else:
        kp = ap = 0.0 * phi
    tangential = cos_phi * (e.vx / e.vy) * (1.0 - kp)
    residual = ca.if_else(momentum, sin_phi / (1.0 - a), sin_phi * (1.0 - k)) - tangential
    return {"a": a, "ap": ap, "k": k, "kp": kp, "F": f, "valid": valid, "residual": residual}


def _momentum_residual(phi: Any, cl: Any, cd: Any, e: ElementData) -> Any:
    """Ning's residual in the momentum region (``0 < φ < π/2``, ``Vx >= 0``), lean for Newton.

    Equal to :func:`induction`'s there (the clamp keeps the iterates inside), without the
    propeller-brake branch and with ``exp(-f/sin φ) <= 1`` known: about half the instructions.
    """
    sin_phi, cos_phi = ca.sin(phi), ca.cos(phi)
    cx = cl * cos_phi + cd * sin_phi if e.axial_drag else cl * cos_phi
    f = 1.0
    if e.tip_loss:
        f = f * _loss_factor(e.tip_const, sin_phi, False)
    if e.hub_loss:
        f = f * _loss_factor(e.hub_const, sin_phi, False)
    f = ca.fmax(f, F_MIN)
    k = e.sigma * cx / (4.0 * f * sin_phi**2)
    two_fk = 2.0 * f * k
    g1, g2 = two_fk - (10.0 / 9.0 - f), two_fk - (4.0 / 3.0 - f) * f
    g3 = two_fk - (25.0 / 9.0 - 2.0 * f)
    inv_buhl = g3 / (g3 - g1 + ca.sqrt(ca.fabs(g2)))  # 1 / (1 - a) on Buhl's line
    inv_one_minus_a = ca.if_else(k <= 2.0 / 3.0, 1.0 + k, inv_buhl)
    if e.tangential_induction:
        cy_over_sin = cl - cd * cos_phi / sin_phi if e.tangential_drag else cl
        kp = e.sigma * cy_over_sin / (4.0 * f * cos_phi)
        tangential = cos_phi * (e.vx / e.vy) * (1.0 - kp)
    else:
        tangential = cos_phi * (e.vx / e.vy)
    return sin_phi * inv_one_minus_a - tangential


def solve_phi(guess: Any, e: ElementData, polars: Any, theta: Any, *, n_newton: int) -> Any:
    """``n_newton`` clamped Newton steps on Ning's residual from ``guess`` (SX column) [rad].

    The slope ``dR/dφ = ∂R/∂φ + ∂R/∂cl dcl/dα (+ ∂R/∂cd dcd/dα)`` is built from the residual
    written in placeholder symbols for the coefficients and the cubics' own derivatives, so
    the graph never differentiates through the polar gather (whose forward derivative is
    expensive in CasADi's generated code).
    """
    lo, hi = PHI_EPS, math.pi / 2.0 - PHI_EPS
    n = guess.shape[0]
    phi_sym, cl_sym, cd_sym = (ca.SX.sym(name, n) for name in ("phi", "cl", "cd"))
    need_cd = e.axial_drag or e.tangential_drag
    residual = _momentum_residual(phi_sym, cl_sym, cd_sym if need_cd else None, e)
    ones = ca.DM.ones(n)
    dr_dphi, dr_dcl = ca.jtimes(residual, phi_sym, ones), ca.jtimes(residual, cl_sym, ones)
    dr_dcd = ca.jtimes(residual, cd_sym, ones) if need_cd else 0.0
    phi = ca.fmin(ca.fmax(guess, lo), hi)
    for _ in range(n_newton):
        # α = φ - θ stays in (-π, π) for φ in (0, π/2) and |θ| < π/2
        coef = polars(phi - theta, e.nodes, lift_only=not need_cd, wrap=False, slope=True)
        cd, dcd = (coef["cd"], coef["dcd"]) if need_cd else (0.0 * phi, 0.0 * phi)
        r, a1, a2, a3 = ca.substitute([residual, dr_dphi, dr_dcl, ca.SX(dr_dcd) * ones],
                                      [phi_sym, cl_sym, cd_sym], [phi, coef["cl"], cd])
        slope = a1 + a2 * coef["dcl"] + a3 * dcd
        phi = ca.fmin(ca.fmax(phi - r / slope, lo), hi)
    return phi
