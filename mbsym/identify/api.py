"""``mbsym.identify``: least-squares fit of model parameters to measured time series.

The model is anything :func:`mbsym.as_dynamics` accepts; the fit is multiple
shooting on the measurement grid solved by Gauss–Newton with exact Jacobians
(:mod:`mbsym.identify.gauss_newton`; ``method="sqpmethod"`` or ``"ipopt"`` solve the
same problem with CasADi's NLP solvers), integrating every sample interval with RK4
(:mod:`mbsym.identify.shooting`: sub-steps chosen for accuracy). Statistics at the
optimum: :mod:`mbsym.identify.result`.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from ..dynamics import Dynamics, as_dynamics
from ..exceptions import (ConvergenceWarning, DataError, DimensionError, IdentifiabilityWarning,
                          IdentificationOptionError, ParameterError)
from .data import Record, as_records, check_channels
from .gauss_newton import ADVICE, ShootingRecord, check_finite, gauss_newton
from .result import IdentificationResult, correlation_of, covariance, fit_error, warn_identifiability
from .shooting import ShootingFunctions, choose_substeps, shooting_functions

__all__ = ["Parameter", "identify", "METHODS"]

#: Solvers of :func:`identify`.
METHODS = ("gauss-newton", "sqpmethod", "ipopt")


@dataclass(frozen=True)
class Parameter:
    """A parameter to estimate, as reported to the user.

    Attributes
    ----------
    name : str
        The model's parameter name (``Dynamics.parameters``).
    label : str, optional
        How it is reported (default ``name``), e.g. an ElastoDyn key ``"TwrFADmp(1)"``.
    factor : float
        ``label value = factor * model value`` (e.g. 100 for a ratio reported in %).
    unit : str
        Unit of the label value.
    lower, upper : float
        Bounds in label units (default unbounded).
    """

    name: str
    label: str | None = None
    factor: float = 1.0
    unit: str = ""
    lower: float = -math.inf
    upper: float = math.inf

    @property
    def key(self) -> str:
        return self.label if self.label is not None else self.name


def _resolve_parameters(model: Any, dyn: Dynamics, parameters) -> list[Parameter]:
    items = [parameters] if isinstance(parameters, (str, Parameter)) else list(parameters or [])
    if not items:
        raise ParameterError("no parameter to identify; pass names such as ['nacelle_mass'] or deck keys.")
    hook = getattr(model, "resolve_parameter", None)
    out = []
    for it in items:
        if isinstance(it, Parameter):
            spec = it
        elif not isinstance(it, str):
            raise ParameterError(f"parameters must be names (str) or mbsym.identify.Parameter; got {it!r}.")
        elif it in dyn.parameters:
            spec = Parameter(it)
        elif callable(hook):
            e = hook(it)                      # raises ParameterError for unknown or absent keys
            spec = Parameter(e.name, it, float(e.factor), e.unit, getattr(e, "lower", -math.inf))
        else:
            raise ParameterError(f"unknown parameter {it!r}; the model's parameters are {list(dyn.parameters)}.")
        if spec.name not in dyn.parameters:
            raise ParameterError(f"{spec.key!r}: {spec.name!r} is not a parameter of the model; its parameters are "
                                 f"{list(dyn.parameters)}.")
        if not (math.isfinite(spec.factor) and spec.factor != 0):
            raise ParameterError(f"{spec.key!r}: factor must be a finite nonzero number; got {spec.factor}.")
        out.append(spec)
    names = [s.name for s in out]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ParameterError(f"parameters {dup} are requested more than once (by name or by key).")
    return out


def _channel_rows(dyn: Dynamics, records: list[Record], channels) -> tuple[list[tuple[str, int]], list[str]]:
    if channels is None:
        names = [n for n in (*dyn.output_names, *dyn.states) if all(n in r.names for r in records)]
        names = list(dict.fromkeys(names))
        if not names:
            raise DataError(f"no data channel matches the model: data channels {list(records[0].names)}, model "
                            f"outputs {list(dyn.output_names)} and states {list(dyn.states)}. Pass channels=[...].")
    else:
        names = [channels] if isinstance(channels, str) else [str(c) for c in channels]
        if not names or len(set(names)) != len(names):
            raise DataError(f"channels must be a non-empty list without repeats; got {names}.")
    rows = []
    for n in names:
        if n in dyn.output_names:
            rows.append(("y", dyn.output_names.index(n)))
        elif n in dyn.states:
            rows.append(("x", dyn.states.index(n)))
        else:
            raise DataError(f"channel {n!r} is neither an output nor a state of the model; outputs are "
                            f"{list(dyn.output_names)}, states {list(dyn.states)}.")
    return rows, names


def _per_channel(option, names: list[str], what: str, default: float) -> np.ndarray:
    values = np.full(len(names), default, dtype=float)
    if option is None:
        return values
    if not isinstance(option, Mapping):
        raise IdentificationOptionError(f"{what} must be a dict {{channel: value}}; got {type(option).__name__}.")
    unknown = sorted(set(option) - set(names))
    if unknown:
        raise IdentificationOptionError(f"{what} name channels {unknown} that are not fitted; fitted channels are "
                                        f"{names}.")
    for k, v in option.items():
        try:
            v = float(v)
        except (TypeError, ValueError):
            raise IdentificationOptionError(f"{what}[{k!r}] must be a number; got {v!r}.") from None
        if not (math.isfinite(v) and v >= 0):
            raise IdentificationOptionError(f"{what}[{k!r}] must be finite and >= 0; got {v}.")
        values[names.index(k)] = v
    return values


def _default_weights(Ys: list[np.ndarray]) -> np.ndarray:
    Y = np.vstack(Ys)
    rng = np.ptp(Y, axis=0)
    big = np.max(np.abs(Y), axis=0)
    scale = np.where(rng > 0, rng, np.where(big > 0, big, 1.0))
    return 1.0 / scale


def _per_record(value, n: int, what: str) -> list:
    """One value per record: a list of arrays/dicts (one per record), or one value shared by all."""
    per = isinstance(value, list) and len(value) > 0 and all(
        isinstance(v, (Mapping, list, tuple, np.ndarray)) or v is None for v in value)
    if n == 1:                              # a nested list may be one record's table (inputs (N, n_u))
        return value if per and len(value) == 1 else [value]
    if per:
        if len(value) != n:
            raise DimensionError(f"{what} is a list of {len(value)} entries; expected one per record ({n}).")
        return value
    return [value] * n


def _inputs(model: Any, dyn: Dynamics, value, t: np.ndarray) -> np.ndarray:
    """Inputs (N, n_u) at the sample times: an array, a dict by name, or the model's defaults."""
    if value is not None and not isinstance(value, Mapping):
        try:
            U = np.asarray(value, dtype=float).reshape(t.size, dyn.n_u)
        except (TypeError, ValueError):
            raise DimensionError(f"inputs must be an array ({t.size}, {dyn.n_u}) in order {list(dyn.inputs)} or a "
                                 f"dict by name; got {type(value).__name__} of size "
                                 f"{np.size(value) if np.ndim(value) else 'scalar'}.") from None
    else:
        hook = getattr(model, "default_inputs", None)
        spec = dict(hook()) if callable(hook) and value is None else {}
        if isinstance(value, Mapping):
            unknown = sorted(set(value) - set(dyn.inputs))
            if unknown:
                raise DimensionError(f"inputs name unknown inputs {unknown}; inputs are {list(dyn.inputs)}.")
            spec = dict(value)
        U = np.tile(dyn.u0, (t.size, 1))
        for i, name in enumerate(dyn.inputs):
            v = spec.get(name)
            if v is None:
                continue
            if callable(v):
                U[:, i] = [float(v(float(s))) for s in t]
            else:
                a = np.asarray(v, dtype=float).reshape(-1)
                if a.size not in (1, t.size):
                    raise DimensionError(f"input {name!r} has {a.size} values; expected 1 or {t.size}.")
                U[:, i] = a
    if not np.all(np.isfinite(U)):
        raise DataError("inputs must be finite at every sample time.")
    return U


def _record_inputs(model: Any, dyn: Dynamics, inputs, records: list[Record]) -> list[np.ndarray]:
    """Inputs per record: given, else read off the record by the model (``inputs_from(record)``, e.g. an operating
    turbine's measured wind, pitch and torque), else the model's defaults. A model given as an object (not a
    Dynamics) with inputs and neither hook nor ``inputs=`` is refused: its zero default inputs would be silent
    nonsense (an operating turbine in still air with zero pitch and torque)."""
    hook = getattr(model, "inputs_from", None)
    if inputs is None and callable(hook):
        return [np.asarray(hook(r), dtype=float).reshape(r.time.size, dyn.n_u) for r in records]
    if (inputs is None and dyn.n_u > 0 and not isinstance(model, Dynamics)
            and not callable(getattr(model, "default_inputs", None))):
        raise IdentificationOptionError(
            f"the model has inputs {list(dyn.inputs)} and no default values for them: pass inputs= (an array "
            f"(N, {dyn.n_u}) or a dict by name). For an operating turbine, identify "
            "mbsym.wind.operation.MeasuredInputTurbine(turbine) instead: it reads the measured wind, pitch and "
            "torque off the record.")
    return [_inputs(model, dyn, v, r.time) for v, r in zip(_per_record(inputs, len(records), "inputs"), records)]


def _record_states(model: Any, dyn: Dynamics, x0, records: list[Record], Us: list[np.ndarray]) -> list[np.ndarray]:
    """Initial state per record: given, else the model's ``initial_state_from(record, u0)`` (e.g. a trim at the
    record's first inputs), else the model's default."""
    hook = getattr(model, "initial_state_from", None)
    if x0 is None and callable(hook):
        return [dyn.state_vector(hook(r, U[0])) for r, U in zip(records, Us)]
    return [dyn.state_vector(v) for v in _per_record(x0, len(records), "x0")]


def _free_initial(model: Any, dyn: Dynamics, estimate_x0) -> np.ndarray:
    """Indices of the estimated initial states; ``True``: all but the model's ``fixed_states`` (e.g. an azimuth)."""
    fixed = tuple(getattr(model, "fixed_states", ()) or ())
    if estimate_x0 is True:
        return np.array([i for i, s in enumerate(dyn.states) if s not in fixed], dtype=int)
    if estimate_x0 is False or estimate_x0 is None:
        return np.zeros(0, dtype=int)
    names = [estimate_x0] if isinstance(estimate_x0, str) else list(estimate_x0)
    unknown = [n for n in names if n not in dyn.states]
    if unknown:
        raise IdentificationOptionError(f"estimate_x0 names unknown states {unknown}; states are {list(dyn.states)}.")
    refused = [n for n in names if n in fixed]
    if refused:
        raise IdentificationOptionError(f"estimate_x0: {refused} cannot be estimated (the model keeps them from the "
                                        "data: an angle no channel determines); leave them out.")
    return np.array(sorted(dyn.states.index(n) for n in names), dtype=int)


def _start_values(specs, dyn: Dynamics, initial, bounds) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """theta0, lb, ub in model units."""
    labels = {s.key: s for s in specs}
    by_name = {s.name: s for s in specs}
    initial, bounds = dict(initial or {}), dict(bounds or {})
    for what, d in (("initial", initial), ("bounds", bounds)):
        unknown = sorted(k for k in d if k not in labels and k not in by_name)
        if unknown:
            raise ParameterError(f"{what} names {unknown}, which are not being identified ({list(labels)}).")
    theta0, lb, ub = [], [], []
    for s in specs:
        v = initial.get(s.key, initial.get(s.name))
        v = dyn.defaults.get(s.name) * s.factor if v is None and s.name in dyn.defaults else v
        if v is None:
            raise ParameterError(f"{s.key!r} has no default value; give it in initial={{{s.key!r}: value}}.")
        lo, hi = bounds.get(s.key, bounds.get(s.name, (s.lower, s.upper)))
        try:
            v, lo, hi = float(v), float(lo), float(hi)
        except (TypeError, ValueError):
            raise ParameterError(f"{s.key!r}: initial value and bounds must be numbers.") from None
        if not math.isfinite(v) or not lo <= v <= hi:
            raise ParameterError(f"{s.key!r}: initial value {v:g} {s.unit} is not finite or outside its bounds "
                                 f"[{lo:g}, {hi:g}].")
        a, b = sorted((lo / s.factor, hi / s.factor))
        theta0.append(v / s.factor)
        lb.append(a)
        ub.append(b)
    return np.array(theta0), np.array(lb), np.array(ub)


def _initial_nodes(fun: ShootingFunctions, rec: ShootingRecord, theta: np.ndarray, p: np.ndarray,
                   init: str) -> np.ndarray:
    """Shooting nodes: a simulation with the starting values, moved onto the data where the channels see them."""
    S = fun.simulate(rec.x0, rec.U, theta, p, rec.H)
    bad = ~np.all(np.isfinite(S), axis=1)
    if bad.any():
        S[bad] = rec.x0
    if init == "simulation":
        return S
    y, C, _ = fun.outputs(S, rec.U, theta, p, jac=True)
    check_finite("channels of the model along its first simulation", y)
    check_finite("channel Jacobians along the first simulation", C.reshape(C.shape[0], -1))
    e = rec.Y - y
    if np.any(rec.period):
        P = np.where(rec.period > 0, rec.period, 1.0)
        e = np.where(rec.period > 0, e - P * np.round(e / P), e)
    Cw = C * rec.w[None, :, None]
    dS = np.einsum("kxc,kc->kx", np.linalg.pinv(Cw, rcond=1e-8), e * rec.w)
    out = S + dS
    fixed = np.setdiff1d(np.arange(S.shape[1]), rec.free0)
    out[0, fixed] = rec.x0[fixed]
    return out


def identify(model: Any, data: Any, parameters: Sequence[str | Parameter] | str, *,
             channels: Sequence[str] | None = None, weights: Mapping[str, float] | None = None,
             initial: Mapping[str, float] | None = None,
             bounds: Mapping[str, tuple[float, float]] | None = None, x0=None,
             estimate_x0: bool | Sequence[str] = False, inputs=None,
             periodic: Mapping[str, float] | None = None, reader: Callable | None = None,
             method: str = "gauss-newton", substeps: int | None = None, init: str = "data",
             compile: bool = True, threads: int = 1, tol: float = 1e-8, max_iter: int = 50,
             correlation_threshold: float = 0.95, verbose: bool = False,
             progress: Callable[[dict], None] | None = None, max_time: float | None = None) -> IdentificationResult:
    """Estimate parameters (and optionally initial states) of a model from measured time series.

    Parameters
    ----------
    model
        Anything :func:`mbsym.as_dynamics` accepts (a :class:`~mbsym.Dynamics`,
        EquationsOfMotion, a turbine model with OpenFAST output channels, ...).
    data
        One record or a list of records (:mod:`mbsym.identify.data`): a dict with
        ``"time"`` and channel arrays, an object with ``time``/``names``/``data``, a
        CSV path (read by ``reader`` or the generic :func:`~mbsym.identify.data.read_csv`).
    parameters : sequence of str or Parameter
        Model parameter names, keys the model resolves (``model.resolve_parameter``,
        e.g. ElastoDyn keys ``"TwrFADmp(1)"`` of a turbine, reported in the deck's
        units), or :class:`Parameter` specifications.
    channels : sequence of str, keyword-only
        Fitted channels (model outputs or states present in the data); default: every
        output or state found in all records.
    weights : dict, keyword-only
        Relative weight per channel (default 1); each channel's residual is also
        divided by the range of its data, so weight 1 gives channels equal importance.
    initial, bounds : dict, keyword-only
        Starting value and ``(lower, upper)`` per parameter in label units; default the
        model's default value and the specification's bounds.
    x0 : array, dict, or list of them (one per record), keyword-only
        Initial state (default: the model's ``initial_state_from(record, u0)`` if it has one, e.g.
        the trim of an operating turbine at the record's first inputs; else its default state).
        Entries not estimated stay fixed.
    estimate_x0 : bool or sequence of state names, keyword-only
        Estimate all (True: all but the model's ``fixed_states``, e.g. a rotor azimuth) or some
        initial states. Initial states the fitted channels do not see at the start are not moved
        (an :class:`~mbsym.exceptions.IdentifiabilityWarning` names them).
    inputs : array (N, n_u), dict by name, or a list per record, keyword-only
        Inputs at the sample times, interpolated linearly in between (default: read off each
        record by the model's ``inputs_from(record)`` if it has one, e.g. the measured wind, pitch
        and torque of :class:`~mbsym.wind.operation.MeasuredInputTurbine`; else the model's default
        inputs, numbers or functions of time; a model object with inputs but neither is refused).
    periodic : dict, keyword-only
        ``{channel: period}`` for wrapped channels (e.g. an azimuth in deg: 360).
    method : {"gauss-newton", "sqpmethod", "ipopt"}, keyword-only
        Condensed Gauss–Newton (default, fast) or CasADi's NLP solvers on the full
        multiple-shooting problem with a Gauss–Newton Hessian.
    substeps : int, keyword-only
        RK4 sub-steps per sample interval (default: :func:`~mbsym.identify.shooting.choose_substeps`).
    init : {"data", "simulation"}, keyword-only
        Shooting nodes from a simulation with the starting values moved onto the data
        where the channels determine the states (default), or the simulation alone.
    compile : bool, keyword-only
        Compiled evaluation of the interval and output Functions (default True,
        cached on disk; falls back to CasADi's virtual machine with a warning).
    threads : int, keyword-only
        Threads evaluating the interval Jacobians (default 1).
    tol, max_iter : keyword-only
        Convergence tolerance on the scaled step and gaps, iteration limit.
    correlation_threshold : float, keyword-only
        Warn about parameter pairs more correlated than this (default 0.95).
    verbose : bool, keyword-only
        Print the iterations.
    progress : callable, keyword-only
        Called with a dict per event: ``{"stage": "built", "elapsed_s", "substeps", "compiled"}`` once
        the Functions exist, then ``{"stage": "iteration", "iteration", "cost", "gap", "step", "alpha",
        "elapsed_s"}`` after every Gauss–Newton iteration.
    max_time : float, keyword-only
        Wall-time limit [s] of the iteration (default none): the fit stops unconverged when exceeded.

    Returns
    -------
    IdentificationResult

    Raises
    ------
    ParameterError
        Unknown parameter or key, a key the model lacks, bad initial values or bounds.
    DataError
        Missing or non-finite data channels, bad time grids, channels not in the model.
    IdentificationOptionError
        Invalid options.
    SolverError
        The model's trajectory or Jacobians became non-finite (a model that does not describe the
        data, an unphysical start); the message says what to check.
    TypeError
        Unsupported model or data kinds.

    Warns
    -----
    IdentifiabilityWarning
        Nearly collinear or undetermined parameters; initial states the channels do not see.
    ConvergenceWarning
        The iteration stopped unconverged (``result.success`` is False); the message gives advice.

    Examples
    --------
    >>> import casadi as ca, numpy as np, mbsym as mb
    >>> x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 0), ca.SX.sym("p", 2)
    >>> f = ca.Function("f", [x, u, p], [ca.vertcat(x[1], -p[0] * x[0] - p[1] * x[1])])
    >>> dyn = mb.Dynamics(f, states=["q", "v"], parameters=["k", "c"], defaults={"k": 4.0, "c": 0.1},
    ...                   x0=[1.0, 0.0])
    >>> t = np.arange(0, 10, 0.05)
    >>> wd = np.sqrt(5 - 0.01)      # data: the exact solution with k = 5, c = 0.2
    >>> q = np.exp(-0.1 * t) * (np.cos(wd * t) + 0.1 / wd * np.sin(wd * t))
    >>> res = mb.identify(dyn, {"time": t, "q": q}, ["k", "c"], compile=False)
    >>> round(res.parameters["k"], 4), round(res.parameters["c"], 4)
    (5.0, 0.2)
    """
    t_start = time.perf_counter()
    if method not in METHODS:
        raise IdentificationOptionError(f"unknown method {method!r}; choose one of {list(METHODS)}.")
    if init not in ("data", "simulation"):
        raise IdentificationOptionError(f"init must be 'data' or 'simulation'; got {init!r}.")
    if not (isinstance(tol, (int, float)) and tol > 0 and isinstance(max_iter, int) and max_iter >= 1):
        raise IdentificationOptionError(f"tol must be > 0 and max_iter an int >= 1; got tol={tol!r}, "
                                        f"max_iter={max_iter!r}.")
    if substeps is not None and not (isinstance(substeps, int) and substeps >= 1):
        raise IdentificationOptionError(f"substeps must be an int >= 1; got {substeps!r}.")
    dyn = as_dynamics(model)
    specs = _resolve_parameters(model, dyn, parameters)
    records = as_records(data, reader)
    rows, chans = _channel_rows(dyn, records, channels)
    Ys = check_channels(records, chans)
    w = _default_weights(Ys) * _per_channel(weights, chans, "weights", 1.0)
    period = _per_channel(periodic, chans, "periodic", 0.0)
    theta0, lb, ub = _start_values(specs, dyn, initial, bounds)
    theta_idx = [dyn.parameters.index(s.name) for s in specs]
    p = dyn.parameter_vector()
    free0 = _free_initial(model, dyn, estimate_x0)
    Us = _record_inputs(model, dyn, inputs, records)
    x0s = _record_states(model, dyn, x0, records, Us)
    recs = [ShootingRecord(U, np.diff(r.time), Y, w, period, xs, free0) for U, r, Y, xs in zip(Us, records, Ys, x0s)]
    p0 = p.copy()
    p0[theta_idx] = theta0
    lam = float("nan")
    if substeps is None:
        substeps, lam = choose_substeps(dyn, x0s[0], Us[0][0], p0, float(max(np.max(r.H) for r in recs)))
    if not (isinstance(threads, int) and threads >= 1):
        raise IdentificationOptionError(f"threads must be an int >= 1; got {threads!r}.")
    if max_time is not None and not (isinstance(max_time, (int, float)) and max_time > 0):
        raise IdentificationOptionError(f"max_time must be a number of seconds > 0; got {max_time!r}.")
    if progress is not None and not callable(progress):
        raise IdentificationOptionError(f"progress must be a callable taking a dict; got {type(progress).__name__}.")
    fun, cached = shooting_functions(dyn, rows, theta_idx, free0.size, substeps, compile=compile, threads=threads)
    t_built = time.perf_counter()
    if progress is not None:
        progress({"stage": "built", "elapsed_s": t_built - t_start, "substeps": fun.substeps,
                  "compiled": fun.compiled})
    S0 = [_initial_nodes(fun, rec, theta0, p, init) for rec in recs]
    columns = [f"initial {dyn.states[i]} (record {k + 1})" for k, r in enumerate(recs) for i in r.free0]
    columns += [s.key for s in specs]
    theta_scale = np.where(np.abs(theta0) > 0, np.abs(theta0), np.maximum(np.abs(p[theta_idx]), 1.0))
    if method == "gauss-newton":
        report = None if progress is None else (lambda h: progress({"stage": "iteration", **h}))
        out = gauss_newton(fun, recs, p, theta0, S0, lb, ub, theta_scale, tol=tol, max_iter=max_iter,
                           verbose=verbose, progress=report, max_time=max_time, columns=columns)
    else:
        from .nlp import solve_nlp

        out = solve_nlp(fun, recs, p, theta0, S0, lb, ub, solver=method, tol=tol, max_iter=max_iter,
                        verbose=verbose)
    t_solved = time.perf_counter()
    if not out.success:
        warnings.warn(f"identification did not converge: {out.message}. The estimates are where the iteration "
                      f"stopped; do not use them as they are. {ADVICE} Raise max_iter or max_time if the cost "
                      "was still falling.", ConvergenceWarning, stacklevel=2)
    return _result(dyn, specs, fun, recs, records, chans, p, theta0, out, method, lam, correlation_threshold,
                   t_start, {"build_s": t_built - t_start - (0.0 if cached else fun.compile_s),
                             "compile_s": 0.0 if cached else fun.compile_s, "solve_s": t_solved - t_built})


def _result(dyn, specs, fun, recs, records, chans, p, theta0, out, method, lam, threshold, t_start,
            timings) -> IdentificationResult:
    t0 = time.perf_counter()
    n_th = len(specs)
    cov_all, sigma, _ = covariance(out.J, out.r)
    f = np.array([s.factor for s in specs])
    cov = cov_all[-n_th:, -n_th:] * np.outer(f, f)
    std = np.sqrt(np.abs(np.diag(cov)))
    corr = correlation_of(cov)
    labels = tuple(s.key for s in specs)
    warn_identifiability(labels, corr, std, threshold)
    state_std = _initial_state_std(dyn, recs, out, cov_all)
    fits, errs, datas = [], [], []
    for rec, r, S in zip(recs, records, out.S):
        x_start = rec.x0.copy()
        x_start[rec.free0] = S[0, rec.free0]
        X = fun.simulate(x_start, rec.U, out.theta, p, rec.H)
        y = fun.outputs(X, rec.U, out.theta, p, jac=False)
        fits.append({"time": r.time, "y": y})
        errs.append(y)
        datas.append(rec.Y)
    eps = fit_error(np.vstack(errs), np.vstack(datas), recs[0].period)
    timings = {**timings, "statistics_s": time.perf_counter() - t0}
    states = []
    for rec, S in zip(recs, out.S):
        x = rec.x0.copy()
        x[rec.free0] = S[0, rec.free0]
        states.append(dict(zip(dyn.states, map(float, x))))
    return IdentificationResult(
        parameters={k: float(v) for k, v in zip(labels, out.theta * f)},
        std={k: float(v) for k, v in zip(labels, std)},
        initial={k: float(v) for k, v in zip(labels, theta0 * f)},
        names=labels, units={s.key: s.unit for s in specs}, correlation=corr, covariance=cov,
        eps={c: float(v) for c, v in zip(chans, eps)}, initial_states=states, iterations=out.iterations,
        wall_s=time.perf_counter() - t_start, timings=timings, success=out.success, message=out.message,
        cost=out.cost, residual_std=sigma, n_residuals=int(out.r.size), substeps=fun.substeps, method=method,
        compiled=fun.compiled, channels=tuple(chans), weights={c: float(v) for c, v in zip(chans, recs[0].w)},
        fit=fits, history=out.history, initial_state_std=state_std)


def _initial_state_std(dyn, recs, out, cov_all) -> list:
    """Standard errors of the estimated initial states per record; warns about states the channels miss."""
    x_scale = np.maximum(np.max(np.abs(np.vstack(out.S)), axis=0), 1e-6)
    theta_scale = np.maximum(np.abs(out.theta), 1e-12)
    scaled = np.linalg.norm(out.J, axis=0) * np.concatenate([*(x_scale[r.free0] for r in recs), theta_scale])
    floor = 1e-8 * float(np.max(scaled)) if scaled.size else 0.0
    result, off, missed = [], 0, set()
    for rec in recs:
        d = {}
        for j, i in enumerate(rec.free0):
            seen = scaled[off + j] > floor
            d[dyn.states[i]] = float(np.sqrt(abs(cov_all[off + j, off + j]))) if seen else float("inf")
            if not seen:
                missed.add(dyn.states[i])
        result.append(d)
        off += rec.free0.size
    if missed:
        warnings.warn(f"poorly identifiable initial states: {sorted(missed)} are not determined by the channels "
                      "(kept at their starting values); add channels that see them or do not estimate them.",
                      IdentifiabilityWarning, stacklevel=4)
    return result
