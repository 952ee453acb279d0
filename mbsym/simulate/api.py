"""``simulate``: one call from a model to named time series."""

from __future__ import annotations

import time
import warnings
from typing import Any, Callable, Mapping, Sequence, Union

import numpy as np

from ..equations import EquationsOfMotion
from ..exceptions import SimulationOptionError
from ..mass_properties import check_mass_matrix
from .base import Problem
from .checks import (SimulationOptionWarning, check_accuracy, check_step, check_t_out, check_tmax, check_tolerances,
                     initial_state)
from .inputs import input_signal
from .methods import get_method
from .model import Plant, plant_of
from .monitor import RunMonitor, SimulationInterrupted, check_resources, interruptible, output_count
from .result import SimulationResult

__all__ = ["simulate", "DEFAULT_OUTPUT_POINTS", "DEFAULT_RTOL", "DEFAULT_ATOL", "DEFAULT_OUTPUT_DT"]

#: Number of output times of adaptive methods when neither ``t_out`` nor ``dt`` is given.
DEFAULT_OUTPUT_POINTS = 200
#: Output spacing of the accuracy-driven default when ``t_out`` is not given [s] (the former default step).
DEFAULT_OUTPUT_DT = 0.01
#: Tolerances of adaptive methods when ``rtol``/``atol`` are not given [-], [state units].
DEFAULT_RTOL, DEFAULT_ATOL = 1e-6, 1e-8

InputValue = Union[float, Sequence[float], tuple, Callable[[float], float]]


def simulate(model: Any, tmax: float, x0: Sequence[float] | Mapping[str, float] | None = None,
             inputs: Mapping[str, InputValue] | Sequence[float] | None = None,
             p: Mapping[str, float] | None = None, *, method: str | None = None, dt: float | None = None,
             rtol: float | None = None, atol: float | None = None, t_out: Sequence[float] | None = None,
             accuracy: float | None = None, compile: bool | None = None, controller: Any = None,
             progress: Callable[[float, float], None] | None = None,
             held_dt: float | None = None, held_order: int = 0) -> SimulationResult:
    """Integrate the model from t = 0 to ``tmax``.

    Without ``method``, ``dt``, ``rtol`` and ``atol``, mbsym chooses the method, the step and
    whether to compile so that the error against the converged solution stays below
    ``accuracy`` at least cost (:mod:`mbsym.simulate.auto`: RK4 at the step the linearized
    spectrum allows, checked by step doubling; BDF for stiff models).

    Parameters
    ----------
    model : Dynamics, EquationsOfMotion or SimulationModel
        An :class:`mbsym.Dynamics` (first-order ``ẋ = f(x, u, p)``, outputs ``y = h(x, u, p)``),
        an object with a hook ``dynamics()``, the equations, or an object with an ``eom``
        attribute and optional hooks ``default_state()``, ``default_parameters()``,
        ``default_inputs()``, ``output_function()`` (see :mod:`mbsym.simulate.model`).
    tmax : float
        End time [s].
    x0 : array (n_x) or dict, optional
        Initial state (``[q; qd]`` [m, rad; m/s, rad/s] for equations of motion), in the
        order of the model's states, or a dict by state name whose missing states keep the
        model's default. Default: the model's default state, else zeros.
    inputs : None, array (n_u), dict or callable, optional
        ``u(t)``: None (the model's default inputs, else zero), constants in the order of the
        model's inputs, or a dict by input name (missing inputs take the model's default,
        else zero) of numbers, tables ``(grid, values)`` or values on a shared grid ``{"t":
        grid, "F": values}`` (interpolated linearly, never extrapolated), or callables
        ``f(t)`` [t in s]; or one callable ``f(t) -> n_u values`` for all inputs. See
        :mod:`mbsym.simulate.inputs`.
    p : dict, optional
        Parameter values by name; the model's defaults fill the gaps.
    method : str, optional
        A key of :data:`mbsym.simulate.METHODS`: fixed step ``"rk4"`` (the whole loop in
        CasADi), ``"newmark"``, ``"generalized-alpha"`` (implicit, second-order form with the
        exact residual Jacobians; equations of motion only); adaptive ``"adams"``
        (explicit), ``"cvodes"``, ``"idas"`` (BDF), ``"scipy-radau"``, ``"scipy-bdf"``
        (scipy, exact Jacobian; references); for a model with a held part (:mod:`mbsym.held`)
        ``"rk4-held"``, and in a loop with a CasADi ``controller`` ElastoDyn's multistep methods
        ``"abm4-held"`` and ``"ab4-held"`` (:mod:`mbsym.simulate.held_multistep`). Given, it is used
        exactly as asked. Not given:
        ``"rk4"`` if ``dt`` is given, ``"cvodes"`` if ``rtol`` or ``atol`` is, else the
        accuracy-driven choice.
    dt : float, optional
        Fixed-step methods: step [s] (default 0.01; shortened if needed so that a whole
        number of steps ends at ``tmax``). Adaptive methods: the output spacing when
        ``t_out`` is not given (given together with ``t_out``, it is ignored with a
        :class:`SimulationOptionWarning`). The accuracy-driven default decouples the two: give
        the output times by ``t_out`` (``mbsym simulate --dt`` does that).
    rtol, atol : float, optional
        Relative (``1e-14 <= rtol < 1``) and absolute tolerances of adaptive methods (default
        1e-6 and 1e-8). Given to a fixed-step method, they are ignored with a
        :class:`SimulationOptionWarning`.
    t_out : array, optional
        Output times [s] in ``[0, tmax]``, strictly increasing. Default: every step (fixed
        step), every ``dt`` if given (adaptive), every :data:`DEFAULT_OUTPUT_DT` = 0.01 s
        (accuracy-driven), else 200 points.
    accuracy : float, optional
        Error bound ``ε = max over states of mean|x - x_ref| / range(x_ref)`` against the
        converged solution, for the accuracy-driven default (``1e-10 <= accuracy <= 0.5``;
        default 1e-3). ``statistics["error_estimate"]`` reports the a-posteriori estimate.
        Not combinable with ``method``, ``dt``, ``rtol`` or ``atol``.
    compile : bool, optional
        True: the integration runs as generated C (:mod:`mbsym.codegen`; compiled once, cached
        on disk). False: CasADi's virtual machine. None (default): the accuracy-driven default
        compiles when the library is cached or compiling pays off; explicit methods do not.
    controller : DiscreteController, optional
        A discrete controller in the loop (:class:`mbsym.simulate.DiscreteController`):
        sampled every ``controller.dt`` with zero-order hold on the inputs it actuates; its
        states are appended to the outputs. Runs with RK4 sub-steps (``method`` unset or
        ``"rk4"``), ``"rk4-held"`` steps, or one ``"abm4-held"``/``"ab4-held"`` step per sample.
    held_dt : float, optional
        With a held method (``"rk4-held"``, ``"abm4-held"``, ``"ab4-held"``) and a ``controller``: the
        interval [s] at which the plant's held part
        (:class:`mbsym.held.HeldPart`, e.g. blade-element aerodynamics) is evaluated again, a whole multiple
        of the controller's sample time; between evaluations it is held while the states advance sample by
        sample and the controller runs at its own rate (samples that return outputs evaluate it afresh).
        Default: every sample.
    held_order : {0, 1, 2}, optional
        With a held method and a ``controller``: between its evaluations the held part is held (0,
        the default) or extrapolated in time through the last 2 (1, linear) or 3 (2, quadratic) evaluations
        at every RK4 stage, as OpenFAST's glue code extrapolates module outputs (``InterpOrder``)
        (:mod:`mbsym.simulate.held_carry`).
    progress : callable ``(t, tmax) -> None``, optional
        Called as the integration advances (long runs are integrated in chunks of ~0.2 s of
        wall time), e.g. :class:`mbsym.simulate.monitor.ProgressPrinter`.

    Returns
    -------
    SimulationResult
        ``t``, ``x`` (with ``q``/``qd`` views and ``state(name)``), ``u``, ``y`` /
        ``output_names`` / ``output_units`` and ``statistics``.

    Warns
    -----
    SimulationOptionWarning
        An option given explicitly that the method does not use (``rtol`` or ``atol`` with a
        fixed-step method; ``dt`` with an adaptive method and ``t_out``).

    Raises
    ------
    IntegrationError
        If the solution diverges or is not finite (the message names the method, the step
        size, the time and the first non-finite state).
    DimensionError
        Wrong sizes, unknown state or input names, non-finite x0 or inputs.
    ParameterError
        Unknown parameters, or missing values without a default.
    SimulationOptionError
        Unknown method; non-positive tmax, dt or tolerances; bad t_out or accuracy; a result
        or a number of steps beyond the limits of :mod:`mbsym.simulate.monitor`; a second-order
        method on first-order dynamics.
    SimulationInterrupted
        Ctrl-C (a ``KeyboardInterrupt``): "interrupted at t = ... s", with the partial result. Ctrl-C
        needs SIGINT to reach Python; when SIGINT is ignored (a process started in the background by a
        script, ``nohup``), SIGTERM (``kill PID``) during the run does the same (see
        :func:`mbsym.simulate.monitor.interruptible`).
    TypeError
        Unknown keyword arguments, a model of the wrong type.

    Examples
    --------
    >>> import mbsym as mb
    >>> from mbsym.simulate import simulate
    >>> sys = mb.System()
    >>> x = sys.coordinates("x")
    >>> sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("m", 1.0), axis=[1, 0, 0], coordinate=x))
    >>> sys.add_spring(x, 4.0)
    >>> eom = sys.equations()
    >>> res = simulate(eom, 3.14159, x0=[1.0, 0.0])                 # omega = 2 rad/s: one period
    >>> round(float(res.state("x")[-1]), 2), res.statistics["error_estimate"] < 1e-3
    (1.0, True)
    >>> tight = simulate(eom, 3.14159, x0=[1.0, 0.0], accuracy=1e-8)
    >>> round(float(tight.state("x")[-1]), 6)
    1.0
    >>> round(float(simulate(eom, 3.14159, x0=[1.0, 0.0], method="rk4", dt=0.01).state("x")[-1]), 6)
    1.0
    """
    if compile is not None and not isinstance(compile, bool):
        raise TypeError(f"compile must be True, False or None; got {compile!r}.")
    plant = plant_of(model)
    tmax = check_tmax(tmax)
    auto = method is None and dt is None and rtol is None and atol is None
    if accuracy is not None and not auto:
        given = ", ".join(f"{k}={v!r}" for k, v in (("method", method), ("dt", dt), ("rtol", rtol), ("atol", atol))
                          if v is not None)
        raise SimulationOptionError(f"accuracy={accuracy!r} chooses the method and step itself; it cannot be "
                                    f"combined with {given}. Give either accuracy (output times by t_out) or the "
                                    "method and its step or tolerances.")
    if auto:
        from .auto import DEFAULT_ACCURACY

        accuracy = check_accuracy(DEFAULT_ACCURACY if accuracy is None else accuracy)
    elif method is None:
        method = "rk4" if dt is not None or (rtol is None and atol is None) else "cvodes"
    cls = None if auto else get_method(method)
    if cls is not None:
        _warn_ignored(cls, dt, rtol, atol, t_out)
    rtol, atol = check_tolerances(DEFAULT_RTOL if rtol is None else rtol, DEFAULT_ATOL if atol is None else atol)
    x_init = initial_state(x0, plant.states, plant.default_x)
    p_vec = plant.parameter_vector(p)
    if plant.default_u and (inputs is None or isinstance(inputs, Mapping)):
        inputs = {**plant.default_u, **(inputs or {})}
    signal = input_signal(inputs, plant.inputs, tmax)
    if plant.eom is not None:                        # M > 0 at x0 before integrating
        check_mass_matrix(plant.eom, x_init[: plant.eom.n_q], signal.at(0.0), p_vec)
    ctrl = None
    if controller is not None:
        from .controller import bind_controller

        ctrl = bind_controller(controller, plant, method, dt, tmax, held_dt=held_dt, held_order=held_order)
    elif held_dt is not None or held_order != 0:
        raise SimulationOptionError("held_dt and held_order set how a controlled loop re-evaluates the plant's held "
                                    "part: each needs controller= and method='rk4-held' (without a controller, "
                                    "choose dt).")
    h, n_steps, times = _grid(cls, tmax, dt, t_out, auto, plant, ctrl)
    monitor = RunMonitor(tmax, progress) if progress is not None else None
    try:
        with interruptible():                        # SIGTERM too when SIGINT is ignored
            if ctrl is not None:
                from .closed_loop import run_closed_loop

                X, stats, extra = run_closed_loop(ctrl, plant, x_init, p_vec, signal, times, tmax, accuracy=accuracy,
                                                  dt=h, compile=compile, monitor=monitor)
            elif auto:
                from .auto import run_auto

                X, stats = run_auto(plant, x_init, p_vec, signal, times, tmax, accuracy, compile, monitor)
                extra = None
            else:
                if n_steps is not None:
                    check_resources(times.size, 1, n_steps, tmax)
                problem = Problem(plant, x_init, p_vec, signal, times, tmax, dt=h, n_steps=n_steps, rtol=rtol,
                                  atol=atol, compile=bool(compile), monitor=monitor)
                X, stats = cls(problem).solve()
                extra = None
    except SimulationInterrupted as exc:
        raise SimulationInterrupted(exc.t, _partial(exc.partial, plant, signal, p_vec)) from None
    except KeyboardInterrupt:                       # before or between the integrations (compiling, preparing)
        raise SimulationInterrupted(0.0 if monitor is None else monitor.t) from None
    if monitor is not None:
        monitor.update(tmax)
    U = signal(times) if extra is None else extra.u
    t0 = time.perf_counter()
    Y = _outputs(plant, X, U, p_vec, compile if auto else bool(compile), extra)
    stats["outputs_wall_s"] = time.perf_counter() - t0
    names, units = plant.output_names, plant.output_units
    if extra is not None:
        Y = np.hstack([Y, extra.y])
        names, units = names + extra.names, units + extra.units
    return SimulationResult(times, X, plant.states, U, plant.inputs, Y, names, stats, units, plant.n_q,
                            _state_units(model, plant), _known(plant.inputs, plant.input_units), _owned=True)


def _outputs(plant: Plant, X: np.ndarray, U: np.ndarray, p: np.ndarray, compile, extra) -> np.ndarray:
    """The plant's outputs at the rows of X: those the closed loop evaluated, the others here."""
    Y = None if extra is None else extra.plant_y
    if Y is None:
        return plant.outputs(X, U, p, compile=compile)
    missing = np.flatnonzero(np.isnan(Y).any(axis=1))
    if missing.size > 64:
        Y[missing] = plant.outputs(X[missing], U[missing], p, compile=compile)
    else:                     # a few rows (the end time): direct calls rather than a mapped or compiled Function
        for i in missing:
            out = plant.output_function(X[i], U[i], p)
            Y[i] = np.concatenate([np.asarray(v, dtype=float).reshape(-1) for v in
                                   (out if isinstance(out, (list, tuple)) else [out])])
    return Y


def _state_units(model, plant) -> dict[str, str]:
    """Units of the states: the plant's (:attr:`mbsym.Dynamics.state_units`), else the structural ones
    (``EquationsOfMotion.units``) of a model with equations."""
    eom = model if isinstance(model, EquationsOfMotion) else getattr(model, "eom", None)
    units = dict(eom.units) if isinstance(eom, EquationsOfMotion) else {}
    units.update(_known(plant.states, plant.state_units))
    return units


def _known(names, units) -> dict[str, str]:
    return {n: u for n, u in zip(names, units) if u}


def _grid(cls, tmax: float, dt, t_out, auto: bool, plant: Plant, ctrl) -> tuple:
    """``(step, n_steps, output times)``, checking the result's size before any array is allocated."""
    columns = 1 + plant.n_x + plant.n_u + len(plant.output_names) + (0 if ctrl is None else ctrl.n_columns)
    h, n_steps = None, None
    if cls is not None and cls.kind == "fixed-step":
        h, n_steps = check_step(cls.default_dt if dt is None else dt, tmax)
    if t_out is not None:
        times = check_t_out(t_out, tmax)
        check_resources(times.size, columns, None, tmax)
        return h, n_steps, times
    if auto:
        spacing = DEFAULT_OUTPUT_DT if ctrl is None or dt is None else dt
    elif cls.kind == "fixed-step":
        spacing = h
    elif dt is not None:
        spacing = dt
    else:
        return h, n_steps, np.linspace(0.0, tmax, DEFAULT_OUTPUT_POINTS)
    check_resources(output_count(tmax, spacing), columns, None, tmax)
    step, n = check_step(spacing, tmax)
    grid = step * np.arange(n + 1)
    grid[-1] = tmax
    return h, n_steps, grid


def _partial(partial, plant: Plant, signal, p_vec):
    """A SimulationResult of the outputs computed before an interruption (or what the method gave)."""
    if not (isinstance(partial, tuple) and len(partial) == 2):
        return partial
    t, X = partial
    if len(t) == 0:
        return None
    U = signal(t)
    try:
        Y = plant.outputs(X, U, p_vec)
    except Exception:  # noqa: BLE001 - a partial result must not hide the interruption
        Y = np.zeros((len(t), len(plant.output_names)))
    return SimulationResult(t, X, plant.states, U, plant.inputs, Y, plant.output_names,
                            {"success": False, "message": "interrupted"}, plant.output_units, plant.n_q,
                            _known(plant.states, plant.state_units), _known(plant.inputs, plant.input_units))


def _warn_ignored(cls, dt, rtol, atol, t_out) -> None:
    """Warn about options given explicitly that the method ``cls`` does not use."""
    if cls.kind == "fixed-step":
        given = [f"{name} = {value!r}" for name, value in (("rtol", rtol), ("atol", atol)) if value is not None]
        if given:
            warnings.warn(f"{' and '.join(given)} ignored: method {cls.name!r} has a fixed step (set dt); "
                          "tolerances apply to adaptive methods only.", SimulationOptionWarning, stacklevel=3)
    elif dt is not None and t_out is not None:
        warnings.warn(f"dt = {dt!r} ignored: method {cls.name!r} is adaptive (its step follows rtol and atol) and "
                      "t_out gives the output times; dt only spaces the outputs when t_out is not given.",
                      SimulationOptionWarning, stacklevel=3)
