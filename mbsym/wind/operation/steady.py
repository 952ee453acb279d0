"""A steady-state *guess* of an operating turbine for a wind speed: initial conditions for simulations.

Not a trim (the operating-points tools solve the closed-loop equilibrium exactly): the rotor
speed and pitch follow the controller's targets, the rest is balanced on the model's own graph.

1. Rotor speed: ``Ω = λ* U / R`` (the controller's optimal TSR, its radius, the wind speed) within
   the controller's minimum and rated speeds.
2. Pitch: the minimum pitch (fine pitch, or the peak-shaving schedule at ``U``); if the
   aerodynamic power there exceeds rated power / generator efficiency, the pitch (within the
   actuator limits) where it equals it, by bisection on the rotor's surfaces.
3. Generator torque: balancing the aerodynamic torque; dynamic inflow at equilibrium.
4. Tower, drivetrain twist (and any other DOF but the rotor azimuth): the static deflection,
   Newton's method on the accelerations of those coordinates (exact Jacobian of the model's rhs),
   their speeds zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ParameterError, SolverError

__all__ = ["SteadyGuess", "steady_guess"]


@dataclass(frozen=True)
class SteadyGuess:
    """``state`` (the model's state vector) and the numbers it was built from (SI units)."""

    wind_speed: float
    rotor_speed: float
    pitch: float
    torque: float
    state: np.ndarray


def steady_guess(model, wind_speed: float, *, settings=None, p=None) -> SteadyGuess:
    """A steady-state guess of ``model`` (an :class:`~.model.OperatingTurbine`) at ``wind_speed`` [m/s].

    Parameters
    ----------
    model : OperatingTurbine
    wind_speed : float
        Hub-height wind [m/s] (> 0).
    settings : BaselineSettings, optional, keyword-only
        The controller's targets; default the built-in NREL 5 MW's (ROSCO 2.10.6).
    p : dict, optional, keyword-only
        Model parameters by name.

    Raises
    ------
    ParameterError
        A wind speed that is not a positive number.
    SolverError
        The tower deflection does not converge.
    """
    from .nrel5mw import nrel5mw_baseline_settings

    if not (isinstance(wind_speed, (int, float)) and np.isfinite(wind_speed) and wind_speed > 0):
        raise ParameterError(f"wind_speed must be a positive number [m/s]; got {wind_speed!r}.")
    s = nrel5mw_baseline_settings() if settings is None else settings
    dyn = model.dynamics()
    pv = dyn.parameter_vector(p)
    par = dict(zip(dyn.parameters, pv))
    n = s.gearbox_ratio
    u = float(wind_speed)
    omega = float(np.clip(s.optimal_tsr * u / s.rotor_radius, s.min_generator_speed / n,
                          s.rated_generator_speed / n))
    beta_min = s.fine_pitch
    if s.peak_shaving:
        beta_min = max(beta_min, float(np.interp(u, s.min_pitch_wind_speeds, s.min_pitch_schedule)))
    beta_min = float(np.clip(beta_min, par["pitch_min"], par["pitch_max"]))
    u_shaft = u * np.cos(model.rotor.shaft_tilt)
    target = s.rated_power / par["generator_efficiency"] / model.gearbox_efficiency     # aerodynamic power
    beta = beta_min
    if _power(model, u_shaft, omega, beta, par) > target:
        lo, hi = beta_min, par["pitch_max"]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if _power(model, u_shaft, omega, mid, par) > target else (lo, mid)
        beta = 0.5 * (lo + hi)
    n_q = model.structure.eom.n_q
    x = dict(zip(dyn.states, model.initial_state(u, pitch=beta, p=p)))
    for name in dyn.states[n_q:2 * n_q]:           # at rest, except the rotor
        x[name] = 0.0
    if model.spins_freely:
        x["GeAz_d"] = omega
    x = _static_tower(model, np.array([x[name] for name in dyn.states]), u, pv)
    x = _balanced_torque(model, _equilibrium_inflow(model, x, u, pv), u, p)
    torque = float(x[dyn.states.index("GenTq")])
    return SteadyGuess(u, omega, beta, torque, x)


def _power(model, u_shaft: float, omega: float, beta: float, par: dict) -> float:
    loads = model.rotor.steady(u_shaft, omega, beta, par["air_density"])
    return float(loads["power"]) * par.get("cp_scale", 1.0)


def _static_tower(model, x: np.ndarray, wind: float, p: np.ndarray, iterations: int = 20) -> np.ndarray:
    """Newton on the accelerations of the non-rotating coordinates (speeds zero), inflow at equilibrium."""
    dyn = model.dynamics()
    eom = model.structure.eom
    n_q = eom.n_q
    idx = [i for i, c in enumerate(eom.coordinates) if c != "GeAz"]
    if not idx:
        return x
    u = dyn.input_vector({"Wind1VelX": wind, "BlPitchCom": x[dyn.states.index("BlPitch")],
                          "GenTqCom": x[dyn.states.index("GenTq")]})
    X = (ca.SX if dyn.rhs.is_a("SXFunction") else ca.MX).sym("x", dyn.n_x)   # a floating plant's rhs is MX
    acc = dyn.rhs(X, u, p)[[n_q + i for i in idx]]
    f = ca.Function("tower_balance", [X], [acc, ca.jacobian(acc, X)[:, idx]])
    x = x.copy()
    for _ in range(iterations):
        x = _equilibrium_inflow(model, x, wind, p)
        x = _balanced_torque(model, x, wind, p)
        r, J = (np.asarray(v, dtype=float) for v in f(x))
        step = np.linalg.solve(J, -r.reshape(-1))
        x[idx] += step
        if np.max(np.abs(step)) < 1e-9:
            return x
    raise SolverError(f"the static tower deflection did not converge at {wind:g} m/s (last step "
                      f"{np.max(np.abs(step)):.3g} m).")


def _equilibrium_inflow(model, x: np.ndarray, wind: float, p: np.ndarray) -> np.ndarray:
    dyn = model.dynamics()
    if model.dynamic_inflow is None and not model.inflow_lag:
        return x
    names = ("DBEMT_w", "DBEMT_v") if model.dynamic_inflow is not None else ("RotThrustLag", "RotTorqLag")
    eq = np.asarray(model._part("inflow_steady")(x, dyn.input_vector({"Wind1VelX": wind}), p), dtype=float)
    x = x.copy()
    for name, value in zip(names, eq.reshape(-1)):
        x[dyn.states.index(name)] = value
    return x


def _balanced_torque(model, x: np.ndarray, wind: float, p) -> np.ndarray:
    """``x`` with the generator torque balancing the aerodynamic torque; ``p`` a dict, a vector or None."""
    dyn = model.dynamics()
    if p is not None and not isinstance(p, dict):
        p = dict(zip(dyn.parameters, np.asarray(p, dtype=float).tolist()))
    x = x.copy()
    x[dyn.states.index("GenTq")] = model.balancing_torque(x, wind, p)
    return x
