"""Closed-loop simulation of an operating turbine with a :class:`~.loop.TurbineLoop` (NMPC, estimator).

:func:`simulate_with_loop` is :func:`mbsym.wind.operation.simulate_turbine` for a loop written in
Python: one RK4 step of the full plant per controller sample, only the loop's measurements evaluated
inside the loop, every OpenFAST channel afterwards from the states, and — with an estimator — the
channels of the prediction model at the estimate as ``<channel>_est`` (:data:`ESTIMATED_CHANNELS`,
same units), the estimate being held between estimator samples.
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any, Callable, Mapping

import casadi as ca
import numpy as np

from ...dynamics import Dynamics

__all__ = ["simulate_with_loop", "ESTIMATED_CHANNELS", "measurement_dynamics"]

#: Channels reported as ``<channel>_est`` with an estimator.
ESTIMATED_CHANNELS = ("Wind1VelX", "RtVAvgxh", "RotSpeed", "GenSpeed", "TTDspFA", "QD_TFA1", "RtAeroFxh",
                      "RtAeroMxh", "TwrBsMyt")


def measurement_dynamics(model, names) -> Dynamics:
    """The plant's dynamics with only the channels ``names`` as outputs (cheap inside the loop)."""
    key = ("loop_measurements", tuple(names))
    cache = model._parts
    if key not in cache:
        d = model.dynamics()
        S = ca.SX if d.outputs.is_a("SXFunction") else ca.MX
        x, u, p = S.sym("x", d.n_x), S.sym("u", d.n_u), S.sym("p", d.n_p)
        y = d.outputs(x, u, p)
        rows = [n for n in names if n in d.output_names]
        h = ca.Function(f"{d.name}_loop_measurements", [x, u, p], [ca.vertcat(*[y[d.output_names.index(n)]
                                                                                   for n in rows])],
                        ["x", "u", "p"], ["y"], {"cse": True} if S is ca.SX else {})
        units = [d.output_units[d.output_names.index(n)] for n in rows]
        cache[key] = Dynamics(d.rhs, states=d.states, inputs=d.inputs, parameters=d.parameters,
                              defaults=dict(d.defaults), outputs=h, output_names=rows, output_units=units, x0=d.x0,
                              u0=d.u0, name=f"{d.name}_loop", eom=d.eom, state_units=d.state_units,
                              input_units=d.input_units)
    return cache[key]


def simulate_with_loop(model, wind: Callable[[Any], Any], tmax: float, loop, *, x0=None, t_out=None,
                       p: Mapping[str, float] | None = None, compile: bool | None = None, progress=None):
    """Simulate ``model`` in ``wind`` with ``loop`` (a :class:`~.loop.TurbineLoop`) for ``tmax`` seconds.

    Parameters
    ----------
    model : OperatingTurbine
        Rotor-effective, or blade-element (then run by
        :func:`~mbsym.wind.operation.simulation.simulate_turbine` with the loop's law as a Python
        controller, ``rk4-held`` at the loop's sample time; the loop needs an estimator).
    wind : WindSignal or callable
        Hub-height wind [m/s] of time [s]; for a blade-element model what
        :func:`~mbsym.wind.operation.simulation.simulate_turbine` takes (None for a model that carries
        its full field).
    tmax : float
        [s].
    loop : TurbineLoop
    x0 : array, optional, keyword-only
        Initial plant state (default ``model.initial_state(wind(0))``).
    t_out : array, optional, keyword-only
        Output times [s].
    p : dict, optional, keyword-only
        Plant parameters by name.
    compile : bool, optional, keyword-only
        Compile the plant step (default: as :func:`~mbsym.wind.operation.simulation.simulate_turbine` decides, from
        the run's samples and the plant's cost in CasADi's virtual machine).
    progress : optional
        As in :func:`mbsym.simulate`.

    Returns
    -------
    SimulationResult
        Outputs: every channel of the plant, the ``<channel>_est`` channels (with an estimator),
        then the loop's states (``est.<name>``, baseline states).
    """
    from ...simulate.api import simulate
    from ..operation.controllers import held_commands
    from ..operation.model import OperatingTurbine
    from ..operation.simulation import _compile_pays_off
    from .loop import TurbineLoop

    if not isinstance(model, OperatingTurbine):
        raise TypeError(f"model must be an OperatingTurbine; got {type(model).__name__}.")
    if not isinstance(loop, TurbineLoop):
        raise TypeError(f"loop must be a TurbineLoop; got {type(loop).__name__}.")
    from ...codegen_async import wait_for_compilations

    wait_for_compilations()           # the solvers' libraries (compiled in the background): not inside a step's time
    dyn = model.dynamics()
    t0 = time.perf_counter()
    if model.aero == "blade":        # its wind inputs, held aerodynamics and every channel: simulate_turbine's loop
        from ..operation.simulation import simulate_turbine

        res = simulate_turbine(model, wind, tmax, controller=loop.controller(), x0=x0, t_out=t_out, p=p,
                               compile=compile, progress=progress)
        t0 = time.perf_counter()
        n_meas = len(dyn.output_names)
        X, Y = np.asarray(res.x), np.asarray(res.y)[:, :n_meas]
    else:
        u0 = float(np.asarray(wind(0.0), dtype=float).reshape(-1)[0])
        x0 = dyn.state_vector(model.initial_state(u0) if x0 is None else x0)
        if compile is None:
            compile = _compile_pays_off(dyn, tmax / loop.dt, x0, p)
        meas = measurement_dynamics(model, loop.measurements)
        inputs: dict[str, Any] = {"Wind1VelX": wind, **held_commands(model, x0)}
        if model.platform is not None:              # the deck's sea (HydroDyn's excitation series), as simulate_turbine
            inputs.update(model.platform.sea_tables(tmax))
        if getattr(model, "structural_controls", None) is not None:    # ServoDyn's prescribed StC loads
            inputs.update(model.structural_controls.tables(tmax))
        controller = loop.controller()
        if model.platform is not None and getattr(model.platform, "moving_lines", None) is not None:
            from ..operation.simulation import moving_lines_controller      # MoorDyn's lines beside the plant

            controller = moving_lines_controller(model, dyn, controller, x0, compile)
        res = simulate(meas, tmax, x0=x0, inputs=inputs, controller=controller, method="rk4", dt=loop.dt,
                       t_out=t_out, p=p, compile=compile, progress=progress)
        t0 = time.perf_counter()
        from ...simulate.model import evaluate_outputs

        X, U = np.asarray(res.x), np.asarray(res.u)
        Y = evaluate_outputs(dyn.rhs, dyn.outputs, X, U, dyn.parameter_vector(p), compile)
        n_meas = len(meas.output_names)
    extra = np.asarray(res.y)[:, n_meas:]
    names, units = list(dyn.output_names), list(dyn.output_units)
    blocks = [Y]
    if loop.estimator is not None:
        E, e_names, e_units = _estimated_channels(loop, res, X, dyn)
        blocks.append(E)
        names += e_names
        units += e_units
    stats = dict(res.statistics)
    stats["outputs_wall_s"] = float(stats.get("outputs_wall_s", 0.0)) + time.perf_counter() - t0
    stats.update(loop.statistics())
    from .loop import warn_failures

    warn_failures(stats)                     # a fallback is a warning in every run, not a --stats key only
    from ..operation.sanity import check_physical

    result = dataclasses.replace(res, y=np.hstack(blocks + [extra]), output_names=tuple(names) +
                                 tuple(res.output_names[n_meas:]), output_units=tuple(units) +
                                 tuple(res.output_units[n_meas:] if res.output_units else ("",) * extra.shape[1]),
                                 statistics=stats)
    check_physical(result, model)            # stops a run gone unphysical (time, channel): UnphysicalRunError
    _warn_deadline(loop)
    return result


def _warn_deadline(loop) -> None:
    """A :class:`~mbsym.exceptions.DeadlineWarning` when the NMPC missed its deadline."""
    if loop.nmpc is None or not loop.nmpc.nmpc.deadline_misses:
        return
    import warnings

    from ...exceptions import DeadlineWarning

    s = loop.nmpc.summary()
    warnings.warn(f"the NMPC missed its {s['deadline_s'] * 1e3:.3g} ms deadline at {s['deadline_misses']} of "
                  f"{s['steps']} steps (worst step {s['step_max_s'] * 1e3:.3g} ms); each applied the previous plan's "
                  "next rates instead of its own. A larger deadline, a shorter horizon or a less loaded "
                  "machine avoids it.", DeadlineWarning, stacklevel=3)


def _estimated_channels(loop, res, X: np.ndarray, dyn) -> tuple[np.ndarray, list[str], list[str]]:
    """``<channel>_est``: the estimation model's channels at the estimate and the measured pitch, torque."""
    est = loop.estimator
    cols = [list(res.output_names).index(f"est.{n}") for n in est.names]
    Z = np.asarray(res.y)[:, cols]
    blades = [dyn.states.index(n) for n in getattr(loop.plant, "pitch_names", ("BlPitch",))]
    pitch, torque = X[:, blades].mean(axis=1), X[:, dyn.states.index("GenTq")]    # a blade-pitched plant: mean
    m = est.dynamics
    n = m.n_x
    U = np.column_stack([Z[:, -1], pitch, torque, Z[:, n:-1]])          # wind, measured actuators, wave loads
    f = m.outputs.map(Z.shape[0])
    Y = np.asarray(f(Z[:, :n].T, U.T, est.p_vector)).T
    chosen = [c for c in ESTIMATED_CHANNELS if c in m.output_names]
    idx = [m.output_names.index(c) for c in chosen]
    return Y[:, idx], [f"{c}_est" for c in chosen], [m.output_units[i] for i in idx]
