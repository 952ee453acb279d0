"""The solver base class, the problem it solves, and the cache of prepared CasADi Functions.

A method (scipy's ``OdeSolver`` is the model) is a small class that declares
``name``, ``order`` and ``kind`` and implements two private hooks:

- ``_prepare()`` builds (or fetches from the cache) what the method needs from
  the model's CasADi Functions and returns it;
- ``_integrate(prepared)`` integrates the :class:`Problem` and returns the
  states on the output grid and its counters.

:meth:`Method.solve` times both and assembles the statistics. Methods raise
:class:`~mbsym.exceptions.IntegrationError` on divergence; they never return
non-finite states.
"""

from __future__ import annotations

import time
import weakref
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any, Callable, ClassVar, Hashable

import casadi as ca
import numpy as np

from ..codegen import compile_function, compiler_command
from ..exceptions import SimulationOptionError
from .inputs import InputSignal

__all__ = ["Problem", "Trajectory", "Method", "prepared", "clear_cache", "compile_key"]

#: Prepared entries kept per model (the least recently used is dropped first).
CACHE_SIZE = 16
_CACHE: "weakref.WeakKeyDictionary[Any, OrderedDict[Hashable, Any]]" = weakref.WeakKeyDictionary()


def prepared(owner: Any, key: Hashable, build: Callable[[], Any]) -> tuple[Any, bool]:
    """The object built by ``build()`` for ``(owner, key)``, cached; returns ``(object, cache_hit)``.

    ``owner`` is the model's :attr:`Plant.owner <mbsym.simulate.model.Plant.owner>` (its
    EquationsOfMotion, or the rhs Function of other dynamics). Least recently used entries are
    dropped beyond :data:`CACHE_SIZE` per owner. The cache holds weak references to the owners:
    entries vanish with them. ``key`` must hold everything that changes the built object (see
    :meth:`Method.cache_key`).
    """
    entries = _CACHE.setdefault(owner, OrderedDict())
    if key in entries:
        entries.move_to_end(key)
        return entries[key], True
    value = build()
    entries[key] = value
    while len(entries) > CACHE_SIZE:
        entries.popitem(last=False)
    return value, False


def compile_key(enabled: bool) -> tuple[str, ...] | None:
    """What identifies compiled code in a cache key: the compiler command when ``enabled``, else None."""
    return compiler_command() if enabled else None


def clear_cache() -> None:
    """Forget every prepared Function (e.g. to time preparation in a benchmark)."""
    _CACHE.clear()


@dataclass(frozen=True, eq=False)
class Problem:
    """An initial-value problem ``xd = rhs(x, u(t), p)``, ``x(0) = x0``, ready for a method.

    Attributes
    ----------
    plant : Plant
        The model (:class:`mbsym.simulate.model.Plant`): rhs, names, and the EquationsOfMotion
        when the second-order methods apply.
    x0 : ndarray (n_x,)
        Initial state ``[q; qd]``.
    p : ndarray (n_p,)
        Parameter vector.
    inputs : InputSignal
        ``u(t)``.
    t_out : ndarray
        Output times [s], strictly increasing in ``[0, tmax]``.
    tmax : float
        End time [s].
    dt : float or None
        Fixed step [s] (fixed-step methods; already adjusted so that a whole
        number of steps ends at ``tmax``).
    n_steps : int or None
        Number of fixed steps.
    rtol, atol : float
        Tolerances of adaptive methods.
    compile : bool
        Evaluate the method's Functions as compiled C (:mod:`mbsym.codegen`).
    monitor : RunMonitor or None
        Progress reports and interruption (:mod:`mbsym.simulate.monitor`); None: silent.
    """

    plant: Any
    x0: np.ndarray
    p: np.ndarray
    inputs: InputSignal
    t_out: np.ndarray
    tmax: float
    dt: float | None = None
    n_steps: int | None = None
    rtol: float = 1e-6
    atol: float = 1e-8
    compile: bool = False
    monitor: Any = None

    @property
    def eom(self):
        """The EquationsOfMotion of the plant (None for first-order dynamics that are more than [q; qd])."""
        return self.plant.eom

    @property
    def owner(self) -> Any:
        """Key of the prepared-Function cache (:attr:`Plant.owner <mbsym.simulate.model.Plant.owner>`)."""
        return self.plant.owner


@dataclass
class Trajectory:
    """What a method's ``_integrate`` returns: states on ``t_out`` and counters."""

    x: np.ndarray                      # (len(t_out), n_x)
    success: bool                      # the integrator reached the last output time
    message: str
    steps: int | None = None
    n_rhs: int | None = None
    n_jac: int | None = None
    extra: dict = field(default_factory=dict)


class Method:
    """Base class of the integration methods registered in :data:`mbsym.simulate.METHODS`.

    Subclasses set the class attributes and implement ``_prepare`` and
    ``_integrate``.

    Attributes
    ----------
    name : str
        Registry name (``method=`` of :func:`mbsym.simulate`).
    order : int
        Order of accuracy (for variable-order methods, the highest order used).
    kind : str
        ``"fixed-step"`` or ``"adaptive"``. A fixed-step method uses ``dt``
        (default :attr:`default_dt`) and outputs every step by default; an
        adaptive one uses ``rtol``/``atol`` and 200 output times by default.
    implicit : bool
        Whether the method solves (non)linear systems with the Jacobian (suited
        to stiff problems).
    needs_held : bool
        Whether the method needs dynamics with a held part (:class:`mbsym.held.HeldPart`).
    second_order : bool
        Whether the method integrates the residual form of an EquationsOfMotion
        (``e(q, qd, qdd) = 0``); such a method refuses first-order dynamics that are
        more than ``[q; qd]``.
    """

    name: ClassVar[str] = ""
    order: ClassVar[int] = 0
    kind: ClassVar[str] = "fixed-step"
    implicit: ClassVar[bool] = False
    second_order: ClassVar[bool] = False
    #: Whether the method needs dynamics that declare a held part (:mod:`mbsym.held`).
    needs_held: ClassVar[bool] = False
    default_dt: ClassVar[float] = 0.01

    def __init__(self, problem: Problem) -> None:
        if self.second_order and problem.eom is None:
            raise SimulationOptionError(
                f"method {self.name!r} integrates the second-order residual form of an EquationsOfMotion, but "
                f"{problem.plant.name!r} is first-order dynamics with states {list(problem.plant.states)[:6]}"
                f"{' ...' if problem.plant.n_x > 6 else ''}; use a first-order method (rk4, adams, cvodes, idas, "
                "scipy-radau, scipy-bdf) or leave method unset.")
        self.problem = problem
        self._compiler = compile_key(problem.compile)
        #: Whether the libraries compiled for this preparation came from the disk cache (None: none loaded).
        self.disk_cache_hit: bool | None = None

    @classmethod
    def settings(cls) -> tuple:
        """The class settings that change results (coefficients, Newton or solver options), hashable."""
        return ()

    def cache_key(self, *parts: Hashable) -> tuple:
        """Key of a prepared Function: method class, its settings, compilation and compiler, then ``parts``."""
        return (type(self), self.settings(), self.problem.compile, self._compiler, *parts)

    def _compile(self, f: ca.Function, *, jacobian: bool = False) -> tuple[ca.Function, bool]:
        """:func:`maybe_compile` of ``f`` as the problem asks, recording :attr:`disk_cache_hit`."""
        g, on, hit = maybe_compile(f, self.problem.compile, jacobian=jacobian, with_hit=True)
        if on:
            self.disk_cache_hit = hit and self.disk_cache_hit is not False
        return g, on

    def solve(self) -> tuple[np.ndarray, dict]:
        """Prepare, integrate and time; return the states on ``t_out`` and the statistics."""
        t0 = time.perf_counter()
        prep, hit = self._prepare()
        t1 = time.perf_counter()
        traj = self._integrate(prep)
        t2 = time.perf_counter()
        stats = {
            "method": self.name,
            "steps": traj.steps,
            "n_rhs": traj.n_rhs,
            "n_jac": traj.n_jac,
            "integration_wall_s": t2 - t1,
            "prepare_wall_s": t1 - t0,
            "cache_hit": hit,
            "disk_cache_hit": self.disk_cache_hit,
            "compiled": False,
            "dt": self.problem.dt,
            "success": bool(traj.success),
            "message": traj.message,
        }
        if self.kind == "adaptive":
            stats.update(rtol=self.problem.rtol, atol=self.problem.atol)
        stats.update(traj.extra)
        return traj.x, stats

    def _prepare(self) -> tuple[Any, bool]:
        raise NotImplementedError

    def _integrate(self, prep: Any) -> Trajectory:
        raise NotImplementedError


def run_buffered(f: ca.Function, args: list, n: int) -> tuple:
    """One call of ``f`` through its buffer on contiguous float arrays ``args``; each output returned as
    ``(size / n, n)`` columns (a view of the column-major result)."""
    outs = [np.empty(f.numel_out(i)) for i in range(f.n_out())]
    buf, trigger = f.buffer()
    for i, a in enumerate(args):
        buf.set_arg(i, memoryview(a))
    for i, o in enumerate(outs):
        buf.set_res(i, memoryview(o))
    trigger()
    return tuple(o.reshape(n, -1).T for o in outs)


def maybe_compile(f: ca.Function, enabled: bool, *, jacobian: bool = False, with_hit: bool = False) -> tuple:
    """``(f compiled, True)`` when ``enabled`` and a compiler works, else ``(f, False)``.

    ``jacobian``: the library also holds ``f.jacobian()`` (for CasADi's SUNDIALS interfaces).
    ``with_hit``: append whether the library came from the disk cache.
    """
    if not enabled:
        return (f, False, False) if with_hit else (f, False)
    c = compile_function(f, jacobian=jacobian)
    return (c.function, c.compiled, c.cache_hit) if with_hit else (c.function, c.compiled)


def _rhs_of(model: Any) -> ca.Function:
    """The first-order rhs of a Plant or Dynamics (``.rhs``) or an EquationsOfMotion (``.functions.rhs``)."""
    rhs = getattr(model, "rhs", None)
    return rhs if isinstance(rhs, ca.Function) else model.functions.rhs


def symbolic_rhs(model: Any) -> tuple[type, ca.Function]:
    """The symbol class matching the model's rhs (SX for an SX Function, else MX) and the rhs."""
    rhs = _rhs_of(model)
    return (ca.SX if rhs.is_a("SXFunction") else ca.MX), rhs


def jacobian_function(model: Any) -> ca.Function:
    """``(x, u, p) -> d rhs / d x`` (n_x, n_x), dense, built from the rhs of a Plant, Dynamics or equations."""
    sym, rhs = symbolic_rhs(model)
    x, u, p = (sym.sym(s, rhs.size1_in(i)) for i, s in enumerate("xup"))
    J = ca.densify(ca.jacobian(rhs(x, u, p), x))
    return ca.Function(f"{model.name}_rhs_jacobian", [x, u, p], [J], ["x", "u", "p"], ["J"], {"cse": True})


class BufferedFunction:
    """Fast Python-side calls ``f(x, u) -> ndarray`` of a Function ``(x, u, p) -> dense matrix``.

    Uses ``Function.buffer()`` (about 1 us per call instead of ~40 us through
    the DM conversion); ``p`` is fixed at construction.
    """

    def __init__(self, f: ca.Function, p: np.ndarray) -> None:
        self._x = np.zeros(f.numel_in(0))
        self._u = np.zeros(f.numel_in(1))
        self._p = np.array(p, dtype=float)
        self._shape = f.size_out(0)
        self._out = np.zeros(f.numel_out(0))
        self._buf, self._trigger = f.buffer()
        for i, arr in enumerate((self._x, self._u, self._p)):
            self._buf.set_arg(i, memoryview(arr))
        self._buf.set_res(0, memoryview(self._out))

    def __call__(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        self._x[:] = x
        self._u[:] = u
        self._trigger()
        out = self._out.copy()
        return out if self._shape[1] == 1 else out.reshape(self._shape, order="F")


def dense_rhs(model: Any) -> ca.Function:
    """``(x, u, p) -> xd`` with a dense output (for buffered calls)."""
    sym, rhs = symbolic_rhs(model)
    x, u, p = (sym.sym(s, rhs.size1_in(i)) for i, s in enumerate("xup"))
    return ca.Function(f"{model.name}_rhs_dense", [x, u, p], [ca.densify(rhs(x, u, p))], ["x", "u", "p"], ["xd"])


def stability_hint(model: Any, problem: Problem, method: str, stability_radius: float) -> str:
    """Explain a divergence of an explicit method: is the step beyond its stability limit at t = 0?"""
    J = np.array(jacobian_function(model)(problem.x0, problem.inputs.at(0.0), problem.p))
    if not np.all(np.isfinite(J)):
        return "The Jacobian at t = 0 is not finite; check the parameters, inputs and initial state."
    rho = float(np.max(np.abs(np.linalg.eigvals(J)), initial=0.0))
    if rho * problem.dt > stability_radius:
        return (f"The largest eigenvalue of the Jacobian at t = 0 has magnitude {rho:.4g} 1/s, so {method} is "
                f"stable only for dt < {stability_radius / rho:.3g} s; reduce dt or use an implicit method "
                "(method='cvodes').")
    return (f"The step is within {method}'s stability limit at t = 0 (|lambda|max dt = {rho * problem.dt:.3g} < "
            f"{stability_radius}): the solution itself may grow without bound, or the rhs may be undefined "
            "(NaN) there; check the model, parameters and inputs.")
