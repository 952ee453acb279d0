"""``sweep``: many cases of one model through simulation, linearization or a user function."""

from __future__ import annotations

import pickle
import time
from typing import Any, Callable, Mapping, Sequence

import casadi as ca
import numpy as np

from ..exceptions import SweepError
from .cases import Case, as_cases, check_keys, resolve_case
from .executors import Progress, execute, parse_executor
from .plans import CallablePlan, LinearizationPlan, Outcome, SimulationPlan, rk4_step
from .table import SweepResult, SweepTable

__all__ = ["sweep", "DEFAULT_DT"]

#: Step of the sweep's fixed-step RK4 when neither ``dt=`` nor a case sets one [s] (as mbsym.simulate's rk4).
DEFAULT_DT = 0.01


def sweep(model: Any, cases: Any, *, run: str | Callable = "simulate", tmax: float | None = None,
          dt: float | None = None, p: Mapping[str, float] | None = None, x0: Mapping[str, float] | None = None,
          inputs: Mapping[str, Any] | None = None, channels: Sequence[str] | None = None,
          del_channels: Sequence[str] = (), wohler: float | Sequence[float] = 10.0, del_frequency: float = 1.0,
          t_start: float = 0.0, n_modes: int = 6, setters: Mapping[str, Callable] | None = None,
          executor: Any = "serial", chunk_size: int | None = None, series: bool = False,
          progress: bool | None = None, compile: bool = False) -> SweepResult:
    """Run a grid or list of cases and tabulate one row per case.

    Parameters
    ----------
    model : EquationsOfMotion, Dynamics, or a simulation model (an object with ``eom``)
        Anything :func:`mbsym.as_dynamics` accepts; may be None with a callable ``run``.
    cases : dict of sequences, or sequence of dicts
        A grid ``{key: [values]}`` (every combination; :func:`mbsym.sweep.grid`) or one dict
        per case. Keys: parameter, state or input names, ``tmax``, ``dt``, or keys of
        ``setters`` (resolution order: :mod:`mbsym.sweep.cases`).
    run : {"simulate", "linearize"} or callable, optional, keyword-only
        ``"simulate"``: fixed-step RK4 from 0 to ``tmax`` (the loop in CasADi), statistics of
        every channel. ``"linearize"``: ``A = d rhs/dx``, ``B = d rhs/du`` at (x0, u(0), p),
        natural frequencies [Hz] and damping ratios of the ``n_modes`` lowest modes.
        A callable ``run(case) -> dict of numbers | SimulationResult`` for anything else (it
        must be picklable for the process and Dask executors, and build its own model there).
    tmax, dt : float, optional, keyword-only
        End time and step [s] of simulations (a case may set its own); ``dt`` defaults to
        :data:`DEFAULT_DT` and is shortened so that whole steps end at ``tmax``.
    p, x0, inputs : dict, optional, keyword-only
        Settings common to every case (by name), under each case's own.
    channels : sequence of str, optional, keyword-only
        Channels summarized (state, input or output names); default the model's outputs,
        else its states.
    del_channels : sequence of str, optional, keyword-only
        Channels whose damage-equivalent load is computed (needs ``mbsym[loads]``).
    wohler : float or sequence of float, optional, keyword-only
        Wöhler exponents m of the DELs (default 10); columns ``<channel>_del_m<m>``.
    del_frequency : float, optional, keyword-only
        Frequency of the equivalent cycles [Hz] (default 1: ``N_eq = duration``).
    t_start : float, optional, keyword-only
        Statistics and DELs use ``t >= t_start`` [s] (drop an initial transient).
    n_modes : int, optional, keyword-only
        Modes tabulated by ``run="linearize"``.
    setters : dict, optional, keyword-only
        ``{key: f}``, ``f(value) -> {"p": {...}, "x0": {...}, "inputs": {...}, "options": {...}}``.
    executor : str or distributed.Client, optional, keyword-only
        ``"serial"`` (default), ``"threads:N"``, ``"processes:N"``, ``"dask:N"``, ``"dask:ADDRESS"``
        (:mod:`mbsym.sweep.executors`). Results are the same bit for bit on every executor.
    chunk_size : int, optional, keyword-only
        Cases per task (serial: per CasADi ``map`` call).
    series : bool, optional, keyword-only
        Keep every case's full result in :attr:`SweepResult.series`.
    progress : bool, optional, keyword-only
        Progress bar on stderr; default: only when stderr is a terminal.
    compile : bool, optional, keyword-only
        Run the RK4 step as compiled C (:mod:`mbsym.codegen`; each worker loads it from the disk cache).

    Returns
    -------
    SweepResult
        ``table`` (one row per case: the case keys, ``<channel>_mean``, ``_std``, ``_max``, ``_min``,
        DELs or modal columns, ``error``), ``series`` on request, timings.

    Raises
    ------
    SweepError
        Unknown case keys or channels, bad options, an unusable executor (before anything runs).
        A case that fails while running (a setter or value error, a diverging simulation) does
        not raise: its row holds NaN and the error message.

    Examples
    --------
    >>> import mbsym as mb
    >>> sys = mb.System()
    >>> x = sys.coordinates("x")
    >>> k = sys.parameters("k", values={"k": 4.0})
    >>> sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("m", 1.0), axis=[1, 0, 0], coordinate=x))
    >>> sys.add_spring(x, k)
    >>> res = sweep(sys.equations(), {"k": [1.0, 4.0]}, tmax=2.0, x0={"x": 1.0}, channels=["x"])
    >>> res.table.columns
    ('k', 'x_mean', 'x_std', 'x_max', 'x_min', 'error')
    """
    t_begin = time.perf_counter()
    spec = parse_executor(executor)
    opts = _options(channels, del_channels, wohler, del_frequency, t_start, n_modes, chunk_size, series, compile)
    _check_times(tmax, dt)
    case_dicts = as_cases(cases)
    setters = dict(setters or {})
    base = {"p": dict(p or {}), "x0": dict(x0 or {}), "inputs": dict(inputs or {}),
            "options": {k: v for k, v in (("tmax", tmax), ("dt", dt)) if v is not None}}
    if callable(run):
        builder = _CallableBuilder(model, run, opts)
    elif run == "simulate":
        builder = _SimulationBuilder(model, opts)
    elif run == "linearize":
        builder = _LinearizationBuilder(model, opts)
    else:
        raise SweepError(f"run must be 'simulate', 'linearize' or a callable run(case); got {run!r}.")
    if builder.names is not None:
        check_keys(case_dicts, setters=setters, **builder.names)
    plans, jobs, early, resolved, payloads = _jobs(builder, case_dicts, base, setters)
    t_prepared = time.perf_counter()
    bar = Progress(len(case_dicts), progress)
    bar.update(list(early.values()))
    try:
        outcomes = execute(spec, plans, jobs, chunk_size=opts["chunk_size"], progress=bar) if jobs else {}
    finally:
        bar.close()
    outcomes.update(early)
    ordered = [outcomes[i] for i in range(len(case_dicts))]
    table = _table(case_dicts, ordered)
    kept = [builder.series(resolved[i], o, *payloads[i]) if resolved[i] is not None and o.error is None else None
            for i, o in enumerate(ordered)] if opts["series"] else None
    return SweepResult(table, kept, resolved, str(spec), time.perf_counter() - t_begin,
                       np.array([o.wall_s for o in ordered]), t_prepared - t_begin,
                       np.array([o.cpu_s for o in ordered]))


def _jobs(builder, case_dicts: list[dict], base: dict, setters: dict):
    """Resolve every case and build its payload: plans by key, jobs ``(index, plan key, payload)``, the outcomes
    of cases that failed already, the resolved cases (None where failed) and ``{index: (plan, payload)}``."""
    plans: dict[str, Any] = {}
    jobs, early, resolved, payloads = [], {}, [], {}
    for i, settings in enumerate(case_dicts):
        try:
            case = (resolve_case(i, settings, base, setters=setters, **builder.names) if builder.names is not None
                    else Case(i, dict(settings), dict(base["p"]), dict(base["x0"]), dict(base["inputs"]),
                              {**base["options"], **settings}))
            plan, payload = builder.job(case)
        except Exception as exc:  # noqa: BLE001 - a bad value fails its case only
            if isinstance(exc, SweepError) and not getattr(exc, "per_case", True):
                raise
            early[i] = builder.failure(exc)
            resolved.append(None)
            continue
        plans.setdefault(plan.key, plan)
        jobs.append((i, plan.key, payload))
        payloads[i] = (plan, payload)
        resolved.append(case)
    return plans, jobs, early, resolved, payloads


def _check_times(tmax, dt) -> None:
    """Common tmax and dt are checked before anything runs (a case's own values fail that case only)."""
    from ..simulate.checks import check_step, check_tmax

    if tmax is not None:
        check_tmax(tmax)
    if dt is not None:
        check_step(dt, float(tmax) if tmax is not None else float(dt))


def _options(channels, del_channels, wohler, del_frequency, t_start, n_modes, chunk_size, series, compile) -> dict:
    ms = (wohler,) if isinstance(wohler, (int, float)) else tuple(wohler)
    if not ms or not all(isinstance(m, (int, float)) and np.isfinite(m) and m > 0 for m in ms):
        raise SweepError(f"wohler must be a positive number or a sequence of them (e.g. 4 or (4, 10)); got {wohler!r}.")
    for name, value in (("del_frequency", del_frequency), ("t_start", t_start)):
        if not isinstance(value, (int, float)) or not np.isfinite(value) or value < 0 or (
                name == "del_frequency" and value == 0):
            raise SweepError(f"{name} must be a {'positive' if name == 'del_frequency' else 'non-negative'} "
                             f"number; got {value!r}.")
    for name, value in (("n_modes", n_modes), ("chunk_size", chunk_size)):
        if value is not None and (not isinstance(value, int) or isinstance(value, bool) or value < 1):
            raise SweepError(f"{name} must be a positive integer; got {value!r}.")
    for name, value in (("series", series), ("compile", compile)):
        if not isinstance(value, bool):
            raise SweepError(f"{name} must be True or False; got {value!r}.")
    if isinstance(channels, str) or isinstance(del_channels, str):
        raise SweepError("channels and del_channels must be sequences of names, e.g. ['TTDspFA_[m]'].")
    return {"channels": None if channels is None else tuple(channels), "del_channels": tuple(del_channels),
            "wohler": tuple(float(m) for m in ms), "del_frequency": float(del_frequency), "t_start": float(t_start),
            "n_modes": n_modes, "chunk_size": chunk_size, "series": series, "compile": compile}


def _table(case_dicts: list[dict], outcomes: list[Outcome]) -> SweepTable:
    keys = list(dict.fromkeys(k for c in case_dicts for k in c))
    summary = list(dict.fromkeys(k for o in outcomes for k in o.summary if k not in keys and k != "error"))
    cols: dict[str, list] = {k: [c.get(k) for c in case_dicts] for k in keys}
    for k in summary:
        cols[k] = [o.summary.get(k, float("nan")) for o in outcomes]
    cols["error"] = [o.error or "" for o in outcomes]
    return SweepTable(cols)


class _ModelBuilder:
    """Common part of the simulation and linearization builders: the model's Dynamics and names."""

    def __init__(self, model: Any, opts: dict) -> None:
        from ..dynamics import as_dynamics

        self.opts = opts
        self.dyn = dyn = as_dynamics(model)
        defaults = getattr(model, "default_inputs", None)
        self.input_defaults = {n: float(v) for n, v in zip(dyn.inputs, dyn.u0)}
        if callable(defaults):
            self.input_defaults.update(defaults())
        self.names = {"parameters": dyn.parameters, "states": dyn.states, "inputs": dyn.inputs}
        self.all_channels = dyn.states + dyn.inputs + dyn.output_names
        for what in ("channels", "del_channels"):
            unknown = [c for c in (opts[what] or ()) if c not in self.all_channels]
            if unknown:
                raise SweepError(f"{what} {unknown} are not states, inputs or outputs of the model; available: "
                                 f"{list(self.all_channels)}.")
        self.channels = opts["channels"] or (dyn.output_names or dyn.states)

    def vectors(self, case: Case, tmax: float):
        from ..simulate.inputs import input_signal

        signal = input_signal({**self.input_defaults, **case.inputs}, self.dyn.inputs, tmax)
        return self.dyn.state_vector(case.x0), signal, self.dyn.parameter_vector(case.p)

    def failure(self, exc: BaseException) -> Outcome:
        return Outcome({}, f"{type(exc).__name__}: {exc}".strip())


class _SimulationBuilder(_ModelBuilder):
    def __init__(self, model: Any, opts: dict) -> None:
        super().__init__(model, opts)
        dyn = self.dyn
        self.step = rk4_step(dyn.rhs, dyn.n_x, dyn.n_u, dyn.n_p).serialize()
        self.outputs = dyn.outputs.serialize() if dyn.outputs is not None else None
        self._plans: dict[int, SimulationPlan] = {}

    def plan(self, n: int) -> SimulationPlan:
        if n not in self._plans:
            d, o = self.dyn, self.opts
            self._plans[n] = SimulationPlan(self.step, self.outputs, n, (d.n_x, d.n_u, d.n_p, d.n_y), d.states,
                                            d.inputs, d.output_names, tuple(self.channels), o["del_channels"],
                                            o["wohler"], o["del_frequency"], o["t_start"], o["series"], o["compile"])
        return self._plans[n]

    def job(self, case: Case):
        from ..simulate.checks import check_step, check_tmax

        if "tmax" not in case.options:
            err = SweepError("simulations need tmax: pass tmax= to sweep() or set it in every case.")
            err.per_case = False
            raise err
        tmax = check_tmax(case.options["tmax"])
        h, n = check_step(case.options.get("dt", DEFAULT_DT), tmax)
        x, signal, p = self.vectors(case, tmax)
        t_grid = h * np.arange(n + 1)
        t_grid[-1] = tmax
        t_stage = (t_grid[:-1, None] + np.array([0.0, 0.5, 1.0])[None, :] * h).reshape(-1)
        U = np.asarray(signal(t_stage), dtype=float).reshape(len(t_stage), -1).T
        return self.plan(n), (x, np.ascontiguousarray(U), p, float(h))

    def series(self, case: Case, outcome: Outcome, plan: SimulationPlan, payload: tuple):
        from ..simulate.result import SimulationResult

        X, Y = outcome.series
        _, U, _, h = payload
        n = plan.n_steps
        t = h * np.arange(n + 1)
        t[-1] = float(case.options["tmax"])
        Ug = np.hstack([U[:, 0:3 * n:3], U[:, 3 * n - 1:3 * n]]) if U.shape[0] else np.zeros((0, n + 1))
        stats = {"method": "rk4", "steps": n, "dt": h, "success": True, "message": "sweep case",
                 "integration_wall_s": outcome.wall_s}
        d = self.dyn
        known = lambda names, units: {n: u for n, u in zip(names, units) if u}  # noqa: E731
        return SimulationResult(t, X.T, d.states, Ug.T, d.inputs, Y.T, d.output_names, stats,
                                output_units=d.output_units, state_units=known(d.states, d.state_units),
                                input_units=known(d.inputs, d.input_units))


class _LinearizationBuilder(_ModelBuilder):
    def __init__(self, model: Any, opts: dict) -> None:
        super().__init__(model, opts)
        d = self.dyn
        sym = ca.SX if d.rhs.is_a("SXFunction") else ca.MX
        x, u, p = sym.sym("x", d.n_x), sym.sym("u", d.n_u), sym.sym("p", d.n_p)
        xd = d.rhs(x, u, p)
        f = ca.Function("sweep_linearization", [x, u, p], [ca.densify(ca.jacobian(xd, x)),
                                                            ca.densify(ca.jacobian(xd, u))], ["x", "u", "p"], ["A", "B"])
        self._plan = LinearizationPlan(f.serialize(), opts["n_modes"], opts["series"])

    def job(self, case: Case):
        x, signal, p = self.vectors(case, 1.0)
        return self._plan, (x, np.asarray(signal.at(0.0), dtype=float).reshape(-1), p)

    def series(self, case: Case, outcome: Outcome, plan: Any, payload: Any):
        return outcome.series


class _CallableBuilder:
    def __init__(self, model: Any, run: Callable, opts: dict) -> None:
        try:
            import cloudpickle as pickler
        except ImportError:  # pragma: no cover - cloudpickle comes with dask
            pickler = pickle
        try:
            blob = pickler.dumps(run)
        except Exception as exc:  # noqa: BLE001 - report any pickling failure the same way
            raise SweepError(f"the run function cannot be sent to workers ({type(exc).__name__}: {exc}); define it "
                             "at module level.") from exc
        self._plan = CallablePlan(blob, opts["channels"], opts["del_channels"], opts["wohler"],
                                  opts["del_frequency"], opts["t_start"], opts["series"])
        self.names = None
        if model is not None:
            from ..dynamics import as_dynamics

            d = as_dynamics(model)
            self.names = {"parameters": d.parameters, "states": d.states, "inputs": d.inputs}

    def job(self, case: Case):
        return self._plan, case

    def failure(self, exc: BaseException) -> Outcome:
        return Outcome({}, f"{type(exc).__name__}: {exc}".strip())

    def series(self, case: Case, outcome: Outcome, plan: Any, payload: Any):
        return outcome.series
