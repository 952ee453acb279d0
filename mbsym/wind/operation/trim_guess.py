"""Initial guesses of a trim from the rotor's performance surfaces (rigid rotor, no tower motion).

For a regime (:class:`~.steady_control.Regime`) and a wind speed, :func:`rotor_guess` finds the
rotor speed ``Ω`` [rad/s], pitch ``β`` [rad] and generator torque ``T`` [N m] that satisfy the
two loop conditions and the rotor's torque balance ``Q(U cos τ, Ω, β) = N T`` on the
:class:`~mbsym.wind.aero.RotorAero` surfaces (``τ`` the shaft tilt), by bisection: good enough
for Newton's method on the full model to converge in a few steps. The estimator's bias is
left out here (``Û = U``); the full trim solves it.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from typing import Callable

import numpy as np

__all__ = ["RotorGuess", "rotor_guess", "predicted_order"]


@dataclass(frozen=True)
class RotorGuess:
    """``rotor_speed`` [rad/s], ``pitch`` [rad], ``torque`` [N m] (generator shaft), ``ok``: bracketed."""

    rotor_speed: float
    pitch: float
    torque: float
    ok: bool


def _bisect(f: Callable[[float], float], lo: float, hi: float, n: int = 40) -> tuple[float, bool]:
    """A root of ``f`` in ``[lo, hi]`` (``ok`` False and the end with the smaller ``|f|`` if not bracketed)."""
    f_lo, f_hi = f(lo), f(hi)
    if not (np.isfinite(f_lo) and np.isfinite(f_hi)) or f_lo * f_hi > 0:
        return (lo if abs(f_lo) <= abs(f_hi) else hi), False
    for _ in range(n):
        mid = 0.5 * (lo + hi)
        f_mid = f(mid)
        if f_lo * f_mid <= 0:
            hi = mid
        else:
            lo, f_lo = mid, f_mid
    return 0.5 * (lo + hi), True


class _Rotor:
    """Aerodynamic torque [N m] of the rigid rotor at the wind along the shaft."""

    _functions: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()   # rotor -> its loads Function

    def __init__(self, model, wind_speed: float, par: dict[str, float]) -> None:
        rotor = model.rotor
        if rotor not in self._functions:
            self._functions[rotor] = rotor.function()       # (u, Ω, β, ρ) -> (torque, ...)
        self.f = self._functions[rotor]
        self.u = float(wind_speed) * math.cos(rotor.shaft_tilt)
        self.rho = par.get("air_density", rotor.air_density)
        self.cq_scale = par.get("cp_scale", 1.0)

    def torque(self, omega: float, pitch: float) -> float:
        return float(self.f(self.u, omega, pitch, self.rho)[0]) * self.cq_scale


def rotor_guess(model, control, regime, wind_speed: float, par: dict[str, float]) -> RotorGuess:
    """``(Ω, β, T)`` of ``regime`` at ``wind_speed`` [m/s] on the rotor surfaces (see the module docstring).

    Parameters
    ----------
    model : OperatingTurbine
    control : SteadyControl
    regime : Regime
    wind_speed : float
    par : dict
        Model parameters by name (air density, cp_scale, pitch limits).
    """
    rotor = _Rotor(model, wind_speed, par)
    c, n = control, control.gearbox_ratio
    nq = n / model.gearbox_efficiency              # the torque's ratio through a lossy gearbox (structure.gearbox)
    beta_min = float(c.min_pitch(wind_speed))
    w_min, w_rated = c.min_generator_speed / n, c.rated_generator_speed / n
    w_pitch = (c.pitch_reference_speed if c.pitch_control else c.rated_generator_speed) / n
    upper = lambda w: float(c.torque_upper(w * n))            # noqa: E731 - torque limit at rotor speed w
    pitch_hi = min(c.pitch_max, par.get("pitch_max", c.pitch_max))
    kind = (regime.torque, regime.pitch)
    if kind[1] == "max":
        beta = pitch_hi
    else:
        beta = beta_min
    if kind == ("track", "min"):
        if c.torque_mode == 2:
            w = float(np.clip(c.optimal_tsr * wind_speed / c.rotor_radius, w_min, w_rated))
            return RotorGuess(w, beta, rotor.torque(w, beta) / nq, True)
        law = lambda w: c.region2_gain * (w * n) ** 2 / c.generator_efficiency   # noqa: E731 (mode 3)
        w, ok = _bisect(lambda w: rotor.torque(w, beta) - nq * law(w), max(w_min, 1e-3), w_rated)
        return RotorGuess(w, beta, law(w), ok)
    if kind[0] == "k2":
        law = lambda w: c.region2_gain * (w * n) ** 2        # noqa: E731
        w, ok = _bisect(lambda w: rotor.torque(w, beta) - nq * law(w), max(w_min, 1e-3), w_rated)
        return RotorGuess(w, beta, law(w), ok)
    if kind[0] in ("hold_min", "hold_rated"):
        w = w_min if kind[0] == "hold_min" else w_rated
        return RotorGuess(w, beta, rotor.torque(w, beta) / nq, True)
    torque_at = {"upper": upper, "lower": lambda w: c.torque_min,
                 "arsat": lambda w: c.region25_torque_max}.get(kind[0], upper)
    if kind[1] == "track":
        w = w_pitch
        t = torque_at(w)
        beta, ok = _bisect(lambda b: rotor.torque(w, b) - nq * t, beta_min, pitch_hi)
        return RotorGuess(w, beta, t, ok)
    lo = max(w_min, 1e-3) if kind[0] == "lower" else min(w_rated, w_pitch)
    floats = kind[0] == "lower" or kind[1] == "max" or not c.pitch_control     # nothing caps the speed
    hi = 3.0 * max(w_pitch, w_rated) if floats else max(w_rated, w_pitch)
    if hi <= lo:
        hi = lo * 1.05
    w, ok = _bisect(lambda w: rotor.torque(w, beta) - nq * torque_at(w), lo, hi)
    return RotorGuess(w, beta, torque_at(w), ok)


def predicted_order(model, control, wind_speed: float, par: dict[str, float]) -> tuple:
    """The controller's regimes, the one the rotor surfaces predict first.

    Region 2 is predicted unless its torque would exceed the region-3 limit (or ``VS_ArSatTq``
    in mode 1), then region 3 first.
    """
    regimes = list(control.regimes())
    first = regimes[0]
    g = rotor_guess(model, control, first, wind_speed, par)
    n = control.gearbox_ratio
    limit = float(control.torque_upper(g.rotor_speed * n))
    if control.torque_mode == 1:
        limit = min(limit, control.region25_torque_max) if control.region25_torque_max > 0 else limit
    if g.torque > limit:
        above = [r for r in regimes if r.pitch == "track" and r.torque == "upper"]
        regimes = above + [r for r in regimes if r not in above]
    return tuple(regimes)
