"""Compilations started now and waited for at first use: a thread pool in front of :func:`mbsym.codegen.compile_function`.

The C compiler is a subprocess, so several libraries compile at once (one per core) while Python goes on
building the next Functions. :func:`compile_async` returns a :class:`Compilation` at once; its
:meth:`~Compilation.result` waits. The solvers of :mod:`mbsym.control` submit their Functions here
when built and wait only when they first evaluate them, so building an NMPC and an MHE overlaps
their compilations. :func:`pending_compilations` and :func:`wait_for_compilations` let a program say
what it is waiting for (``mbsym simulate`` prints it on stderr).

Before submitting, the disk cache is looked up (:func:`mbsym.codegen.cached_library`): a cached
library is marked as such and has no time estimate. The estimate of a compilation
(:func:`compile_seconds_estimate`) counts the SX instructions of the Functions in the graph.
"""

from __future__ import annotations

import os
import threading
import time
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Callable, Sequence

import casadi as ca

from . import codegen

__all__ = ["Compilation", "compile_async", "pending_compilations", "wait_for_compilations",
           "compile_seconds_estimate"]

#: Calibration of :func:`compile_seconds_estimate` (gcc 12 -O1, one unloaded core): seconds per SX instruction
#: of the generated code, a fixed cost, and the cost of a lookup table's constants (the NREL 5 MW rotor
#: surfaces: 5.5 MB of C). Measured on the turbine estimator's Functions (issue 22 item 8): rhs 2.2k
#: instructions 2.0 s, step Jacobian 17.8k 7.4 s, MHE preparation 25.3k 9.9 s.
S_PER_INSTRUCTION, FIXED_S, TABLE_S = 3.5e-4, 0.3, 1.0

_POOL: ThreadPoolExecutor | None = None
_POOL_LOCK = threading.Lock()
_PENDING: list["Compilation"] = []


def _pool() -> ThreadPoolExecutor:
    global _POOL
    with _POOL_LOCK:
        if _POOL is None:
            _POOL = ThreadPoolExecutor(max_workers=max(1, os.cpu_count() or 1), thread_name_prefix="mbsym-compile")
        return _POOL


def compile_seconds_estimate(f: ca.Function) -> float:
    """Rough wall time [s] of compiling ``f`` at -O1 on one free core (see :data:`S_PER_INSTRUCTION`)."""
    functions = [f, *f.find_functions()]
    instructions = sum(g.n_instructions() for g in functions if g.is_a("SXFunction"))
    tables = any(g.class_name().endswith("Interpolant") for g in functions)
    return FIXED_S + S_PER_INSTRUCTION * instructions + (TABLE_S if tables else 0.0)


@dataclass
class Compilation:
    """A compilation submitted by :func:`compile_async`.

    Attributes
    ----------
    name : str
        The Function's name.
    cached : bool
        The library was in the disk cache when submitted (loading only).
    estimate_s : float
        Expected compile time [s] on a free core (0 when cached).
    future : concurrent.futures.Future
        Of the :class:`~mbsym.codegen.CompiledFunction`.
    """

    name: str
    cached: bool
    estimate_s: float
    future: Future = field(repr=False)

    def done(self) -> bool:
        return self.future.done()

    def result(self) -> "codegen.CompiledFunction":
        """The compiled Function (waits); a failed compilation gives the original Function with a warning."""
        return self.future.result()


def compile_async(f: ca.Function, *, flags: Sequence[str] = codegen.DEFAULT_FLAGS) -> Compilation:
    """Start compiling ``f`` (:func:`mbsym.codegen.compile_function`) in the thread pool; return at once.

    Examples
    --------
    >>> import casadi as ca
    >>> x = ca.SX.sym("x")
    >>> c = compile_async(ca.Function("cube", [x], [x ** 3]))
    >>> float(c.result().function(2.0))
    8.0
    """
    flags = tuple(flags)
    cached = codegen.compile_disabled() or codegen.cached_library(f, flags=flags) is not None
    estimate = 0.0 if cached else compile_seconds_estimate(f)
    future = _pool().submit(codegen.compile_function, f, flags=flags)
    job = Compilation(f.name(), cached, estimate, future)
    with _POOL_LOCK:
        _PENDING[:] = [c for c in _PENDING if not c.done()] + [job]
    return job


def pending_compilations() -> list[Compilation]:
    """Compilations submitted and not finished."""
    with _POOL_LOCK:
        return [c for c in _PENDING if not c.done()]


def wait_for_compilations(report: Callable[[str], None] | None = None, *, interval_s: float = 5.0) -> float:
    """Wait for :func:`pending_compilations`; returns the seconds waited.

    ``report`` (e.g. ``print`` to stderr) gets one line before waiting when something is compiled (not
    only loaded from the cache) — what, how many and the estimate —, one every ``interval_s`` seconds,
    and one at the end.
    """
    t0 = time.perf_counter()
    jobs = pending_compilations()
    compiling = [c for c in jobs if not c.cached]
    if not compiling or report is None:
        for c in jobs:
            c.future.exception()
        return time.perf_counter() - t0
    workers = max(1, min(len(compiling), os.cpu_count() or 1))
    longest = max(c.estimate_s for c in compiling)
    estimate = max(longest, sum(c.estimate_s for c in compiling) / workers)
    names = ", ".join(c.name for c in compiling)
    report(f"compiling {len(compiling)} solver libraries ({names}) with {' '.join(codegen.compiler_command() or ())}"
           f", about {estimate:.0f} s on {workers} core(s) of a free machine; once: they are cached in "
           f"{codegen.cache_dir()}")
    last = t0
    while True:
        left = [c for c in compiling if not c.done()]
        if not left:
            break
        try:
            left[0].future.exception(timeout=max(0.0, last + interval_s - time.perf_counter()))
        except TimeoutError:
            last = time.perf_counter()
            done = sum(c.done() for c in compiling)
            report(f"compiling: {done} of {len(compiling)} done, {last - t0:.0f} s elapsed")
    for c in jobs:
        c.future.exception()
    waited = time.perf_counter() - t0
    report(f"compiled {len(compiling)} libraries in {waited:.1f} s")
    return waited
