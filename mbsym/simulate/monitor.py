"""Observable, interruptible runs: progress reports, Ctrl-C, and bounded resources.

Long runs are integrated in chunks (fixed-step methods: ~:data:`CHUNK_WALL_S` of wall time
each, at multiples of the step, so the result is the same as in one piece). After every
chunk the :class:`RunMonitor` reports progress (``progress=`` of :func:`mbsym.simulate`),
and a Ctrl-C that arrived meanwhile ends the run with :class:`SimulationInterrupted`
("interrupted at t = ... s"), which carries the outputs computed so far. The SUNDIALS
methods (cvodes, adams, idas) run as one call: CasADi stops them within milliseconds of a
Ctrl-C, with the same exception; scipy methods are checked after every step.

Ctrl-C needs SIGINT to reach Python. A process started in the background by a non-interactive
shell (``cmd &`` in a script, ``nohup cmd &``, many CI runners and job schedulers) inherits
SIGINT as *ignored*, and Ctrl-C or ``kill -INT`` then does nothing. For that case
:func:`interruptible` (entered by :func:`mbsym.simulate` for the length of a run) turns SIGTERM
(``kill PID``) into the same interruption while the run is active, when SIGINT is ignored and
SIGTERM has its default action; outside a run, and when SIGINT works, SIGTERM keeps its usual
meaning (the process ends).

Before integrating, :func:`check_resources` estimates the memory of the result (output
times x columns) and the number of steps, and refuses runs beyond :data:`MEMORY_LIMIT_BYTES`
or :data:`MAX_STEPS` with a :class:`~mbsym.exceptions.SimulationOptionError` saying how to
proceed (fewer output times, a shorter run, or a larger step).

:class:`ProgressPrinter` is the reporter of ``mbsym simulate``: on a terminal a bar updated in
place; otherwise (a pipe, a log file) one line every :attr:`ProgressPrinter.interval_s`
seconds (5 s), so that batch jobs show they are alive.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time
from typing import Callable, Iterator, TextIO

import numpy as np

from ..exceptions import SimulationOptionError

__all__ = ["SimulationInterrupted", "RunMonitor", "ProgressPrinter", "check_resources", "interruptible",
           "MEMORY_LIMIT_BYTES", "MAX_STEPS", "CHUNK_WALL_S"]

#: Largest estimated memory of a result (outputs x columns x 8 bytes x copies) [bytes]; above it the run is
#: refused. Override with the environment variable ``MBSYM_MEMORY_LIMIT`` (bytes, e.g. ``8e9``).
MEMORY_LIMIT_BYTES = 2 * 1024 ** 3
#: Largest number of integration steps of a fixed-step run (about an hour at a few microseconds per step).
MAX_STEPS = 2_000_000_000
#: Target wall time of one chunk of a fixed-step run [s] (Ctrl-C and progress are handled between chunks).
CHUNK_WALL_S = 0.2
#: Copies of the output arrays alive at once while a result is assembled (states, interpolation, result).
_COPIES = 3


class SimulationInterrupted(KeyboardInterrupt):
    """A run of :func:`mbsym.simulate` ended by Ctrl-C (a ``KeyboardInterrupt``, so it is not caught by
    ``except Exception``), or by SIGTERM when SIGINT is ignored (see :func:`interruptible`).

    Attributes
    ----------
    t : float
        Simulated time reached [s].
    partial : SimulationResult or None
        The outputs computed before the interruption (output times up to ``t``), when available.
    """

    def __init__(self, t: float, partial=None) -> None:
        super().__init__(f"interrupted at t = {t:.6g} s")
        self.t = float(t)
        self.partial = partial


class RunMonitor:
    """Calls ``progress(t, tmax)`` as an integration advances; says where a Ctrl-C stopped it.

    Parameters
    ----------
    tmax : float
        End time [s].
    progress : callable ``(t, tmax) -> None``, optional
        Called after each chunk with the simulated time reached [s], and once at the end.
    """

    def __init__(self, tmax: float, progress: Callable[[float, float], None] | None = None) -> None:
        self.tmax = float(tmax)
        self.progress = progress
        self.t = 0.0

    def update(self, t: float) -> None:
        """Record that the integration reached ``t`` [s] and report it."""
        self.t = float(t)
        if self.progress is not None:
            self.progress(self.t, self.tmax)


class ProgressPrinter:
    """Progress of a run on a stream (stderr by default): ``__call__(t, tmax)`` as :class:`RunMonitor` expects.

    On a terminal a bar ``[#####.....]  12.00 / 60.00 s`` is redrawn in place; elsewhere a line
    ``mbsym simulate: t = 12.00 / 60.00 s (20 %), 4.1 s elapsed`` is written every ``interval_s``
    seconds, and nothing for runs shorter than that.
    """

    def __init__(self, stream: TextIO | None = None, *, interval_s: float = 5.0, label: str = "mbsym simulate",
                 tty: bool | None = None) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.interval_s = float(interval_s)
        self.label = label
        try:
            self.tty = bool(self.stream.isatty()) if tty is None else tty
        except (AttributeError, ValueError):
            self.tty = False
        self._start = time.perf_counter()
        self._last = self._start
        self._drawn = False

    def __call__(self, t: float, tmax: float) -> None:
        now = time.perf_counter()
        if self.tty:
            done = int(30 * min(t / tmax, 1.0)) if tmax > 0 else 30
            self.stream.write(f"\r[{'#' * done}{'.' * (30 - done)}] {t:8.2f} / {tmax:.2f} s")
            self._drawn = True
            if t >= tmax:
                self.stream.write("\n")
                self._drawn = False
            self.stream.flush()
        elif now - self._last >= self.interval_s and t < tmax:
            self.stream.write(f"{self.label}: t = {t:.2f} / {tmax:.2f} s ({100 * t / tmax:.0f} %), "
                              f"{now - self._start:.1f} s elapsed\n")
            self.stream.flush()
            self._last = now

    def close(self) -> None:
        """End a bar left open (e.g. after an interruption)."""
        if self._drawn:
            self.stream.write("\n")
            self.stream.flush()
            self._drawn = False


def _terminate_as_interrupt(signum, frame) -> None:
    """SIGTERM handler of :func:`interruptible`: the run ends as after a Ctrl-C."""
    raise KeyboardInterrupt


@contextlib.contextmanager
def interruptible() -> Iterator[bool]:
    """Keep a run interruptible when SIGINT cannot reach Python: while the block runs, SIGTERM ends it as
    Ctrl-C would (``KeyboardInterrupt``, hence :class:`SimulationInterrupted`).

    Only when all of these hold: the block runs in the main thread (only there can Python handle signals),
    SIGINT is ignored (``signal.getsignal(SIGINT) is SIG_IGN``: inherited from a non-interactive shell that
    started the process in the background, or set by the program) and SIGTERM has its default action (a
    handler set by the program is left alone). The previous SIGTERM action is restored on leaving. Nested
    blocks keep the outer handler. Yields whether SIGTERM is handled by this block.
    """
    import signal

    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "SIGTERM"):
        yield False
        return
    if signal.getsignal(signal.SIGINT) != signal.SIG_IGN or signal.getsignal(signal.SIGTERM) != signal.SIG_DFL:
        yield False
        return
    try:
        signal.signal(signal.SIGTERM, _terminate_as_interrupt)
    except (ValueError, OSError):           # not allowed here (embedded interpreter): nothing changes
        yield False
        return
    try:
        yield True
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


@contextlib.contextmanager
def sigint_seen() -> Iterator[list]:
    """Record whether SIGINT (Ctrl-C) arrives during the block (CasADi's SUNDIALS interfaces turn it into a
    solver failure without saying so); the previous handler still runs. SIGTERM is recorded the same way
    while :func:`interruptible` handles it; an ignored SIGINT stays ignored. Yields a list, non-empty once
    seen. Outside the main thread (no signal handlers there) nothing is recorded."""
    import signal

    seen: list = []
    if threading.current_thread() is not threading.main_thread():
        yield seen
        return
    signums = [] if signal.getsignal(signal.SIGINT) == signal.SIG_IGN else [signal.SIGINT]
    if hasattr(signal, "SIGTERM") and signal.getsignal(signal.SIGTERM) is _terminate_as_interrupt:
        signums.append(signal.SIGTERM)
    previous = {signum: signal.getsignal(signum) for signum in signums}

    def handler(signum, frame):
        seen.append(time.perf_counter())
        before = previous[signum]
        if callable(before):
            before(signum, frame)
        elif before == signal.SIG_DFL:
            raise KeyboardInterrupt

    installed = []
    try:
        for signum in signums:
            signal.signal(signum, handler)
            installed.append(signum)
    except (ValueError, OSError):           # not allowed here (embedded interpreter): record nothing
        for signum in installed:
            signal.signal(signum, previous[signum])
        yield seen
        return
    try:
        yield seen
    finally:
        for signum in signums:
            signal.signal(signum, previous[signum])


def memory_limit() -> float:
    """:data:`MEMORY_LIMIT_BYTES`, or ``$MBSYM_MEMORY_LIMIT`` [bytes] when set."""
    env = os.environ.get("MBSYM_MEMORY_LIMIT", "").strip()
    if env:
        try:
            value = float(env)
        except ValueError:
            raise SimulationOptionError(f"MBSYM_MEMORY_LIMIT must be a number of bytes; got {env!r}.") from None
        if value > 0:
            return value
    return float(MEMORY_LIMIT_BYTES)


def check_resources(n_out: int, n_columns: int, n_steps: float | None, tmax: float, *,
                    fewer_steps: str = "use a larger step dt") -> float:
    """Refuse runs whose result or step count is beyond the limits; return the estimated result size [bytes].

    Parameters
    ----------
    n_out : int
        Number of output times.
    n_columns : int
        Columns per output time (time, states, inputs, outputs, controller states).
    n_steps : float or None
        Number of integration steps of a fixed-step method (None for adaptive methods).
    tmax : float
        End time [s] (for the message).
    fewer_steps : str, optional, keyword-only
        How to take fewer steps, for the message.

    Raises
    ------
    SimulationOptionError
        Estimated memory above :func:`memory_limit`, or more than :data:`MAX_STEPS` steps.
    """
    need = float(n_out) * n_columns * 8.0 * _COPIES
    limit = memory_limit()
    if need > limit:
        spacing = tmax / max(n_out - 1, 1)
        fit = max(int(limit / (n_columns * 8.0 * _COPIES)), 2)
        raise SimulationOptionError(
            f"the result would hold {n_out:.4g} output times x {n_columns} columns, about {_size(need)} of memory, "
            f"above the limit of {_size(limit)}; space the outputs more widely (dt or t_out: at most {fit:.3g} "
            f"output times, i.e. a spacing of at least {tmax / (fit - 1):.3g} s instead of {spacing:.3g} s), "
            "shorten tmax, or raise the limit with the environment variable MBSYM_MEMORY_LIMIT (bytes).")
    if n_steps is not None and n_steps > MAX_STEPS:
        raise SimulationOptionError(
            f"the run would take {n_steps:.4g} integration steps (more than {MAX_STEPS:.3g}, hours of computing); "
            f"shorten tmax = {tmax:g} s or {fewer_steps}.")
    return need


def _size(n_bytes: float) -> str:
    for unit, scale in (("TiB", 1024 ** 4), ("GiB", 1024 ** 3), ("MiB", 1024 ** 2)):
        if n_bytes >= scale:
            return f"{n_bytes / scale:.3g} {unit}"
    return f"{n_bytes / 1024:.3g} KiB"


def output_count(tmax: float, dt: float) -> float:
    """Number of output times of a uniform grid of spacing ``dt`` over [0, tmax] (as a float: may be huge)."""
    return float(np.floor(tmax / dt + 1e-9)) + 1.0
