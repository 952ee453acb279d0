"""The baseline controller linearized about a steady operating point (a discrete-time linear model).

:class:`~.baseline.BaselineController` is one CasADi step ``(xc, y) -> (xc_next, u)`` at its sample
time ``dt``. At a trimmed operating point of the turbine the measurements ``y*`` and the commands
``u*`` are constant; the controller's **fixed point** ``xc*`` is the state it settles to there:

    xc* = f(xc*, y*),        u(xc*, y*) = u*.

Its integrators (pitch and torque PI) make the first equation singular on its own (a PI holds any output
once its error is zero), so the commands are part of the problem: :func:`controller_fixed_point` solves
the (consistent, overdetermined) system by Levenberg–Marquardt on residuals scaled by the size of each
state (plain Gauss–Newton steps from the settled state can cross a saturation, e.g. of the pitch at its
peak-shaving minimum, and stall there). Nothing moves at a fixed point, so the rate limiters are
inactive there and the search runs on the same controller without them (a Newton step that changed a
limiter's memory by more than a sample's worth of rate would otherwise stall on the limit); the residual
is then checked on the controller itself. It starts from the state after the controller's own first call
(which initializes every block from ``y*``) and :data:`SETTLE_TIME` seconds of steps at constant ``y*``
with the states that remember the previous commands and the PI integrals (:data:`COMMAND_MEMORIES`) held
at ``u*``: that cuts the loops inside the controller (previous pitch and torque → wind-speed estimate →
minimum pitch, torque reference and set-point smoother → commands), which without the turbine can drift,
so the filters and the estimator settle to their values at the trim. The estimator's covariance and gain
(:data:`COVARIANCE_STATES`) are then advanced by the controller's own recursion, every other state held, until they
stop changing: the stabilizing solution of the EKF's Riccati equation, from which the search starts (from
farther away it had found another solution, an indefinite covariance with a gain of the wrong sign, and with it
closed loops unstable where the controller runs stably). The logical states
(:data:`LOGICAL_STATES`: the first-call flag, the estimator's in-range flag) keep the values the
controller gives them. If no such state exists the trim and the controller disagree (a
:class:`~mbsym.exceptions.SolverError` says so).

:func:`linearize_controller` then takes the exact Jacobians of the step there (CasADi AD through every
branch that is active at the point: a saturated PI passes nothing, a rate limiter below its limit passes
everything, the gain schedule is evaluated at the filtered pitch, the estimator's EKF at its settled
covariance). One care: the estimator's Cp table is piecewise bilinear, and in region 2 the torque loop
holds the estimator's tip-speed ratio at ``VS_TSRopt``, a node of the table, where the slope jumps. AD
at the node returns one of the two one-sided slopes, whichever rounding selects (the NREL 5 MW's
torque-loop gain margin at 6 m/s came out 10.1 or 11.0 dB for two trims equal to 1e-14). The Jacobians
are therefore the mean of the AD Jacobians with the estimator's wind states (:data:`NUDGED_STATES`)
moved by ±:data:`NUDGE` (relative), one on each side of the node: the gain a small oscillation about
the node sees. Off a node the two agree with AD to ~1e-9. (Central differences of the whole step would
do the same at the node but cross the controller's switches, e.g. the estimator's range check when the
pitch rests on its minimum.) The model is

    δxc_{k+1} = A δxc_k + B δy_k,        δu_k = C δxc_k + D δy_k,

a **discrete-time** model at the controller's own sample time — exactly what runs in the loop
(:mod:`mbsym.wind.operation.controllers`), with no continuous approximation of its Tustin filters.
States that, at the point, neither feel the measurements nor move the commands (the first-call flag,
the EKF's covariance and gain, whose effect on the estimate is multiplied by the innovation, zero at a
fixed point, the rate limiters' memories …) are left out: an entry of a Jacobian counts when it
exceeds :data:`CONNECTION_TOLERANCE` after scaling by the sizes of the signals it connects. Removing
states with no path from ``y`` to ``u`` leaves the transfer function unchanged; the names of the left-out
states are kept (``removed_states``).

Refused: individual pitch control (its loops act on the rotating blade loads, which a rotor-effective
model does not have).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from ...exceptions import ControllerError, DimensionError, ParameterError, SolverError
from .baseline import BaselineController

__all__ = ["LinearizedController", "controller_fixed_point", "linearize_controller", "LOGICAL_STATES",
           "SETTLE_TIME", "COMMAND_MEMORIES", "CONNECTION_TOLERANCE", "FIXED_POINT_TOLERANCE"]

#: States that hold logic (flags, stages, the shut-down's latch, the step count that is ROSCO's clock), kept at
#: the values the controller's own steps give them (the shut-down and start-up sit where :data:`SETTLE_TIME`
#: leaves them: normal operation when the start-up has ended and no trigger has tripped).
LOGICAL_STATES = ("first", "estimator_on", "step_count", "shutdown_trigger", "shutdown_stage", "startup_stage")
#: States that advance by one every step (their fixed-point residual is ``xc_next - xc - 1``).
CLOCK_STATES = ("step_count",)
#: The estimator's covariance and gain: at a fixed point they solve the EKF's Riccati equation, which has other
#: solutions than the one its recursion converges to (an indefinite covariance, a gain of the wrong sign: found by
#: a root search on the whole state, it made the NREL 5 MW deck's region-2 loop unstable at 5-6 m/s where the
#: controller runs stably). They are settled by the recursion itself, never moved by the search.
COVARIANCE_STATES = ("ekf_P", "ekf_K")
#: Steps per round of the covariance's recursion, and the most rounds (the change per round must fall below
#: :data:`POLISH_TOLERANCE`, scaled).
COVARIANCE_STEPS, COVARIANCE_ROUNDS = 2000, 200
#: Time [s] the controller runs at constant measurements, its command memories held, before the search.
SETTLE_TIME = 60.0
#: States equal to a command at a fixed point (state -> command), held there while settling: the memories of
#: the previous commands, and the PI integrals (a PI at rest outputs its integral, a saturated one is clamped
#: at its limit, the command; with ``VS_ControlMode 2`` also ``torque_integral``).
COMMAND_MEMORIES = {"torque_last": "GenTqCom", "pitch_total_last": "BlPitchCom", "pitch_last": "BlPitchCom",
                    "pitch_command_last": "BlPitchCom", "pitch_integral": "BlPitchCom"}
#: Scaled Jacobian entries below this count as no connection when states are left out.
CONNECTION_TOLERANCE = 1e-9
#: Largest scaled residual of an accepted fixed point (state change per step / state size; command / size).
FIXED_POINT_TOLERANCE = 1e-9
#: The search goes on to this scaled residual (or until no step lowers it): at an exact fixed point the estimator's
#: innovation vanishes, and with it the coupling of the EKF's covariance to the estimate.
POLISH_TOLERANCE = 1e-14
#: The estimator's wind states (EKF mean and turbulent wind, the estimate) moved by ±NUDGE (relative) for the two
#: one-sided Jacobians at a node of the Cp table (module docstring).
NUDGED_STATES = ("ekf_x[1]", "ekf_x[2]", "wind_estimate")
NUDGE = 1e-9
#: Rate limit [rad/s, N m/s] of the controller the fixed point is searched on (no limit in effect: module docstring).
UNLIMITED_RATE = 1e12


@dataclass(frozen=True)
class LinearizedController:
    """The baseline controller's discrete-time linear model about a fixed point (module docstring).

    ``δxc_{k+1} = A δxc_k + B δy_k``, ``δu_k = C δxc_k + D δy_k`` with ``δ`` the deviations from
    :attr:`operating_point`, every signal in SI units (:data:`~.baseline.MEASUREMENTS`,
    :data:`~.baseline.COMMANDS`).

    Attributes
    ----------
    A, B, C, D : ndarray
        (n, n), (n, n_y), (n_u, n), (n_u, n_y).
    dt : float
        Sample time [s].
    states : tuple of str
        The kept controller states (names of :attr:`BaselineController.state_names`).
    measurements, commands : tuple of str
    operating_point : dict
        ``xc`` (every state of the controller, ndarray), ``y``, ``u`` (by name, SI).
    removed_states : tuple of str
        States without a path from the measurements to the commands at this point.
    residual : float
        Largest scaled residual of the fixed point.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    dt: float
    states: tuple[str, ...]
    measurements: tuple[str, ...]
    commands: tuple[str, ...]
    operating_point: Mapping = field(repr=False)
    removed_states: tuple[str, ...] = ()
    residual: float = 0.0

    def to_statespace(self):
        """A discrete python-control ``StateSpace`` (``dt``; signals named, states ``baseline.<name>``)."""
        import control

        return control.ss(self.A, self.B, self.C, self.D, self.dt, inputs=list(self.measurements),
                          outputs=list(self.commands), states=[f"baseline.{s}" for s in self.states],
                          name="baseline_controller")

    def __repr__(self) -> str:
        return (f"LinearizedController(dt={self.dt:g} s, {len(self.states)} states kept, "
                f"{len(self.removed_states)} left out, measurements={list(self.measurements)}, "
                f"commands={list(self.commands)}, residual={self.residual:.1e})")


def _vector(values, names: Sequence[str], what: str) -> np.ndarray:
    """Values by name (mapping) or in ``names`` order (sequence) as a finite float vector."""
    if isinstance(values, Mapping):
        missing = [n for n in names if n not in values]
        unknown = [k for k in values if k not in names]
        if missing or unknown:
            raise DimensionError(f"{what}: expected the names {list(names)}; missing {missing}, unknown {unknown}.")
        v = np.array([float(values[n]) for n in names])
    else:
        v = np.asarray(values, dtype=float).reshape(-1)
        if v.size != len(names):
            raise DimensionError(f"{what} has {v.size} entries; expected {len(names)}: {list(names)}.")
    if not np.all(np.isfinite(v)):
        raise ParameterError(f"{what} must be finite; got {dict(zip(names, v.tolist()))}.")
    return v


def _check(controller) -> None:
    if not isinstance(controller, BaselineController):
        raise TypeError(f"controller must be a BaselineController; got {type(controller).__name__}.")
    if controller.ipc:
        raise ControllerError(f"the controller runs individual pitch control (IPC_ControlMode "
                              f"{controller.settings.ipc_mode}): its loops act on rotating blade loads, which the "
                              "linearization about a steady point does not model; set IPC_ControlMode 0.")


def _residual_function(controller: BaselineController) -> ca.Function:
    """``(xc, y) -> ([xc_next - xc; u], d/dxc)`` of the controller without rate limits (:data:`UNLIMITED_RATE`),
    built once per controller."""
    cache = controller.__dict__.setdefault("_linear_functions", {})
    if "residual" not in cache:
        s = controller.settings
        f = BaselineController(dataclasses.replace(s, pitch_rate_min=-UNLIMITED_RATE, pitch_rate_max=UNLIMITED_RATE,
                                                   torque_rate_max=UNLIMITED_RATE)).function
        x, y = ca.SX.sym("xc", f.numel_in(0)), ca.SX.sym("y", f.numel_in(1))
        xn, u = f(x, y)
        r = ca.vertcat(xn - x, u)
        cache["residual"] = ca.Function("baseline_fixed_point", [x, y], [r, ca.jacobian(r, x)])
    return cache["residual"]


def _jacobian_function(controller: BaselineController) -> ca.Function:
    """``(xc, y) -> (A, B, C, D)`` of one step, built once per controller."""
    cache = controller.__dict__.setdefault("_linear_functions", {})
    if "jacobian" not in cache:
        f = controller.function
        x, y = ca.SX.sym("xc", f.numel_in(0)), ca.SX.sym("y", f.numel_in(1))
        xn, u = f(x, y)
        cache["jacobian"] = ca.Function("baseline_jacobian", [x, y], [ca.jacobian(xn, x), ca.jacobian(xn, y),
                                                                      ca.jacobian(u, x), ca.jacobian(u, y)])
    return cache["jacobian"]


def _start(controller: BaselineController, y: np.ndarray, u: np.ndarray) -> np.ndarray:
    """The state after the first call and :data:`SETTLE_TIME` seconds at ``y`` with the command memories held at
    ``u`` (module docstring)."""
    x = np.array(controller.function(controller.x0, y)[0], dtype=float).reshape(-1)
    steps = max(1, int(math.ceil(SETTLE_TIME / controller.dt)))
    X = _settle_function(controller, steps)(x, np.concatenate([y, u]))
    return np.array(X, dtype=float)[:, -1]


def _settle_function(controller: BaselineController, steps: int) -> ca.Function:
    """``(xc, [y; u]) -> Xc``: ``steps`` controller steps at constant ``y`` with :data:`COMMAND_MEMORIES` held at
    ``u`` (CasADi ``mapaccum``), built once per controller and length."""
    cache = controller.__dict__.setdefault("_linear_functions", {})
    key = ("settle", steps)
    if key not in cache:
        f = controller.function
        x, yu = ca.SX.sym("xc", f.numel_in(0)), ca.SX.sym("yu", f.numel_in(1) + len(controller.commands))
        y, u = yu[:f.numel_in(1)], yu[f.numel_in(1):]

        held = dict(COMMAND_MEMORIES)
        if controller.settings.torque_mode in (2, 3):
            held["torque_integral"] = "GenTqCom"

        def hold(v):
            for state, command in held.items():
                v[controller.state_names.index(state)] = u[controller.commands.index(command)]
            return v

        xn = hold(f(hold(ca.SX(x)), y)[0])
        step = ca.Function("baseline_settle_step", [x, yu], [xn])
        cache[key] = step.mapaccum("baseline_settle", steps, [0], [0])
    return cache[key]


def controller_fixed_point(controller: BaselineController, measurements, commands, *,
                           tol: float = FIXED_POINT_TOLERANCE, max_iter: int = 200) -> tuple[np.ndarray, float]:
    """The controller state that holds ``commands`` at constant ``measurements`` (module docstring).

    Parameters
    ----------
    controller : BaselineController
    measurements : mapping or sequence
        ``y*`` by name or in :attr:`BaselineController.measurements` order, SI units.
    commands : mapping or sequence
        ``u*`` (``BlPitchCom`` [rad], ``GenTqCom`` [N m]).
    tol : float, keyword-only
        Largest accepted scaled residual.
    max_iter : int, keyword-only

    Returns
    -------
    xc : ndarray
        Every state of the controller.
    residual : float
        Largest scaled residual.

    Raises
    ------
    SolverError
        No fixed point: the controller does not settle at these commands.
    ControllerError
        Individual pitch control.
    """
    _check(controller)
    y = _vector(measurements, controller.measurements, "measurements")
    u = _vector(commands, controller.commands, "commands")
    x = _start(controller, y, u)
    cov = _covariance_indices(controller)
    x = _settle_covariance(controller, x, y, cov)
    free = [i for i, n in enumerate(controller.state_names) if n not in LOGICAL_STATES]
    weights = 1.0 / np.concatenate([np.maximum(np.abs(x), 1.0), np.maximum(np.abs(u), 1.0)])
    advance = np.array([1.0 if n in CLOCK_STATES else 0.0 for n in controller.state_names])
    target = np.concatenate([advance, u])
    G = _residual_function(controller)

    def residual(xv):
        r, J = G(xv, y)
        return (np.array(r, dtype=float).reshape(-1) - target) * weights, \
            (np.array(J, dtype=float) * weights[:, None])[:, free]

    x = _levenberg_marquardt(residual, x, free, POLISH_TOLERANCE, max_iter)      # from the recursion's limit
    xn, un = (np.array(v, dtype=float).reshape(-1) for v in controller.function(x, y))
    r = np.concatenate([xn - x - advance, un - u]) * weights  # the controller itself, rate limits included
    worst = float(np.max(np.abs(r)))
    if not worst <= tol:
        names = list(controller.state_names) + list(controller.commands)
        bad = names[int(np.argmax(np.abs(r)))]
        raise SolverError(f"the baseline controller has no steady state at the measurements "
                          f"{dict(zip(controller.measurements, y.tolist()))} with the commands "
                          f"{dict(zip(controller.commands, u.tolist()))}: scaled residual {worst:.3g} (largest in "
                          f"{bad!r}, tolerance {tol:g}). The trim's steady laws and the controller must describe the "
                          "same controller: trim with SteadyControl.from_baseline(controller.settings).")
    return x, worst


def _covariance_indices(controller: BaselineController) -> list[int]:
    """Indices of :data:`COVARIANCE_STATES` in the controller's state."""
    return [i for i, n in enumerate(controller.state_names) if n.split("[")[0] in COVARIANCE_STATES]


def _settle_covariance(controller: BaselineController, x: np.ndarray, y: np.ndarray, cov: list[int]) -> np.ndarray:
    """``x`` with the covariance states advanced by the controller's own steps, every other state held, until they
    stop changing: the recursion's limit, the stabilizing solution of the Riccati equation (at a fixed point the
    innovation is zero, so the covariance does not move the other states)."""
    if not cov:
        return x
    cache = controller.__dict__.setdefault("_linear_functions", {})
    if "covariance" not in cache:
        f = controller.function
        xs, ys = ca.SX.sym("xc", f.numel_in(0)), ca.SX.sym("y", f.numel_in(1))
        xn = f(xs, ys)[0]
        mask = np.zeros(f.numel_in(0))
        mask[cov] = 1.0
        step = ca.Function("baseline_covariance_step", [xs, ys], [xs + ca.DM(mask) * (xn - xs)])
        cache["covariance"] = step.mapaccum("baseline_covariance", COVARIANCE_STEPS, [0], [0])
    scale = np.maximum(np.abs(x[cov]), 1e-12)
    for _ in range(COVARIANCE_ROUNDS):
        nxt = np.array(cache["covariance"](x, y), dtype=float)[:, -1]
        change = float(np.max(np.abs(nxt[cov] - x[cov]) / scale))
        x = nxt
        if change <= POLISH_TOLERANCE * COVARIANCE_STEPS:
            break
    return x


def _levenberg_marquardt(residual, x: np.ndarray, free: list[int], tol: float, max_iter: int) -> np.ndarray:
    """Minimize ``|residual(x)|`` over ``x[free]`` (Marquardt's diagonal scaling; a step is taken only when it
    lowers the residual, so an iterate never jumps across a saturation into a region it cannot leave)."""
    r, J = residual(x)
    lam = 1e-6
    for _ in range(max_iter):
        if np.max(np.abs(r)) <= tol:
            break
        JTJ, g = J.T @ J, J.T @ r
        scale = np.diag(np.diag(JTJ) + 1e-300)
        while lam <= 1e10:
            step = np.zeros_like(x)
            step[free] = np.linalg.solve(JTJ + lam * scale, -g)
            r_new, J_new = residual(x + step)
            if np.linalg.norm(r_new) < np.linalg.norm(r):
                x, r, J, lam = x + step, r_new, J_new, max(lam / 10.0, 1e-12)
                break
            lam *= 10.0
        else:
            break
    return x


def linearize_controller(controller: BaselineController, measurements, commands, *, reduce: bool = True,
                         tol: float = FIXED_POINT_TOLERANCE) -> LinearizedController:
    """The controller's discrete linear model about its fixed point at ``(measurements, commands)``.

    Parameters
    ----------
    controller : BaselineController
    measurements, commands : mapping or sequence
        As in :func:`controller_fixed_point` (SI units).
    reduce : bool, optional, keyword-only
        Leave out the states without a path from the measurements to the commands (module docstring).
    tol : float, keyword-only
        Fixed-point tolerance.

    Returns
    -------
    LinearizedController

    Examples
    --------
    >>> from mbsym.wind.control import BaselineController
    >>> from mbsym.wind.operation.nrel5mw import nrel5mw_baseline_settings
    >>> ctrl = BaselineController(nrel5mw_baseline_settings())
    >>> y = {"GenSpeed": 122.9096, "RotSpeed": 1.2671, "BldPitch1": 0.2083, "GenPwr": 5e6, "Wind1VelX": 16.0}
    >>> lin = linearize_controller(ctrl, y, {"BlPitchCom": 0.2083, "GenTqCom": 43093.5})  # doctest: +SKIP
    """
    x, worst = controller_fixed_point(controller, measurements, commands, tol=tol)
    y = _vector(measurements, controller.measurements, "measurements")
    u = _vector(commands, controller.commands, "commands")
    A, B, C, D = (np.array(m, dtype=float) for m in _jacobian_function(controller)(x, y))
    names = controller.state_names
    keep = _connected(A, B, C, np.maximum(np.abs(x), 1.0), np.maximum(np.abs(y), 1.0),
                      np.maximum(np.abs(u), 1.0)) if reduce else np.ones(len(names), dtype=bool)
    A, B, C, D = _two_sided_jacobians(controller, x, y)
    k = np.flatnonzero(keep)
    op = {"xc": x, "y": dict(zip(controller.measurements, y.tolist())),
          "u": dict(zip(controller.commands, u.tolist()))}
    return LinearizedController(A[np.ix_(k, k)], B[k], C[:, k], D, controller.dt, tuple(names[i] for i in k),
                                tuple(controller.measurements), tuple(controller.commands), op,
                                tuple(names[i] for i in np.flatnonzero(~keep)), worst)


def _two_sided_jacobians(controller: BaselineController, x: np.ndarray, y: np.ndarray):
    """``(A, B, C, D)``: the mean of the AD Jacobians at ``x`` with the estimator's wind states (:data:`NUDGED_STATES`)
    moved by ±:data:`NUDGE` × max(|value|, 1) (module docstring)."""
    jac = _jacobian_function(controller)
    idx = [controller.state_names.index(n) for n in NUDGED_STATES if n in controller.state_names]
    if controller.settings.wind_estimator != 2 or not idx:
        return tuple(np.array(m, dtype=float) for m in jac(x, y))
    h = np.zeros_like(x)
    h[idx] = NUDGE * np.maximum(np.abs(x[idx]), 1.0)
    plus, minus = jac(x + h, y), jac(x - h, y)
    return tuple(0.5 * (np.array(p, dtype=float) + np.array(m, dtype=float)) for p, m in zip(plus, minus))


def _connected(A, B, C, sx, sy, su, tol: float = CONNECTION_TOLERANCE) -> np.ndarray:
    """States on a path measurements -> states -> commands (scaled Jacobian entries above ``tol``)."""
    As = np.abs(A) * sx[None, :] / sx[:, None] > tol            # As[i, j]: state j moves state i
    reach = np.any(np.abs(B) * sy[None, :] / sx[:, None] > tol, axis=1)
    seen = np.any(np.abs(C) * sx[None, :] / su[:, None] > tol, axis=0)
    for _ in range(len(sx)):
        new_reach = reach | np.any(As[:, reach], axis=1)
        new_seen = seen | np.any(As[seen, :], axis=0)
        if np.array_equal(new_reach, reach) and np.array_equal(new_seen, seen):
            break
        reach, seen = new_reach, new_seen
    return reach & seen
