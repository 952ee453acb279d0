"""The blade-element rotor at rest: its dynamic-wake (DBEMT) and unsteady-airfoil (UA) states in equilibrium.

Helpers of :meth:`~mbsym.wind.aero.blade.BladeElementRotor.steady_states` (numbers in, numbers out).
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from ....exceptions import ParameterError
from . import dbemt, ua_continuous, unsteady

__all__ = ["wake_states", "unsteady_states"]


def unsteady_states(rotor, args: list, azimuth: Any, wake: np.ndarray, rotor_inputs: dict,
                    ua_omega: Any = None) -> np.ndarray:
    """The UA states at rest (:func:`.unsteady.steady_states`) at the nodes' angle of attack and speed with
    the wake states ``wake`` and the rotor-level inputs (skew, ``un_disk``, ``tsr``, ``tip_radius``).

    ``ua_omega`` (n values, blade by blade; default 0): the sections' rotation rate ``omega_z`` that the
    continuous models (``UA_Mod`` 4, 6) read: ``HGM_Steady`` sets their states from the first step's inputs, so
    from the 3/4-chord angle ``alpha_34`` with that rate (UnsteadyAero.f90 v5.0.0 ``HGM_Steady`` calls
    ``Get_HGM_constants`` with ``u%omega``). The discrete model (``UA_Mod 3``) does not read it."""
    n = rotor.n_blades * rotor.n_nodes
    keys = ("skew", "skew_azimuth", "tip_radius", "tsr", "un_disk")
    given = tuple(k for k in keys if rotor_inputs.get(k) is not None)
    f = rotor._cache.get(("ua_steady", given))  # type: ignore[attr-defined]
    if f is None:
        syms = [ca.SX.sym(name, n) for name in ("vx", "vy", "r", "theta", "azimuth")]
        omega = ca.SX.sym("omega", n)
        x = ca.SX.sym("x", wake.size)
        extra = {k: ca.SX.sym(k) for k in given}
        ua = rotor.unsteady
        m_ua = len(rotor.state_names) - wake.size
        out = rotor.evaluate(*syms, ca.vertcat(x, ca.SX.zeros(m_ua)), rho=1.0, **extra)
        idx = [int(i) for i in ua.index]
        if ua.continuous:                        # HGM_Steady at the rest's inputs and section rotation rate
            z = ua_continuous.steady(ua, rotor.polars, out["alpha"][idx], out["vrel"][idx], omega[idx])
        else:
            z = unsteady.steady_states(ua, out["alpha"][idx], out["vrel"][idx], rotor._static_polars(ua))
        f = ca.Function("blade_ua_steady", [*syms, x, omega, *extra.values()], [z])
        rotor._cache[("ua_steady", given)] = f  # type: ignore[attr-defined]
    psi = np.zeros(n) if azimuth is None else np.asarray(azimuth, dtype=float).ravel()
    psi = np.repeat(psi, rotor.n_nodes) if psi.size == rotor.n_blades else psi
    omega = np.zeros(n) if ua_omega is None else np.asarray(ua_omega, dtype=float).ravel()
    if omega.size != n or not np.all(np.isfinite(omega)):
        raise ParameterError(f"ua_omega must hold {n} finite numbers (one per node of every blade); got "
                             f"{omega.size}.")
    return np.asarray(f(*args, psi, wake, omega, *[float(rotor_inputs[k]) for k in given]), dtype=float).ravel()


def wake_states(rotor, args: list, tol: float, max_iter: int, guess: float) -> np.ndarray:
    """The DBEMT states at rest: iteration of the quasi-steady induction from the axial induction ``guess``."""
    n = rotor.n_blades * rotor.n_nodes
    f = rotor._cache.get("qs")  # type: ignore[attr-defined]
    if f is None:
        syms = [ca.SX.sym(name, n) for name in ("vx", "vy", "r", "theta")]
        x = ca.SX.sym("x", 4 * n)
        a, ap = rotor._quasi_steady(*syms, x)
        f = ca.Function("blade_qs_induction", [*syms, x], [ca.horzcat(-a * syms[0], ap * syms[1])])
        rotor._cache["qs"] = f  # type: ignore[attr-defined]
    # start from the states whose inflow angle is the quasi-steady start atan2(Vx (1 - a0), Vy): the first
    # iterate is then the quasi-steady induction (no second graph to build for it)
    x = dbemt.equilibrium(np.stack([-guess * args[0], np.zeros(n)], axis=1))
    for _ in range(max_iter):
        new = dbemt.equilibrium(np.asarray(f(*args, x)))
        change = np.max(np.abs(new - x))
        x = new
        if change <= tol:
            return x
    raise ParameterError(f"steady_states did not converge in {max_iter} iterations (last change {change:.3g} "
                         "m/s); check that the inputs describe an operating rotor (vx, vy > 0).")
