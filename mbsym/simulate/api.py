"""``simulate``: one call from a model to named time series."""

from __future__ import annotations

import time
import warnings
from typing import Any, Callable, Mapping, Sequence, Union

import numpy as np

from ..mass_properties import check_mass_matrix
from .base import Problem
from .checks import SimulationOptionWarning, check_step, check_t_out, check_tmax, check_tolerances, initial_state
from .inputs import input_signal
from .methods import get_method
from .model import resolve_model
from .result import SimulationResult, result_units

__all__ = ["simulate", "DEFAULT_OUTPUT_POINTS", "DEFAULT_RTOL", "DEFAULT_ATOL"]

#: Number of output times of adaptive methods when neither ``t_out`` nor ``dt`` is given.
DEFAULT_OUTPUT_POINTS = 200
#: Tolerances of adaptive methods when ``rtol``/``atol`` are not given [-], [state units].
DEFAULT_RTOL, DEFAULT_ATOL = 1e-6, 1e-8

InputValue = Union[float, Sequence[float], tuple, Callable[[float], float]]


def simulate(model: Any, tmax: float, x0: Sequence[float] | Mapping[str, float] | None = None,
             inputs: Mapping[str, InputValue] | Sequence[float] | None = None,
             p: Mapping[str, float] | None = None, *, method: str = "rk4", dt: float | None = None,
             rtol: float | None = None, atol: float | None = None, t_out: Sequence[float] | None = None,
             compile: bool = False) -> SimulationResult:
    """Integrate the equations of motion from t = 0 to ``tmax``.

    Parameters
    ----------
    model : EquationsOfMotion or SimulationModel
        The equations, or an object with an ``eom`` attribute and optional
        hooks ``default_state()``, ``default_parameters()``,
        ``output_function()`` (see :mod:`mbsym.simulate.model`).
    tmax : float
        End time [s].
    x0 : array (n_x) or dict, optional
        Initial state ``[q; qd]`` [m, rad; m/s, rad/s], in the order of
        ``eom.states``, or a dict by state name whose missing states keep the
        model's default (zero for an EquationsOfMotion). Default: the model's
        default state, else zeros.
    inputs : None, array (n_u), dict or callable, optional
        ``u(t)``: None (zero, or the model's default inputs), constants in
        order ``eom.inputs``, or a dict by input name (missing inputs take the
        model's default, else zero) of numbers, tables ``(grid,
        values)`` or values on a shared grid ``{"t": grid, "F": values}``
        (interpolated linearly, never extrapolated), or callables ``f(t)``
        [t in s]; or one callable ``f(t) -> n_u values`` for all inputs. See
        :mod:`mbsym.simulate.inputs`.
    p : dict, optional
        Parameter values by name; the model's defaults fill the gaps.
    method : str, optional
        A key of :data:`mbsym.simulate.METHODS`: fixed step ``"rk4"`` (the
        whole loop in CasADi), ``"newmark"``, ``"generalized-alpha"``
        (implicit, second-order form with the exact residual Jacobians);
        adaptive ``"adams"`` (explicit), ``"cvodes"``, ``"idas"`` (BDF),
        ``"scipy-radau"``, ``"scipy-bdf"`` (scipy, exact Jacobian; references).
    dt : float, optional
        Fixed-step methods: step [s] (default 0.01; shortened if needed so
        that a whole number of steps ends at ``tmax``). Adaptive methods: the
        output spacing when ``t_out`` is not given (given together with
        ``t_out``, it is ignored with a :class:`SimulationOptionWarning`).
    rtol, atol : float, optional
        Relative and absolute tolerances of adaptive methods (default 1e-6
        and 1e-8). Given to a fixed-step method, they are ignored with a
        :class:`SimulationOptionWarning`.
    t_out : array, optional
        Output times [s] in ``[0, tmax]``, strictly increasing. Default: every
        step (fixed step), every ``dt`` if given, else 200 points.

    Returns
    -------
    SimulationResult
        ``t``, ``x`` (with ``q``/``qd`` views and ``state(name)``), ``u``,
        ``y``/``output_names`` and ``statistics``.

    Warns
    -----
    SimulationOptionWarning
        An option given explicitly that the method does not use (``rtol`` or
        ``atol`` with a fixed-step method; ``dt`` with an adaptive method and
        ``t_out``).

    Raises
    ------
    IntegrationError
        If the solution diverges or is not finite (the message names the
        method, the step size, the time and the first non-finite state).
    DimensionError
        Wrong sizes, unknown state or input names, non-finite x0 or inputs.
    ParameterError
        Unknown parameters, or missing values without a default.
    SimulationOptionError
        Unknown method; non-positive tmax, dt or tolerances; bad t_out.
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
    >>> res = simulate(sys.equations(), 3.14159, x0=[1.0, 0.0])   # omega = 2 rad/s: one period
    >>> round(float(res.state("x")[-1]), 4)
    1.0
    """
    if not isinstance(compile, bool):
        raise TypeError(f"compile must be True or False; got {compile!r}.")
    resolved = resolve_model(model)
    eom = resolved.eom
    tmax = check_tmax(tmax)
    cls = get_method(method)
    _warn_ignored(cls, dt, rtol, atol, t_out)
    rtol, atol = check_tolerances(DEFAULT_RTOL if rtol is None else rtol, DEFAULT_ATOL if atol is None else atol)
    h, n_steps = None, None
    if cls.kind == "fixed-step":
        h, n_steps = check_step(cls.default_dt if dt is None else dt, tmax)
        grid = h * np.arange(n_steps + 1)
        grid[-1] = tmax
    elif dt is not None:
        step, n = check_step(dt, tmax)
        grid = step * np.arange(n + 1)
        grid[-1] = tmax
    else:
        grid = np.linspace(0.0, tmax, DEFAULT_OUTPUT_POINTS)
    times = grid if t_out is None else check_t_out(t_out, tmax)
    x_init = initial_state(x0, eom.states, resolved.default_x)
    params = dict(resolved.default_p)
    if p is not None and not isinstance(p, Mapping):
        eom.parameter_vector(p)          # raises ParameterError with the model's names
    params.update(p or {})
    p_vec = eom.parameter_vector(params)
    if resolved.default_u and (inputs is None or isinstance(inputs, Mapping)):
        inputs = {**resolved.default_u, **(inputs or {})}
    signal = input_signal(inputs, eom.inputs, tmax)
    check_mass_matrix(eom, x_init[: eom.n_q], signal.at(0.0), p_vec)   # M > 0 at x0 before integrating
    problem = Problem(eom, x_init, p_vec, signal, times, tmax, dt=h, n_steps=n_steps, rtol=rtol, atol=atol,
                      compile=compile)
    X, stats = cls(problem).solve()
    U = signal(times)
    t0 = time.perf_counter()
    Y = resolved.outputs(X, U, p_vec, compile=compile)
    stats["outputs_wall_s"] = time.perf_counter() - t0
    return SimulationResult(times, X, eom.states, U, eom.inputs, Y, resolved.output_names, stats,
                            result_units(model, eom, resolved.output_names))


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
