"""What a sweep ships to its workers: plans (serialized CasADi Functions) and per-case payloads.

A *plan* is built once per sweep in the calling process and holds plain data only:
CasADi Functions as their serialization (``Function.serialize()``), names and options.
A worker turns it into callable Functions once (:func:`prepare`, cached per process by
the plan's key) and evaluates any number of cases with it; a case's *payload* holds only
numbers (initial state, sampled inputs, parameters). Nothing is rebuilt or re-derived per
case, and every executor evaluates the same Functions on the same numbers, so the same
case gives the same results bit for bit.

Plans:

- :class:`SimulationPlan`: fixed-step RK4 (the formula of :func:`mbsym.simulate`'s
  ``"rk4"``), the whole loop in CasADi (``mapaccum``) with the outputs mapped over the
  grid: ``case(x0, U, p, h) -> (X, Y)``; payload ``(x0, U, p, h)`` with the inputs sampled
  at the stage times;
- :class:`LinearizationPlan`: ``(x, u, p) -> (A, B)`` (CasADi AD of the rhs); payload
  ``(x, u, p)``;
- :class:`CallablePlan`: a user function ``run(case)`` shipped by (cloud)pickle; payload
  the :class:`~mbsym.sweep.cases.Case`.
"""

from __future__ import annotations

import hashlib
import pickle
import time
from dataclasses import dataclass, field
from typing import Any, Mapping

import casadi as ca
import numpy as np

from .stats import channel_statistics, modal_summary

__all__ = ["SimulationPlan", "LinearizationPlan", "CallablePlan", "Outcome", "prepare", "run_chunk",
           "evaluate_mapped", "rk4_step"]

#: Prepared plans of this process, by plan key (a worker prepares each plan once); the oldest beyond
#: PREPARED_MAX are dropped.
_PREPARED: dict[str, Any] = {}
PREPARED_MAX = 8


@dataclass
class Outcome:
    """What evaluating one case returns: its summary columns, error (or None), optional series, wall time [s]
    and CPU time [s] of the evaluation in its worker."""

    summary: dict
    error: str | None = None
    series: Any = None
    wall_s: float = 0.0
    cpu_s: float = 0.0


def _key(*parts) -> str:
    h = hashlib.sha1()
    for p in parts:
        h.update(repr(p).encode())
    return h.hexdigest()


def rk4_step(rhs: ca.Function, n_x: int, n_u: int, n_p: int) -> ca.Function:
    """``(x, U (n_u, 3), p, h) -> x_next``: one classical RK4 step, inputs at t, t + h/2, t + h."""
    sym = ca.SX if rhs.is_a("SXFunction") else ca.MX
    x, U, p, h = sym.sym("x", n_x), sym.sym("U", n_u, 3), sym.sym("p", n_p), sym.sym("h")
    k1 = rhs(x, U[:, 0], p)
    k2 = rhs(x + (h / 2) * k1, U[:, 1], p)
    k3 = rhs(x + (h / 2) * k2, U[:, 1], p)
    k4 = rhs(x + h * k3, U[:, 2], p)
    opts = {"cse": True} if sym is ca.SX else {}
    return ca.Function("sweep_rk4_step", [x, U, p, h], [x + (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4)],
                       ["x", "U", "p", "h"], ["x_next"], opts)


# ---------------------------------------------------------------------------- simulation
@dataclass(frozen=True)
class SimulationPlan:
    """Fixed-step RK4 over ``n_steps`` steps, outputs on the step grid, summaries per case."""

    step: str
    outputs: str | None
    n_steps: int
    sizes: tuple[int, int, int, int]            # n_x, n_u, n_p, n_y
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    output_names: tuple[str, ...]
    channels: tuple[str, ...]
    del_channels: tuple[str, ...] = ()
    wohler: tuple[float, ...] = (10.0,)
    del_frequency: float = 1.0
    t_start: float = 0.0
    series: bool = False
    compile: bool = False
    key: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "key", _key("sim", self.step, self.outputs, self.n_steps, self.channels,
                                             self.del_channels, self.wohler, self.del_frequency, self.t_start,
                                             self.series, self.compile))


class _PreparedSimulation:
    def __init__(self, plan: SimulationPlan) -> None:
        from ..codegen import compile_function

        self.plan = plan
        step = ca.Function.deserialize(plan.step)
        if plan.compile:
            step = compile_function(step).function
        n_x, n_u, n_p, n_y = plan.sizes
        n = plan.n_steps
        loop = step.mapaccum("sweep_loop", n)
        x0, U, p, h = ca.MX.sym("x0", n_x), ca.MX.sym("U", n_u, 3 * n), ca.MX.sym("p", n_p), ca.MX.sym("h")
        X = ca.horzcat(x0, loop(x0, U, ca.repmat(p, 1, n), ca.repmat(h, 1, n)))
        Ug = ca.horzcat(U[:, 0:3 * n:3], U[:, 3 * n - 1]) if n_u else ca.MX(0, n + 1)
        if plan.outputs is not None:
            out = ca.Function.deserialize(plan.outputs).map(n + 1)
            Y = out(X, Ug, ca.repmat(p, 1, n + 1))
        else:
            Y = ca.MX(0, n + 1)
        self.function = ca.Function("sweep_case", [x0, U, p, h], [X, Y], ["x0", "U", "p", "h"], ["X", "Y"])
        self._mapped: dict = {}

    def mapped(self, n_cases: int, parallelization: str, workers: int) -> ca.Function:
        key = (n_cases, parallelization, workers)
        if key not in self._mapped:
            if parallelization == "thread":
                self._mapped[key] = self.function.map(n_cases, "thread", workers)
            else:
                self._mapped[key] = self.function.map(n_cases, "serial")
        return self._mapped[key]

    @staticmethod
    def stack(payloads: list) -> list[np.ndarray]:
        return [np.column_stack([pl[0] for pl in payloads]), np.hstack([pl[1] for pl in payloads]),
                np.column_stack([pl[2] for pl in payloads]), np.array([[pl[3] for pl in payloads]])]

    def split(self, outs, n_cases: int) -> list[tuple[np.ndarray, np.ndarray]]:
        X, Y = (np.asarray(o) for o in outs)
        w = self.plan.n_steps + 1
        return [(X[:, k * w:(k + 1) * w], Y[:, k * w:(k + 1) * w]) for k in range(n_cases)]

    def one(self, payload) -> tuple[np.ndarray, np.ndarray]:
        X, Y = self.function(*payload)
        return np.asarray(X), np.asarray(Y)

    def outcome(self, payload, result, wall: float) -> Outcome:
        plan = self.plan
        X, Y = result
        t = payload[3] * np.arange(plan.n_steps + 1)
        bad = ~np.all(np.isfinite(X), axis=0)
        if np.any(bad):
            k = int(np.argmax(bad))
            state = plan.states[int(np.argmax(~np.isfinite(X[:, k])))]
            nan = {c: float("nan") for c in _summary_columns(plan)}
            return Outcome(nan, f"IntegrationError: the states are not finite from t = {t[k]:.6g} s (first: "
                                f"{state!r}) with rk4 and dt = {payload[3]:.6g} s; reduce dt.", None, wall)
        U = np.asarray(payload[1], dtype=float)
        n = plan.n_steps
        Ug = np.hstack([U[:, 0:3 * n:3], U[:, 3 * n - 1:3 * n]]) if U.shape[0] else np.zeros((0, n + 1))
        cols = {**dict(zip(plan.states, X)), **dict(zip(plan.inputs, Ug)), **dict(zip(plan.output_names, Y))}
        summary = channel_statistics(t, cols, channels=plan.channels, del_channels=plan.del_channels,
                                     wohler=plan.wohler, del_frequency=plan.del_frequency, t_start=plan.t_start)
        return Outcome(summary, None, (np.ascontiguousarray(X), np.ascontiguousarray(Y)) if plan.series else None,
                       wall)


def _summary_columns(plan: SimulationPlan) -> list[str]:
    from .stats import STATISTICS, del_column

    cols = [f"{c}_{s}" for c in plan.channels for s in STATISTICS]
    return cols + [del_column(c, m) for c in plan.del_channels for m in plan.wohler]


# ---------------------------------------------------------------------------- linearization
@dataclass(frozen=True)
class LinearizationPlan:
    """``(x, u, p) -> (A, B)``; summaries: the ``n_modes`` lowest natural frequencies and damping ratios."""

    function: str
    n_modes: int
    series: bool = False
    key: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "key", _key("lin", self.function, self.n_modes, self.series))


class _PreparedLinearization:
    def __init__(self, plan: LinearizationPlan) -> None:
        self.plan = plan
        self.function = ca.Function.deserialize(plan.function)
        self._mapped: dict = {}

    def mapped(self, n_cases: int, parallelization: str, workers: int) -> ca.Function:
        key = (n_cases, parallelization, workers)
        if key not in self._mapped:
            args = ("thread", workers) if parallelization == "thread" else ("serial",)
            self._mapped[key] = self.function.map(n_cases, *args)
        return self._mapped[key]

    @staticmethod
    def stack(payloads: list) -> list[np.ndarray]:
        return [np.column_stack([np.asarray(pl[i], dtype=float).reshape(-1) for pl in payloads]) for i in range(3)]

    def split(self, outs, n_cases: int):
        A, B = (np.asarray(o) for o in outs)
        nx, nu = A.shape[0], B.shape[1] // max(n_cases, 1)
        return [(A[:, k * nx:(k + 1) * nx], B[:, k * nu:(k + 1) * nu]) for k in range(n_cases)]

    def one(self, payload):
        A, B = self.function(*payload)
        return np.asarray(A), np.asarray(B)

    def outcome(self, payload, result, wall: float) -> Outcome:
        A, B = result
        if not np.all(np.isfinite(A)) or not np.all(np.isfinite(B)):
            nan = {f"mode{k + 1}_{s}": float("nan") for k in range(self.plan.n_modes) for s in ("freq_hz", "damping")}
            return Outcome(nan, "SolverError: the linearized model is not finite at this operating point.", None, wall)
        summary, lam = modal_summary(A, self.plan.n_modes)
        series = {"A": np.ascontiguousarray(A), "B": np.ascontiguousarray(B), "eigenvalues": lam}
        return Outcome(summary, None, series if self.plan.series else None, wall)


# ---------------------------------------------------------------------------- user callables
@dataclass(frozen=True)
class CallablePlan:
    """A user function ``run(case) -> dict of numbers | SimulationResult``, pickled (cloudpickle if available)."""

    runner: bytes
    channels: tuple[str, ...] | None = None
    del_channels: tuple[str, ...] = ()
    wohler: tuple[float, ...] = (10.0,)
    del_frequency: float = 1.0
    t_start: float = 0.0
    series: bool = False
    key: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "key", _key("call", self.runner, self.channels, self.del_channels, self.wohler,
                                             self.del_frequency, self.t_start, self.series))


class _PreparedCallable:
    def __init__(self, plan: CallablePlan) -> None:
        self.plan = plan
        self.run = pickle.loads(plan.runner)

    def one(self, case):
        return self.run(case)

    def outcome(self, case, result, wall: float) -> Outcome:
        from ..simulate.result import SimulationResult

        plan = self.plan
        if isinstance(result, SimulationResult):
            cols = result.to_dict()
            channels = plan.channels or (result.output_names or result.states)
            summary = channel_statistics(result.t, cols, channels=channels, del_channels=plan.del_channels,
                                         wohler=plan.wohler, del_frequency=plan.del_frequency, t_start=plan.t_start)
        elif isinstance(result, Mapping):
            summary = {str(k): float(v) for k, v in result.items()}
        else:
            raise TypeError(f"the run function must return a dict of numbers or a SimulationResult; got "
                            f"{type(result).__name__}.")
        return Outcome(summary, None, result if plan.series else None, wall)


# ---------------------------------------------------------------------------- evaluation
def prepare(plan) -> Any:
    """The callable form of ``plan`` in this process (built once per plan key)."""
    prepared = _PREPARED.get(plan.key)
    if prepared is None:
        cls = {SimulationPlan: _PreparedSimulation, LinearizationPlan: _PreparedLinearization,
               CallablePlan: _PreparedCallable}[type(plan)]
        prepared = _PREPARED[plan.key] = cls(plan)
        while len(_PREPARED) > PREPARED_MAX:
            _PREPARED.pop(next(iter(_PREPARED)))
    return prepared


def _error(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}".strip()


def _failed(prepared, exc: BaseException, wall: float) -> Outcome:
    plan = prepared.plan
    if isinstance(plan, SimulationPlan):
        cols = _summary_columns(plan)
    elif isinstance(plan, LinearizationPlan):
        cols = [f"mode{k + 1}_{s}" for k in range(plan.n_modes) for s in ("freq_hz", "damping")]
    else:
        cols = []
    return Outcome({c: float("nan") for c in cols}, _error(exc), None, wall)


def run_chunk(plan, payloads: list) -> list[Outcome]:
    """Evaluate the cases of ``payloads`` one by one (the worker side of every parallel executor)."""
    prepared = prepare(plan)
    out = []
    for payload in payloads:
        t0, c0 = time.perf_counter(), time.thread_time()
        try:
            result = prepared.one(payload)
            outcome = prepared.outcome(payload, result, time.perf_counter() - t0)
        except Exception as exc:  # noqa: BLE001 - a failing case is recorded in its row, the sweep goes on
            outcome = _failed(prepared, exc, time.perf_counter() - t0)
        outcome.cpu_s = time.thread_time() - c0
        out.append(outcome)
    return out


def evaluate_mapped(plan, payloads: list, *, parallelization: str = "serial", workers: int = 1) -> list[Outcome]:
    """Evaluate the cases of ``payloads`` through one mapped Function call (CasADi ``map``).

    Callable plans, and a mapped call that raises, fall back to :func:`run_chunk` (case by case,
    so that one failing case does not take the others with it).
    """
    prepared = prepare(plan)
    if isinstance(plan, CallablePlan) or len(payloads) < 2:
        return run_chunk(plan, payloads)
    t0, c0 = time.perf_counter(), time.process_time()          # process time: includes CasADi's map threads
    try:
        f = prepared.mapped(len(payloads), parallelization, workers)
        results = prepared.split(f(*prepared.stack(payloads)), len(payloads))
    except Exception:  # noqa: BLE001 - isolate the failing case
        return run_chunk(plan, payloads)
    wall = (time.perf_counter() - t0) / len(payloads)
    out = [prepared.outcome(pl, r, wall) for pl, r in zip(payloads, results)]
    cpu = (time.process_time() - c0) / len(payloads)
    for o in out:
        o.cpu_s = cpu
    return out
