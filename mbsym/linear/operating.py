"""Operating points for linearization: static equilibrium, steady rotation, azimuth sweeps.

- :func:`static_equilibrium`: ``F(q, 0, u, p) = 0`` under gravity and constant inputs,
  solved by CasADi's Newton rootfinder with the exact stiffness Jacobian.
- :func:`steady_rotation`: a rotor spinning at a constant speed, every other DOF at its
  *mean* deflection: the generalized forces averaged over ``n_azimuth`` equally spaced
  rotor azimuths vanish.

Coordinates without stiffness (a free generator azimuth, an unmoored surge) have no
static equilibrium value: they are *held* at their initial value (found automatically,
or named with ``hold=``). If a held coordinate carries a net generalized force there is
no equilibrium, and the result says so (``success`` False and a ``message`` naming it);
solver failures are reported the same way, never silently.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from ..exceptions import DimensionError, ModelDefinitionError, OptionError
from ._cache import cached
from .functions import jacobian_function
from .point import OperatingPoint
from .target import Target

__all__ = ["static_equilibrium", "steady_rotation"]


def _neutral(K: np.ndarray, names: Sequence[str], rtol: float = 1e-9) -> list[str]:
    """Coordinates whose stiffness row and column vanish (free DOFs)."""
    scale = max(float(np.max(np.abs(K), initial=0.0)), 1e-300)
    small = np.abs(K) <= rtol * scale
    return [n for i, n in enumerate(names) if np.all(small[i]) and np.all(small[:, i])]


def _check_hold(hold, names: Sequence[str]) -> list[str]:
    hold = [hold] if isinstance(hold, str) else list(hold)
    unknown = sorted(set(hold) - set(names))
    if unknown:
        raise DimensionError(f"hold names unknown coordinates {unknown}; coordinates are {list(names)}.")
    return hold


def _solve(target: Target, Qs: np.ndarray, qd: np.ndarray, U: np.ndarray, pp: np.ndarray, held: Sequence[str],
           tol: float, max_iter: int) -> tuple[np.ndarray, np.ndarray, bool, str]:
    """Newton on the mean over the samples of F(q, qd, u) for the free coordinates.

    ``Qs`` (n_s, n_q) and ``U`` (n_u, n_s): per sample, the coordinates (the held ones
    keep these values, e.g. the rotor azimuth of each sample) and the inputs; the free
    coordinates are the unknowns, shared by every sample (their initial guess: row 0).
    """
    eom = target.eom
    free = [i for i, c in enumerate(eom.coordinates) if c not in held]
    n_s = U.shape[1]
    z = ca.SX.sym("z", len(free))
    Q = ca.SX(ca.DM(Qs.T))
    for k, i in enumerate(free):
        Q[i, :] = ca.repmat(z[k], 1, n_s)
    Fs = _forcing_map(eom, n_s)(Q, ca.repmat(ca.DM(qd), 1, n_s), ca.DM(U), ca.DM(pp))
    F = ca.sum2(Fs) / n_s
    scale = max(1.0, float(np.max(np.abs(_mean_force(eom, Qs, qd, U, pp)), initial=0.0)))
    Q_sol = Qs.copy()
    ok = True
    if free:
        g = ca.Function("equilibrium", [z], [F[free]])
        rf = ca.rootfinder("equilibrium_newton", "newton", g,
                           {"abstol": tol * scale, "max_iter": max_iter, "error_on_fail": False})
        sol = np.array(rf(Qs[0, free])).reshape(-1)
        ok = bool(rf.stats().get("success", False))
        Q_sol[:, free] = sol
    residual = _mean_force(eom, Q_sol, qd, U, pp)
    if not ok or not np.all(np.isfinite(Q_sol)):
        return Q_sol[0], residual, False, _newton_failure(target, Q_sol, qd, U, pp, free)
    return Q_sol[0], residual, True, ""


def _forcing_map(eom, n_s: int) -> ca.Function:
    """``forcing.map(n_s)``, built once per model and number of samples."""
    return cached(eom, ("forcing_map", n_s), lambda: eom.functions.forcing.map(n_s))


def _mean_force(eom, Qs: np.ndarray, qd: np.ndarray, U: np.ndarray, pp: np.ndarray) -> np.ndarray:
    """Mean over the samples (rows of Qs, columns of U) of the generalized forces F(q, qd, u, p)."""
    return np.array(_forcing_map(eom, U.shape[1])(Qs.T, qd, U, pp)).mean(axis=1)


def _newton_failure(target, Qs, qd, U, pp, free) -> str:
    eom = target.eom
    K = np.array(jacobian_function(eom)(Qs[0], qd, np.zeros(eom.n_q), U[:, 0], pp)[2])
    names = [eom.coordinates[i] for i in free]
    Kf = K[np.ix_(free, free)]
    msg = (f"Newton's method found no equilibrium for {names} (residual "
           f"{np.max(np.abs(_mean_force(eom, Qs, qd, U, pp)[free]), initial=0.0):.3g} N or N m).")
    if np.all(np.isfinite(Kf)) and Kf.size:
        w, v = np.linalg.eigh(0.5 * (Kf + Kf.T))
        if np.min(np.abs(w)) <= 1e-9 * max(np.max(np.abs(w)), 1e-300):
            weak = [names[i] for i in np.flatnonzero(np.abs(v[:, np.argmin(np.abs(w))]) > 0.1)]
            msg += f" The stiffness of {weak} vanishes at the last iterate: hold them (hold=[...]) or add a spring."
        else:
            msg += " Try a closer initial guess (q0=...) or smaller loads."
    return msg


def _held_message(eom, residual: np.ndarray, held: Sequence[str], scale: float, tol: float) -> str:
    bad = [(c, residual[eom.coordinates.index(c)]) for c in held
           if abs(residual[eom.coordinates.index(c)]) > max(tol * scale, 1e-9)]
    if not bad:
        return ""
    listed = ", ".join(f"{c} ({v:.4g})" for c, v in bad)
    return (f"no static equilibrium: the held coordinates without stiffness carry a net generalized force: {listed} "
            "[N or N m]; balance it with an input, add a spring, or linearize at this non-equilibrium state.")


def static_equilibrium(model, u0=None, p: Mapping[str, float] | None = None, *, q0=None,
                       hold: Sequence[str] | None = None, tol: float = 1e-10, max_iter: int = 50) -> OperatingPoint:
    """Static equilibrium ``F(q, 0, u, p) = 0`` under gravity and constant inputs.

    Parameters
    ----------
    model : EquationsOfMotion or model object (see :func:`mbsym.linearize`)
    u0 : sequence or dict, optional
        Constant inputs (default: the model's default inputs at t = 0).
    p : dict, optional
        Parameter values by name.
    q0 : sequence or dict, optional, keyword-only
        Initial guess (default: the model's default state); held coordinates keep it.
    hold : sequence of str, optional, keyword-only
        Coordinates to keep at ``q0``; default: those with no stiffness at ``q0``.
    tol : float, keyword-only
        Tolerance on the generalized forces, relative to their size at ``q0`` (at
        least 1e-9 N or N m): for Newton's method and for the net force a held
        coordinate may carry.
    max_iter : int, keyword-only

    Returns
    -------
    OperatingPoint
        ``success`` False with a ``message`` when Newton fails or a held coordinate
        carries a net force.

    Examples
    --------
    >>> import mbsym as mb
    >>> sys = mb.System(gravity=[0, 0, -10.0])
    >>> z = sys.coordinates("z")
    >>> sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("m", 2.0), axis=[0, 0, 1], coordinate=z))
    >>> sys.add_spring(z, 100.0)
    >>> op = static_equilibrium(sys.equations())
    >>> op.success, round(float(op.q[0]), 6)       # -m g / k
    (True, -0.2)
    """
    target = Target(model)
    eom = target.eom
    q_guess, _ = target.state(q0, None)
    uu, pp = target.inputs(u0), target.parameters(p)
    qd = np.zeros(eom.n_q)
    if hold is None:
        K = np.array(jacobian_function(eom)(q_guess, qd, qd, uu, pp)[2])
        held = _neutral(K, eom.coordinates)
    else:
        held = _check_hold(hold, eom.coordinates)
    U, Qs = uu.reshape(-1, 1), q_guess.reshape(1, -1)
    scale = max(1.0, float(np.max(np.abs(_mean_force(eom, Qs, qd, U, pp)), initial=0.0)))
    q, residual, ok, msg = _solve(target, Qs, qd, U, pp, held, tol, max_iter)
    if ok:
        msg = _held_message(eom, residual, held, scale, tol)
        ok = not msg
    if ok:
        msg = "static equilibrium" + (f"; held without stiffness: {held}" if held else "")
    return OperatingPoint(q, qd, np.zeros(eom.n_q), uu, dict(zip(eom.parameters, pp.tolist())), eom.coordinates,
                          eom.inputs, tuple(held), residual, ok, msg)


def _rotating_coordinate(target: Target, coordinate: str | None) -> tuple[str, bool]:
    """(name, prescribed?) of the spinning coordinate; default GeAz (wind turbines)."""
    eom = target.eom
    name = coordinate or ("GeAz" if "GeAz" in eom.coordinates + eom.prescribed else None)
    if name is None:
        raise ModelDefinitionError(f"name the spinning coordinate: coordinate=... (one of {list(eom.coordinates)} "
                                   f"or prescribed {list(eom.prescribed)}).")
    if name in eom.coordinates:
        return name, False
    if name in eom.prescribed:
        return name, True
    raise DimensionError(f"no coordinate {name!r}; coordinates are {list(eom.coordinates)}, prescribed "
                         f"{list(eom.prescribed)}.")


def _azimuth_samples(target, name, prescribed, q, qd, u, psi):
    """States (n_s, n_x) and inputs (n_s, n_u) at the rotor azimuths psi (values of the coordinate)."""
    eom = target.eom
    X = np.tile(np.concatenate([q, qd]), (psi.size, 1))
    U = np.tile(u, (psi.size, 1))
    if prescribed:
        U[:, eom.inputs.index(name)] = psi
    else:
        X[:, eom.coordinates.index(name)] = psi
    return X, U


def steady_rotation(model, speed: float, *, coordinate: str | None = None, u0=None,
                    p: Mapping[str, float] | None = None, q0=None, hold: Sequence[str] | None = None,
                    n_azimuth: int = 12, tol: float = 1e-10, max_iter: int = 50) -> OperatingPoint:
    """Steady rotation at ``speed`` [rad/s], the other DOFs at their mean deflection.

    The spinning coordinate (default ``GeAz``, the generator azimuth of a turbine;
    a prescribed one works too) turns at ``speed`` with zero acceleration; the other
    coordinates solve ``mean_k F(q, qd, u; ψ_k) = 0`` over ``n_azimuth`` equally spaced
    azimuths ψ_k (gravity and centrifugal loads, averaged over a revolution).

    Parameters
    ----------
    model : EquationsOfMotion or model object
    speed : float
        Rotor speed [rad/s] (d coordinate / dt).
    coordinate : str, optional, keyword-only
        The spinning coordinate (default ``"GeAz"`` when the model has it).
    u0, p, q0, hold, tol, max_iter : optional
        As for :func:`static_equilibrium`; the spinning coordinate is always held
        (its azimuth at the returned point is its value in ``q0``).
    n_azimuth : int, keyword-only
        Number of azimuths in the average (1: at the azimuth of ``q0`` only).

    Returns
    -------
    OperatingPoint
        ``residual`` at the spinning coordinate is the mean torque needed to keep
        the speed constant.
    """
    target = Target(model)
    eom = target.eom
    name, prescribed = _rotating_coordinate(target, coordinate)
    if not _finite_number(speed) or not _finite_number(n_azimuth) or int(n_azimuth) < 1:
        raise OptionError(f"speed must be finite [rad/s] and n_azimuth >= 1; got speed={speed!r}, "
                          f"n_azimuth={n_azimuth!r}.")
    q_guess, _ = target.state(q0, None)
    uu, pp = target.inputs(u0), target.parameters(p)
    qd = np.zeros(eom.n_q)
    if prescribed:
        psi0 = uu[eom.inputs.index(name)]
        uu[eom.inputs.index(f"{name}_d")], uu[eom.inputs.index(f"{name}_dd")] = speed, 0.0
    else:
        psi0 = q_guess[eom.coordinates.index(name)]
        qd[eom.coordinates.index(name)] = speed
    psi = psi0 + 2 * np.pi * np.arange(int(n_azimuth)) / int(n_azimuth)
    X, U = _azimuth_samples(target, name, prescribed, q_guess, qd, uu, psi)
    if hold is None:
        K = np.array(jacobian_function(eom)(q_guess, qd, np.zeros(eom.n_q), uu, pp)[2])
        held = [c for c in _neutral(K, eom.coordinates) if c != name]
    else:
        held = [c for c in _check_hold(hold, eom.coordinates) if c != name]
    held_all = held + ([] if prescribed else [name])
    Qs = X[:, :eom.n_q]
    scale = max(1.0, float(np.max(np.abs(_mean_force(eom, Qs, qd, U.T, pp)), initial=0.0)))
    q, residual, ok, msg = _solve(target, Qs, qd, U.T, pp, held_all, tol, max_iter)
    if ok:
        msg = _held_message(eom, residual, held, scale, tol)
        ok = not msg
    if ok:
        msg = f"steady rotation of {name} at {speed:.6g} rad/s" + (f"; held without stiffness: {held}" if held else "")
    return OperatingPoint(q, qd, np.zeros(eom.n_q), uu, dict(zip(eom.parameters, pp.tolist())), eom.coordinates,
                          eom.inputs, tuple(held_all), residual, ok, msg)


def _finite_number(value) -> bool:
    """Whether ``value`` is a finite real number (bool excluded)."""
    try:
        return not isinstance(value, bool) and bool(np.isfinite(float(value)))
    except (TypeError, ValueError):
        return False
