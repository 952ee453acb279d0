"""Rotor-averaged dynamic inflow: AeroDyn's DBEMT (Øye's two-stage filter) on performance surfaces.

OpenFAST v4 and later run AeroDyn's dynamic BEMT whenever ``Wake_Mod = 1`` and
``DBEMT_Mod`` is 1, 2 or 3 (before v4: ``WakeMod = 2``): the induced velocity of every blade
element lags its quasi-steady value, so a pitch or wind change moves the loads at once
(frozen induction) and the induction then relaxes. A quasi-steady rotor (surfaces alone)
misses that overshoot; in the 10 → 14 m/s step of the shared OpenFAST runs the aerodynamic
torque differs from the quasi-steady map at OpenFAST's own TSR and pitch by −85 % to +11 %
while the pitch moves at its rate limit.

The rotor-averaged model here keeps one induced velocity ``v`` [m/s] (positive against the
wind) for the whole disk:

* **Quasi-steady induction** ``v_qs = ā(λ, β) U`` with ``λ = Ω R / U``, ``U`` the relative wind
  along the shaft and ``ā`` the axial induction an actuator disk needs for the rotor's thrust
  coefficient ``ct(λ, β)``: ``ct = 4 ā (1 − ā)`` up to ``ct = 0.96`` (``ā = 0.4``), Buhl's
  high-thrust line beyond (``ct = 8/9 + (4 − 40/9) ā + (50/9 − 4) ā²``).
* **Blade-element characteristic.** Along the steady solutions the disk sees
  ``U_d = U (1 − ā)``; the loads written in ``U_d`` and ``λ_d = Ω R / U_d``,
  ``ct_d = ct / (1 − ā)²``, ``cq_d = cq / (1 − ā)²`` over ``(λ_d, β)``, are what the blade
  elements produce for a given disk inflow. Out of equilibrium the loads are
  ``T = ½ ρ π R² U_d² ct_d(λ_d, β)``, ``Q = ½ ρ π R³ U_d² cq_d(λ_d, β)`` with ``U_d = U − v``:
  at ``v = v_qs`` they are the steady loads (to the resampling accuracy, see the tests).
* **Øye's filter** (AeroDyn's DBEMT): ``v_int + τ₁ v̇_int = v_qs + k τ₁ v̇_qs`` and
  ``v + τ₂ v̇ = v_int`` with ``k = 0.6``, written with the state ``w = v_int − k v_qs``
  (``τ₁ ẇ = (1 − k) v_qs − w``, no derivative of the input); ``τ₁ = 1.1 / (1 − 1.3 min(ā, 0.5))
  R / U`` (``DBEMT_Mod = 2``, ``ā = v / U``) or the deck's ``tau1_const`` (``DBEMT_Mod = 1, 3``);
  ``τ₂ = (0.39 − 0.26 (r/R)²) τ₁`` per annulus in AeroDyn, here its disk-area average
  ``0.26 τ₁``.

What it leaves out: the radial distribution of the lag (one ``τ₂`` for the disk), the
change of the induction's radial shape out of equilibrium, and the per-annulus ``a``; the
loads' ``cp_scale``/``ct_scale`` do not change ``v_qs``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ParameterError
from ..aero.interpolant import SurfaceSpline
from ..aero.rotor import RotorAero
from ..deck.performance import PerformanceTable

__all__ = ["DynamicInflow", "momentum_induction", "dbemt_settings", "OYE_K", "TAU2_RATIO"]

#: Øye's k in ``v_int + τ₁ v̇_int = v_qs + k τ₁ v̇_qs`` (AeroDyn's DBEMT).
OYE_K = 0.6
#: ``τ₂ / τ₁``: the disk-area average of AeroDyn's ``0.39 − 0.26 (r/R)²``.
TAU2_RATIO = 0.39 - 0.26 * 0.5
_BUHL_CT = 0.96


def momentum_induction(ct: Any) -> np.ndarray:
    """Axial induction of an actuator disk with thrust coefficient ``ct`` (momentum, then Buhl's line).

    Examples
    --------
    >>> round(float(momentum_induction(8 / 9)), 6)        # Betz: a = 1/3
    0.333333
    >>> round(float(momentum_induction(0.96)), 6), round(float(momentum_induction(2.0)), 6)   # Buhl: a = 1 at ct = 2
    (0.4, 1.0)
    """
    ct = np.asarray(ct, dtype=float)
    momentum = 0.5 * (1.0 - np.sqrt(np.clip(1.0 - ct, 0.0, None)))
    a2, a1 = 50.0 / 9.0 - 4.0, 4.0 - 40.0 / 9.0
    buhl = (-a1 + np.sqrt(np.clip(a1 * a1 - 4.0 * a2 * (8.0 / 9.0 - ct), 0.0, None))) / (2.0 * a2)
    return np.where(ct <= _BUHL_CT, momentum, buhl)


def dbemt_settings(aerodyn) -> tuple[int, float] | None:
    """``(DBEMT_Mod, tau1_const)`` if an AeroDyn 15 input runs dynamic BEMT, else None.

    OpenFAST v4+ files (``Wake_Mod`` with ``SkewMomCorr``): ``Wake_Mod = 1`` and
    ``DBEMT_Mod`` in 1..3. Older files: ``WakeMod = 2``.
    """
    extra = dict(getattr(aerodyn, "extra", {}) or {})
    try:
        mode = int(float(extra.get("DBEMT_Mod", 0)))
        tau1 = float(extra.get("tau1_const", 0.0))
    except ValueError:
        return None
    v4 = "SkewMomCorr" in extra
    on = (aerodyn.wake_model == 1 and v4) or aerodyn.wake_model == 2
    if not on or mode not in (1, 2, 3):
        return None
    return mode, tau1


@dataclass(frozen=True, eq=False)
class DynamicInflow:
    """Rotor-averaged dynamic inflow for a :class:`RotorAero` (see the module docstring).

    Parameters
    ----------
    rotor : RotorAero
        Its ``ct``/``cq`` table defines the quasi-steady induction and the blade-element
        characteristic.
    mode : int, optional
        AeroDyn's ``DBEMT_Mod``: 2 (default, ``τ₁`` from the induction and the wind), 1 or 3
        (constant ``tau1_const``).
    tau1_const : float, optional
        ``τ₁`` [s] for modes 1 and 3.
    lambda_step : float, optional
        Spacing of the ``λ_d`` grid of the characteristic [-].
    """

    rotor: RotorAero
    mode: int = 2
    tau1_const: float = 0.0
    lambda_step: float = 0.2
    induction: SurfaceSpline = field(init=False, repr=False)
    characteristic: SurfaceSpline = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.rotor, RotorAero):
            raise TypeError(f"rotor must be a RotorAero; got {type(self.rotor).__name__}.")
        if self.mode not in (1, 2, 3):
            raise ParameterError(f"DynamicInflow.mode (DBEMT_Mod) must be 1, 2 or 3; got {self.mode!r}.")
        if self.mode != 2 and not (math.isfinite(self.tau1_const) and self.tau1_const > 0):
            raise ParameterError(f"DBEMT_Mod {self.mode} needs tau1_const > 0 [s]; got {self.tau1_const!r}.")
        table = self.rotor.table
        a = momentum_induction(table.ct)
        # the induction in the cp slot of a table: one spline lookup gives ā
        induction = PerformanceTable(tsr=table.tsr, pitch=table.pitch, cp=a, ct=table.ct, cq=table.cq,
                                     source="momentum induction of the rotor's ct")
        object.__setattr__(self, "induction", SurfaceSpline.from_table(induction, names=("cp",),
                                                                        degree=self.rotor.degree))
        object.__setattr__(self, "characteristic", SurfaceSpline.from_table(
            self._characteristic_table(), names=("ct", "cq"), degree=self.rotor.degree))

    def _characteristic_table(self) -> PerformanceTable:
        """``ct_d``, ``cq_d`` over ``(λ_d, β)``, resampled from a fine λ sweep of the rotor's splines."""
        table = self.rotor.table
        lam = np.arange(table.tsr[0], table.tsr[-1] + 1e-9, 0.01)
        grid = np.arange(table.tsr[0], 1.5 * table.tsr[-1] + 1e-9, self.lambda_step)
        L, B = np.meshgrid(lam, table.pitch, indexing="ij")
        qs = self.rotor.spline.evaluate(L, B)
        a = momentum_induction(qs["ct"])
        lam_d = L / (1.0 - np.minimum(a, 0.99))
        ct_d, cq_d = (qs[n] / (1.0 - np.minimum(a, 0.99)) ** 2 for n in ("ct", "cq"))
        out_ct, out_cq = np.empty((grid.size, table.pitch.size)), np.empty((grid.size, table.pitch.size))
        for j in range(table.pitch.size):
            x = lam_d[:, j]
            keep = x > np.maximum.accumulate(np.concatenate([[-np.inf], x[:-1]]))    # the increasing branch
            out_ct[:, j] = _interp(grid, x[keep], ct_d[keep, j])
            out_cq[:, j] = _interp(grid, x[keep], cq_d[keep, j])
        return PerformanceTable(tsr=grid, pitch=table.pitch, cp=grid[:, None] * out_cq, ct=out_ct, cq=out_cq,
                                source="blade-element characteristic (disk inflow)")

    # ------------------------------------------------------------------ expressions
    def steady_state(self, u_rel: Any, omega: Any, pitch: Any) -> Any:
        """``(w, v)`` at equilibrium [m/s] (numbers or CasADi expressions)."""
        v = self.quasi_steady(u_rel, omega, pitch)
        return (1.0 - OYE_K) * v, v

    def quasi_steady(self, u_rel: Any, omega: Any, pitch: Any) -> Any:
        """``v_qs = ā(λ, β) U`` [m/s] with the floored relative wind."""
        u = self.rotor._speed(u_rel)
        return self.induction(omega * self.rotor.radius / u, pitch)["cp"] * u

    def rhs(self, state: Any, u_rel: Any, omega: Any, pitch: Any, rho: Any, *, cp_scale: Any = 1.0,
            ct_scale: Any = 1.0) -> tuple[Any, dict[str, Any]]:
        """``(ẇ, v̇)`` and the loads at state ``(w, v)`` [m/s].

        Returns
        -------
        rhs : (2,) expression
        loads : dict
            ``thrust`` [N], ``torque`` [N m], ``v_qs`` [m/s], ``u_disk`` [m/s], ``tau1`` [s].
        """
        rotor = self.rotor
        w, v = state[0], state[1]
        u = rotor._speed(u_rel)
        v_qs = self.quasi_steady(u_rel, omega, pitch)
        u_d = rotor._speed(u - v)
        c = self.characteristic(omega * rotor.radius / u_d, pitch)
        dyn = 0.5 * rho * math.pi * rotor.radius**2 * u_d**2
        thrust = ct_scale * dyn * c["ct"]
        torque = cp_scale * dyn * rotor.radius * c["cq"]
        if self.mode == 2:
            a = v / u
            a_lim = 0.5 * (a + 0.5 - ca.sqrt((a - 0.5) ** 2 + 1e-4))          # smooth min(a, 0.5)
            tau1 = 1.1 / (1.0 - 1.3 * a_lim) * rotor.radius / u
        else:
            tau1 = self.tau1_const
        tau2 = TAU2_RATIO * tau1
        w_d = ((1.0 - OYE_K) * v_qs - w) / tau1
        v_d = (w + OYE_K * v_qs - v) / tau2
        return ca.vertcat(w_d, v_d), {"thrust": thrust, "torque": torque, "v_qs": v_qs, "u_disk": u_d,
                                      "tau1": tau1}


def _interp(x: np.ndarray, xp: np.ndarray, fp: np.ndarray) -> np.ndarray:
    """Linear interpolation with linear continuation beyond the data (not held)."""
    y = np.interp(x, xp, fp)
    if xp.size >= 2:
        lo, hi = x < xp[0], x > xp[-1]
        y[lo] = fp[0] + (x[lo] - xp[0]) * (fp[1] - fp[0]) / (xp[1] - xp[0])
        y[hi] = fp[-1] + (x[hi] - xp[-1]) * (fp[-1] - fp[-2]) / (xp[-1] - xp[-2])
    return y
