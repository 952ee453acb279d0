"""MoorDyn's moving lines beside a floating model in a simulation, as OpenFAST's glue code runs MoorDyn.

A model whose platform has :attr:`~.operating.FloatingPlatform.moving_lines` holds the lines' statics in its graph
(the fairlead forces of the lines at rest, :class:`~.mooring.MooringSystem`) and takes their dynamic part as inputs
(:attr:`~.operating.FloatingPlatform.mooring_inputs`). :class:`LinesInLoop` supplies those inputs: it is a
discrete module of the closed loop (:class:`~mbsym.simulate.DiscreteController`, a Python law called once per
sample, like a DISCON library), which at every sample ``t_k``

1. reads the platform's DOFs and rates (disabled DOFs at their initial values, as ElastoDyn holds them) and
   places the fairleads (position ``r = q[0:3] + R p``, velocity ``q̇[0:3] + ω × R p``);
2. moves the lines over ``[t_k, t_k + Δt]`` with the fairleads at that velocity, in MoorDyn's RK2 steps of
   ``dtM`` (:meth:`~.lumped_dynamics.DynamicMooring.step`), and averages the fairlead forces over the steps;
3. holds, until the next sample, their load about the reference point (the moments with the arms at ``t_k``)
   less the quasi-static load the model computes itself, taken at the middle of the sample
   (``q_k + q̇_k Δt/2``): the model's own statics then follow the platform within the sample and the held part is
   only what the lines' motion adds; likewise the fairlead tensions (MoorDyn's ``FAIRTEN``).

Before the first sample the lines are relaxed as MoorDyn relaxes them, with the platform held at its initial
position (:meth:`~.lumped_dynamics.DynamicMooring.relax`). A turbine controller in the loop (a CasADi Function law
or a Python callable) is called at the same samples, its measurements and commands beside the lines' own.
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca
import numpy as np

from ...exceptions import SimulationOptionError
from ...simulate.controller import DiscreteController
from ._casadi import body_motion, euler_zyx
from .lumped_dynamics import Relaxed

__all__ = ["LinesInLoop", "with_moving_lines"]


class LinesInLoop:
    """The moving lines' law ``(t, xc, y) → (xc_next, u)`` (module docstring), with an optional inner controller.

    Parameters
    ----------
    platform : FloatingPlatform
        With ``moving_lines`` and ``mooring``.
    dofs : sequence of str or None
        Per platform DOF (surge … yaw) the model's state that holds it, or None when disabled.
    fixed : sequence of float
        The values of disabled DOFs [m, rad].
    q0 : array (6)
        The platform's initial position [m, rad] (the lines are relaxed there).
    dt : float
        Sample time [s].
    inner : DiscreteController or None
        The turbine's controller, called at the same samples.
    compile : bool
        Compile the lines' steps to C (default True).
    """

    def __init__(self, platform, dofs: Sequence[str | None], fixed: Sequence[float], q0, dt: float,
                 inner: DiscreteController | None = None, *, compile: bool = True) -> None:
        self.moving, self.mooring = platform.moving_lines, platform.mooring
        self.dofs, self.fixed = list(dofs), np.asarray(fixed, dtype=float)
        self.inner, self.dt = inner, float(dt)
        self.n_sub, self.h = self.moving.substeps(self.dt)
        self.step = self.moving.compiled_step(self.n_sub, compile)
        self.kinematics = _kinematics(self.mooring, compile)
        rf0 = np.asarray(self.kinematics(np.asarray(q0, dtype=float), np.zeros(6))[0], dtype=float)
        self.relaxed: Relaxed = self.moving.relax(rf0, compile=compile)
        self.x = self.relaxed.state.copy()
        self.n_inner_y = 0 if inner is None else len(inner.measurements)
        inner_y = () if inner is None else tuple(inner.measurements)
        self.extra = tuple(n for n in self.measurements if n not in inner_y)   # the lines' own beyond the inner's
        both = inner_y + self.extra
        self.y_index = np.array([both.index(n) for n in self.measurements], dtype=int)
        if inner is None or inner.is_function or callable(getattr(inner.law, "reset", None)):
            self.reset = self._reset       # repeatable (mbsym.simulate re-runs a loop only with reset()); a DISCON
            #                                library keeps hidden state: then neither is this law

    @property
    def measurements(self) -> tuple[str, ...]:
        """The model states the lines read: the enabled platform DOFs, then their rates."""
        enabled = [n for n in self.dofs if n is not None]
        return tuple(enabled) + tuple(f"{n}_d" for n in enabled)

    def platform_motion(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(q, q̇) of the six platform DOFs from the measured states ``y``."""
        q, qd = self.fixed.copy(), np.zeros(6)
        enabled = [k for k, n in enumerate(self.dofs) if n is not None]
        q[enabled] = y[:len(enabled)]
        qd[enabled] = y[len(enabled):2 * len(enabled)]
        return q, qd

    def lines_step(self, y: np.ndarray) -> np.ndarray:
        """Move the lines over one sample from the platform's state ``y``; the held inputs (load, tensions)."""
        q, qd = self.platform_motion(y)
        rf, vf, arms, _, _ = (np.asarray(v, dtype=float) for v in self.kinematics(q, qd))
        x, force, tension, _ = self.step(self.x, rf, vf, self.h, 1.0)
        self.x = np.asarray(x, dtype=float).ravel()
        force, tension = np.asarray(force, dtype=float), np.asarray(tension, dtype=float).ravel()
        load = np.concatenate([force.sum(axis=1), np.cross(arms.T, force.T).sum(axis=0)])
        _, _, _, static, t_static = (np.asarray(v, dtype=float) for v in self.kinematics(q + qd * self.dt / 2, qd))
        return np.concatenate([load - static.ravel(), tension - t_static.ravel()])

    def __call__(self, t: float, xc: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        y = np.asarray(y, dtype=float).ravel()
        u_lines = self.lines_step(y[self.y_index])
        if self.inner is None:
            return np.asarray(xc, dtype=float), u_lines
        y_inner = y[:self.n_inner_y]
        if self.inner.is_function:
            xc_next, u = (np.asarray(v, dtype=float).ravel() for v in self.inner.law(xc, y_inner))
        else:
            xc_next, u = self.inner.law(t, xc, y_inner)
        return np.asarray(xc_next, dtype=float).ravel(), np.concatenate([np.asarray(u, dtype=float).ravel(), u_lines])

    def _reset(self) -> None:
        """Back to the relaxed lines and the inner controller's initial state."""
        self.x = self.relaxed.state.copy()
        if self.inner is not None and not self.inner.is_function:
            self.inner.law.reset()


def _kinematics(mooring, compile: bool) -> ca.Function:
    """``(q, q̇) → (fairlead positions (3 × n), velocities (3 × n), arms R p (3 × n), quasi-static load (6),
    tensions (n))`` [m, m/s, m, N and N m, N]."""
    q, qd = ca.SX.sym("q", 6), ca.SX.sym("qd", 6)
    R = euler_zyx(q[3:6])
    body, _, _ = body_motion(q, qd)
    omega = body[3:6]
    arms = ca.horzcat(*[ca.mtimes(R, ca.DM(p)) for p in mooring.fairleads])
    rf = ca.repmat(q[0:3], 1, arms.shape[1]) + arms
    vf = ca.horzcat(*[qd[0:3] + ca.cross(omega, arms[:, k]) for k in range(arms.shape[1])])
    load, tension, _ = mooring.function()(q)
    f = ca.Function("fairlead_kinematics", [q, qd], [rf, vf, arms, load, tension])
    if not compile:
        return f
    from ...codegen import compile_function

    return compile_function(f).function


def _lines_function(platform, dofs: Sequence[str | None], fixed: Sequence[float], dt: float, measured: Sequence[str],
                    inner: DiscreteController | None) -> ca.Function:
    """The law ``(xc, y) → (xc_next, u)`` of the lines (and a CasADi ``inner`` law) as one CasADi Function: ``xc`` is
    the inner law's states then the lines'; ``y`` the measurements ``measured``; ``u`` the inner commands then the
    lines' inputs (the module docstring's steps 1-3)."""
    moving, mooring = platform.moving_lines, platform.mooring
    n_in = 0 if inner is None else inner.n_xc
    xc, y = ca.MX.sym("xc", n_in + moving.n_states), ca.MX.sym("y", len(measured))
    q, qd = [float(v) for v in fixed], [0.0] * 6
    for k, name in enumerate(dofs):
        if name is not None:
            q[k], qd[k] = y[measured.index(name)], y[measured.index(f"{name}_d")]
    q, qd = ca.vertcat(*q), ca.vertcat(*qd)
    kin = _kinematics(mooring, False)
    rf, vf, arms, _, _ = kin(q, qd)
    n, h = moving.substeps(dt)
    x1, force, tension, _ = moving.step(n)(xc[n_in:], rf, vf, h, 1.0)
    load = ca.vertcat(ca.sum2(force), sum(ca.cross(arms[:, k], force[:, k]) for k in range(moving.n_lines)))
    _, _, _, static, t_static = kin(q + qd * dt / 2, qd)
    u_lines = ca.vertcat(load - static, tension - t_static)
    if inner is None:
        return ca.Function("moving_lines_law", [xc, y], [x1, u_lines], ["xc", "y"], ["xc_next", "u"])
    xi, ui = inner.law(xc[:n_in], y[:len(inner.measurements)])
    return ca.Function(f"{inner.name}_with_moving_lines", [xc, y], [ca.vertcat(xi, x1), ca.vertcat(ui, u_lines)],
                       ["xc", "y"], ["xc_next", "u"])


def with_moving_lines(platform, dofs: Sequence[str | None], fixed: Sequence[float], q0, *,
                      controller: DiscreteController | None, dt: float | None, compile: bool = True
                      ) -> tuple[DiscreteController, Relaxed]:
    """A :class:`~mbsym.simulate.DiscreteController` that runs ``platform``'s moving lines and ``controller``.

    With a CasADi Function law (or none) the lines join it in one Function, their states hidden
    (``hidden_states``): the whole loop stays one generated, compiled loop. With a Python law (a DISCON library)
    :class:`LinesInLoop` calls both once per sample.

    Parameters
    ----------
    platform, dofs, fixed, q0, compile
        As :class:`LinesInLoop`.
    controller : DiscreteController or None
        The turbine's controller (its sample time is the lines' too), or None.
    dt : float or None
        The sample time without a controller [s] (the deck's ``DT``, OpenFAST's coupling step).

    Returns
    -------
    (DiscreteController, Relaxed)
        The combined controller (the inner one's recorded states, names and units; measurements and actuated inputs
        the inner one's, then the lines'), and the lines' initial relaxation.

    Raises
    ------
    SimulationOptionError
        Neither a controller nor a sample time.
    """
    if controller is None and dt is None:
        raise SimulationOptionError("moving mooring lines need a sample time: give a controller or dt (the deck's DT).")
    step = controller.dt if controller is not None else float(dt)
    inner_y = tuple(controller.measurements) if controller is not None else ()
    inner_u = tuple(controller.actuates) if controller is not None else ()
    names = None if controller is None else controller.state_names
    units = None if controller is None else controller.state_units
    name = controller.name if controller is not None else "lines"
    if controller is not None and not controller.is_function:
        law = LinesInLoop(platform, dofs, fixed, q0, step, controller, compile=compile)
        combined = DiscreteController(law, step, controller.x0, measurements=inner_y + law.extra,
                                      actuates=inner_u + tuple(platform.mooring_inputs), state_names=names,
                                      state_units=units, name=name)
        return combined, law.relaxed
    rf0 = np.asarray(_kinematics(platform.mooring, False)(np.asarray(q0, dtype=float), np.zeros(6))[0], dtype=float)
    relaxed = platform.moving_lines.relax(rf0, compile=compile)
    enabled = [n for n in dofs if n is not None]
    extra = tuple(n for n in tuple(enabled) + tuple(f"{n}_d" for n in enabled) if n not in inner_y)
    measured = inner_y + extra
    law_f = _lines_function(platform, dofs, fixed, step, measured, controller)
    x0 = relaxed.state if controller is None else np.concatenate([controller.x0, relaxed.state])
    combined = DiscreteController(law_f, step, x0, measurements=measured,
                                  actuates=inner_u + tuple(platform.mooring_inputs), state_names=names,
                                  state_units=units, name=name, hidden_states=relaxed.state.size)
    return combined, relaxed
