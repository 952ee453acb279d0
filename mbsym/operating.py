"""Operating points for linearization: static equilibrium, steady rotation, azimuth sweeps.

- :func:`static_equilibrium`: ``F(q, 0, u, p) = 0`` under gravity and constant inputs,
  solved by CasADi's Newton rootfinder with the exact stiffness Jacobian.
- :func:`steady_rotation`: a rotor spinning at a constant speed, every other DOF at its
  *mean* deflection: the generalized forces averaged over ``n_azimuth`` equally spaced
  rotor azimuths vanish.
- :func:`linearize_azimuths`: linearizations at several rotor azimuths in one batch
  (:func:`mbsym.linear.linearize_batch`), and their average
  (:meth:`AzimuthSweep.average`), in multi-blade coordinates
  (:func:`mbsym.wind.analysis.mbc.mbc_transform`) when the model has rotating-frame blade DOFs.

Coordinates without stiffness (a free generator azimuth, an unmoored surge) have no
static equilibrium value: they are *held* at their initial value (found automatically,
or named with ``hold=``). If a held coordinate carries a net generalized force there is
no equilibrium, and the result says so (``success`` False and a ``message`` naming it);
solver failures are reported the same way, never silently.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Callable, Mapping, Sequence

import casadi as ca
import numpy as np

from .exceptions import DimensionError, ModelDefinitionError
from .linear import LinearBatch, LinearModel, _cached, _Target, jacobian_function, linearize_batch

__all__ = ["OperatingPoint", "static_equilibrium", "steady_rotation", "AzimuthSweep", "linearize_azimuths"]


@dataclass(frozen=True)
class OperatingPoint:
    """A state, inputs and parameters to linearize about (pass it as ``q0`` to ``linearize``).

    Attributes
    ----------
    q, qd, qdd : ndarray (n_q,)
        Coordinates [m, rad], speeds and accelerations (zero at an equilibrium).
    u : ndarray (n_u,)
        Inputs.
    p : dict
        Parameter values by name.
    coordinates, inputs : tuple of str
    held : tuple of str
        Coordinates kept at their initial value (no stiffness, or the spinning one).
    residual : ndarray (n_q,)
        Generalized forces left at the solution [N, N m] (averaged over azimuth for a
        steady rotation; the spinning coordinate's entry is the torque needed to keep
        the speed constant).
    success : bool
    message : str
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    u: np.ndarray
    p: dict
    coordinates: tuple[str, ...]
    inputs: tuple[str, ...]
    held: tuple[str, ...] = ()
    residual: np.ndarray = field(default_factory=lambda: np.zeros(0))
    success: bool = True
    message: str = ""

    @property
    def x(self) -> np.ndarray:
        """``[q; qd]``."""
        return np.concatenate([self.q, self.qd])


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


def _solve(target: _Target, Qs: np.ndarray, qd: np.ndarray, U: np.ndarray, pp: np.ndarray, held: Sequence[str],
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
    return _cached(eom, ("forcing_map", n_s), lambda: eom.functions.forcing.map(n_s))


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
    target = _Target(model)
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


def _rotating_coordinate(target: _Target, coordinate: str | None) -> tuple[str, bool]:
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
    target = _Target(model)
    eom = target.eom
    name, prescribed = _rotating_coordinate(target, coordinate)
    if not np.isfinite(speed) or int(n_azimuth) < 1:
        raise ValueError(f"speed must be finite and n_azimuth >= 1; got speed={speed!r}, n_azimuth={n_azimuth!r}.")
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


# --------------------------------------------------------------------------- azimuth sweeps
_BLADE = re.compile(r"B(\d+)(F1|E1|F2)")


def blade_indices(coordinates: Sequence[str]) -> list[tuple[int, ...]]:
    """Index triplets (blades 1, 2, 3) per blade DOF type, from names ``B<k>F1``, ``B<k>E1``, ``B<k>F2``."""
    groups: dict[str, dict[int, int]] = {}
    for i, c in enumerate(coordinates):
        m = _BLADE.fullmatch(c)
        if m:
            groups.setdefault(m.group(2), {})[int(m.group(1))] = i
    return [tuple(g[k] for k in sorted(g)) for g in groups.values()]


@dataclass(frozen=True)
class AzimuthSweep:
    """Linearizations of a spinning rotor at several azimuths.

    Attributes
    ----------
    azimuths : ndarray (n_s,)
        Values of the spinning coordinate [rad].
    blade_azimuths : ndarray (n_s,)
        Azimuth of blade 1 [rad] (for multi-blade coordinates).
    rotor_speed : float
        [rad/s].
    batch : LinearBatch
        The linear models, one per azimuth.
    blade_indices : list of tuple
        Rotating-frame blade DOF triplets in ``q`` (empty without blade DOFs).
    """

    azimuths: np.ndarray
    blade_azimuths: np.ndarray
    rotor_speed: float
    batch: LinearBatch
    blade_indices: list

    def average(self, *, mbc: Callable | None = None) -> LinearModel:
        """The azimuth-averaged linear model.

        Without rotating-frame DOFs every coordinate is in the fixed frame and the
        matrices are averaged as they are. With blade DOFs each azimuth's model is
        first written in multi-blade coordinates (Coleman): ``mbc(A, blade_indices,
        azimuth, rotor_speed, B=B) -> (A_B, B_B)`` (default
        :func:`mbsym.wind.analysis.mbc.mbc_transform`), M, C, K by
        :func:`mbsym.wind.analysis.mbc.mbc_second_order`, outputs by ``Cy T``; blade
        coordinates then read collective, cosine, sine.
        """
        b = self.batch
        lins = [b[i] for i in range(len(b))]
        if self.blade_indices:
            lins = [self._to_fixed_frame(lin, psi, mbc) for lin, psi in zip(lins, self.blade_azimuths)]
        keys = ("M", "C", "K", "Q", "A", "B", "Cy", "Dy")
        mean = {k: np.mean([getattr(lin, k) for lin in lins], axis=0) for k in keys}
        op = dict(lins[0].operating_point)
        op["azimuths"] = self.azimuths.copy()
        return LinearModel(mean["M"], mean["C"], mean["K"], mean["Q"], mean["A"], mean["B"], b.coordinates, b.states,
                           b.inputs, op, b.outputs, mean["Cy"], mean["Dy"], b.output_units, b.method)

    def _to_fixed_frame(self, lin: LinearModel, psi: float, mbc) -> LinearModel:
        from .wind.analysis.mbc import coleman_matrices, mbc_second_order, mbc_transform

        mbc = mbc or mbc_transform
        om, n = self.rotor_speed, len(lin.coordinates)
        A, B = mbc(lin.A, self.blade_indices, psi, om, B=lin.B)
        M, C, K = mbc_second_order(lin.M, lin.C, lin.K, self.blade_indices, psi, om)
        T = coleman_matrices(n, self.blade_indices, psi)
        Tx = np.block([[T.T1, np.zeros((n, n))], [om * T.T2, T.T1]])
        Q = np.linalg.solve(T.T1, lin.Q)
        return LinearModel(M, C, K, Q, A, B, lin.coordinates, lin.states, lin.inputs, lin.operating_point,
                           lin.outputs, lin.Cy @ Tx, lin.Dy, lin.output_units, lin.method)

    def modes(self, **kw) -> list:
        """Modes of the averaged model (:meth:`average`)."""
        return self.average(**kw).modes()


def linearize_azimuths(model, op: OperatingPoint | None = None, azimuths: int | Sequence[float] = 12, *,
                       coordinate: str | None = None, outputs=None, method: str = "exact", steps=None,
                       qdd0=None) -> AzimuthSweep:
    """Linearize at several azimuths of the spinning coordinate, all in one batch.

    Parameters
    ----------
    model : EquationsOfMotion or model object
    op : OperatingPoint, optional
        E.g. from :func:`steady_rotation`; default: the model's default state and inputs.
    azimuths : int or sequence of float
        A number of equally spaced azimuths over a revolution, starting at the
        operating point's, or the coordinate values themselves [rad].
    coordinate : str, optional, keyword-only
        The spinning coordinate (default ``"GeAz"``).
    outputs, method, steps, qdd0 : optional, keyword-only
        As for :func:`mbsym.linearize`.

    Returns
    -------
    AzimuthSweep
        ``.average()`` gives the azimuth-averaged model (multi-blade coordinates
        with blade DOFs).
    """
    target = _Target(model)
    eom = target.eom
    name, prescribed = _rotating_coordinate(target, coordinate)
    if op is None:
        q, qd = target.state(None, None)
        u, p = target.inputs(None), None
    else:
        q, qd, u, p = op.q, op.qd, op.u, op.p
    if prescribed:
        psi0, speed = u[eom.inputs.index(name)], u[eom.inputs.index(f"{name}_d")]
    else:
        psi0, speed = q[eom.coordinates.index(name)], qd[eom.coordinates.index(name)]
    if np.ndim(azimuths) == 0:
        psi = psi0 + 2 * np.pi * np.arange(int(azimuths)) / int(azimuths)
    else:
        psi = np.asarray(azimuths, dtype=float).reshape(-1)
    X, U = _azimuth_samples(target, name, prescribed, q, qd, u, psi)
    batch = linearize_batch(model, X, U, p, outputs=outputs, method=method, steps=steps,
                            qdd0=qdd0)
    offset = _blade1_offset(target, name)
    if not prescribed and "DrTr" in eom.coordinates:
        offset_q = X[:, eom.coordinates.index("DrTr")]
    else:
        offset_q = 0.0
    return AzimuthSweep(psi, psi + offset_q + offset, float(speed), batch, blade_indices(eom.coordinates))


def _blade1_offset(target: _Target, name: str) -> float:
    """Azimuth of blade 1 minus the spinning coordinate: ElastoDyn's AzimB1Up + π/2 for a turbine's GeAz."""
    turbine = getattr(target.owner, "turbine", None)
    if name == "GeAz" and turbine is not None and hasattr(turbine, "azimuth_blade1_up"):
        return float(turbine.azimuth_blade1_up + np.pi / 2)
    return 0.0
