"""Bounded resources and observable long runs (issue 11.3-11.4): refused before any work, interruptible,
reporting progress, and chunked without changing the result.

The checks are exact (typed errors, bitwise equality of chunked and one-piece runs) or timed with generous
bounds for a loaded 2-core machine (Ctrl-C must end a run within a second; asserted below 3 s).

Tests that send signals make sure they can arrive (the ``sigint_delivered`` / ``sigint_ignored`` fixtures of
conftest.py) and bound their own "long run" to about 20 s of wall time (:func:`long_run_tmax`), so that an
interruption that is not honoured fails the test within seconds instead of running for hours.
"""

import io
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from mbsym.simulate import ProgressPrinter, SimulationInterrupted, SimulationOptionError, simulate
from mbsym.simulate import fixed, monitor

from .conftest import pendulum


@pytest.mark.parametrize("kwargs, match", [
    ({"tmax": 1e12, "method": "rk4"}, r"output times .* above the limit .* space the outputs more widely"),
    ({"tmax": 1e12}, r"above the limit"),
    ({"tmax": 1e12, "method": "cvodes", "dt": 1e-3}, r"above the limit"),
    ({"tmax": 60.0, "t_out": None, "method": "rk4", "dt": 1e-9}, r"above the limit"),
    ({"tmax": 1e12, "method": "rk4", "t_out": [0.0, 1e12]}, r"integration steps .* shorten tmax"),
])
def test_oversized_runs_are_refused_before_any_work(osc, kwargs, match):
    t0 = time.perf_counter()
    with pytest.raises(SimulationOptionError, match=match):
        simulate(osc, x0=[0.1, 0.0], **kwargs)
    assert time.perf_counter() - t0 < 2.0


def test_memory_limit_can_be_raised(osc, monkeypatch):
    t_out = np.linspace(0.0, 1.0, 20001)
    monkeypatch.setenv("MBSYM_MEMORY_LIMIT", "1e5")
    with pytest.raises(SimulationOptionError, match="MBSYM_MEMORY_LIMIT"):
        simulate(osc, 1.0, x0=[0.1, 0.0], t_out=t_out)
    monkeypatch.setenv("MBSYM_MEMORY_LIMIT", "1e9")
    assert simulate(osc, 1.0, x0=[0.1, 0.0], t_out=t_out).t.size == 20001
    monkeypatch.setenv("MBSYM_MEMORY_LIMIT", "lots")
    with pytest.raises(SimulationOptionError, match="number of bytes"):
        simulate(osc, 1.0, x0=[0.1, 0.0], t_out=t_out)


@pytest.mark.parametrize("kwargs, match", [
    ({"rtol": 10.0, "method": "cvodes"}, "must be below 1"),
    ({"rtol": 1.0}, "must be below 1"),
])
def test_relative_tolerance_below_one(osc, kwargs, match):
    with pytest.raises(SimulationOptionError, match=match):
        simulate(osc, 1.0, **kwargs)


@pytest.mark.parametrize("tmax", [np.inf, np.nan, 0.0])
def test_tmax_must_be_finite_and_positive(osc, tmax):
    with pytest.raises(SimulationOptionError, match="tmax"):
        simulate(osc, tmax)


def test_chunked_run_equals_one_piece(monkeypatch):
    pend = pendulum()
    kw = dict(x0=[1.0, 0.0], method="rk4", dt=1e-3, t_out=np.linspace(0.0, 20.0, 777))
    one = simulate(pend, 20.0, **kw)
    monkeypatch.setattr(fixed, "CHUNK_WALL_S", 1e-4)          # many chunks of 64-4096 steps
    seen = []
    many = simulate(pend, 20.0, progress=lambda t, tmax: seen.append(t), **kw)
    np.testing.assert_array_equal(many.x, one.x)
    assert len(seen) > 3 and seen == sorted(seen) and seen[-1] == 20.0


def test_progress_printer_lines_when_not_a_terminal():
    out = io.StringIO()
    printer = ProgressPrinter(out, interval_s=0.0, tty=False)
    for t in (1.0, 2.0, 3.0):
        printer(t, 4.0)
    printer(4.0, 4.0)                                            # the end: no line
    lines = out.getvalue().splitlines()
    assert lines == [f"mbsym simulate: t = {t:.2f} / 4.00 s ({25 * t:.0f} %), " + ln.split("), ")[1]
                     for t, ln in zip((1.0, 2.0, 3.0), lines)]
    quiet = io.StringIO()
    slow = ProgressPrinter(quiet, interval_s=60.0, tty=False)
    slow(1.0, 4.0)
    assert quiet.getvalue() == ""                                # short runs stay silent


def test_progress_printer_bar_on_a_terminal():
    out = io.StringIO()
    printer = ProgressPrinter(out, tty=True)
    printer(1.0, 4.0)
    printer(4.0, 4.0)
    text = out.getvalue()
    assert text.startswith("\r[#######") and text.endswith("4.00 / 4.00 s\n")


def _interrupt_after(seconds, signum=signal.SIGINT):
    def fire():
        time.sleep(seconds)
        os.kill(os.getpid(), signum)
    threading.Thread(target=fire, daemon=True).start()


#: Wall time an uninterrupted "long run" of these tests takes [s]: 40 times the 0.5 s after which the signal is
#: sent, so that the signal falls well inside the run on any machine, and short enough that a signal that is not
#: honoured fails the test (the run ends without SimulationInterrupted) within seconds instead of hours.
LONG_RUN_WALL_S = 20.0
#: Simulated time of the calibration run per method [s]: a few tenths of a second of wall time here.
CALIBRATION_S = {"rk4": 5.0, "cvodes": 300.0, "scipy-radau": 5.0}


def long_run_tmax(model, method, **kw):
    """End time [s] of a run of about :data:`LONG_RUN_WALL_S` on this machine (a multiple of 10 s, at most
    1e5 s), from the wall time of a short run with the same options (after a first call that builds and caches
    the integrator, so that the calibration measures integration only)."""
    simulate(model, 0.1, x0=[1.0, 0.0], method=method, **kw)
    t_cal = CALIBRATION_S[method]
    t0 = time.perf_counter()
    simulate(model, t_cal, x0=[1.0, 0.0], method=method, **kw)
    rate = t_cal / max(time.perf_counter() - t0, 1e-3)          # simulated seconds per wall second
    return float(min(1e5, 10.0 * np.ceil(rate * LONG_RUN_WALL_S / 10.0)))


LONG_RUN_OPTIONS = {"rk4": dict(dt=1e-4), "cvodes": dict(rtol=1e-12, atol=1e-14), "scipy-radau": dict(rtol=1e-10)}


@pytest.mark.parametrize("method", ["rk4", "cvodes", "scipy-radau"])
def test_ctrl_c_ends_a_long_run_within_a_second(method, sigint_delivered):
    """SIGINT during a run that would take ~20 s: SimulationInterrupted (a KeyboardInterrupt) soon after."""
    import scipy.integrate  # noqa: F401 - imported on first use by scipy-radau: not inside the timed window

    pend = pendulum()
    kw = LONG_RUN_OPTIONS[method]
    tmax = long_run_tmax(pend, method, **kw)
    _interrupt_after(0.5)
    t0 = time.perf_counter()
    with pytest.raises(SimulationInterrupted, match=r"interrupted at t = [0-9.e+]+ s") as info:
        simulate(pend, tmax, x0=[1.0, 0.0], method=method, t_out=np.linspace(0.0, tmax, 1001), **kw)
    elapsed = time.perf_counter() - t0
    assert elapsed < 3.0, elapsed
    assert isinstance(info.value, KeyboardInterrupt) and 0.0 <= info.value.t < tmax


def test_interrupted_run_carries_the_outputs_so_far(monkeypatch, sigint_delivered):
    monkeypatch.setattr(fixed, "CHUNK_WALL_S", 0.01)
    pend = pendulum()
    tmax = long_run_tmax(pend, "rk4", dt=1e-4)
    _interrupt_after(0.8)
    with pytest.raises(SimulationInterrupted) as info:
        simulate(pend, tmax, x0=[1.0, 0.0], method="rk4", dt=1e-4, t_out=np.linspace(0.0, tmax, int(tmax) + 1))
    partial = info.value.partial
    if partial is not None:                                    # the first output lies past t reached otherwise
        assert partial.t[-1] <= info.value.t and partial.x.shape == (partial.t.size, 2)
        assert partial.statistics["message"] == "interrupted"


def test_ctrl_c_while_preparing_is_an_interruption_at_the_start(monkeypatch):
    """A Ctrl-C before the integration starts (here while the step is compiled, seconds with an empty compile
    cache) is the same SimulationInterrupted, at t = 0 s, not a bare KeyboardInterrupt from inside mbsym."""
    from mbsym.simulate import base

    def interrupted_compiler(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(base, "maybe_compile", interrupted_compiler)
    with pytest.raises(KeyboardInterrupt) as info:                # a bare one must not end the whole session
        simulate(pendulum(), 1.0, x0=[1.0, 0.0], method="rk4", dt=1e-3, compile=True)   # a new model: not prepared
    assert isinstance(info.value, SimulationInterrupted), repr(info.value)
    assert str(info.value) == "interrupted at t = 0 s" and info.value.t == 0.0 and info.value.partial is None


def test_sigterm_is_left_alone_while_sigint_works(sigint_delivered):
    """SIGINT delivered: a run does not touch SIGTERM (it keeps ending the process)."""
    with monitor.interruptible() as handled:
        assert not handled and signal.getsignal(signal.SIGTERM) == signal.SIG_DFL


def test_sigterm_interrupts_only_during_a_run_when_sigint_is_ignored(sigint_ignored):
    """SIGINT ignored: SIGTERM raises KeyboardInterrupt inside the block only, and a program's own SIGTERM
    handler is never replaced. (No signal is sent here; the subprocess tests below send them.)"""
    if signal.getsignal(signal.SIGTERM) != signal.SIG_DFL:
        pytest.skip("this test process handles SIGTERM itself")
    with monitor.interruptible() as handled:
        assert handled and signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL
        with monitor.interruptible() as inner:                  # nested: the outer handler stays
            assert not inner
        with pytest.raises(KeyboardInterrupt):
            signal.getsignal(signal.SIGTERM)(signal.SIGTERM, None)
    assert signal.getsignal(signal.SIGTERM) == signal.SIG_DFL

    def own(signum, frame):
        pass

    signal.signal(signal.SIGTERM, own)
    try:
        with monitor.interruptible() as handled:
            assert not handled and signal.getsignal(signal.SIGTERM) is own
    finally:
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


#: A run in a child process that inherits SIGINT as ignored: it prints "ready" before the long run, then
#: "interrupted <t> <tmax> <SIGTERM restored>" on SimulationInterrupted, or "finished" (exit 1) after the whole run.
SIGTERM_CHILD = """
import signal, sys
import numpy as np
sys.path.insert(0, {tests!r})
from simulate.conftest import pendulum
from simulate.test_limits import LONG_RUN_OPTIONS, long_run_tmax
from mbsym.simulate import SimulationInterrupted, simulate

assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN, "SIGINT should be inherited as ignored"
method = {method!r}
pend = pendulum()
kw = LONG_RUN_OPTIONS[method]
tmax = long_run_tmax(pend, method, **kw)
print("ready", flush=True)
try:
    simulate(pend, tmax, x0=[1.0, 0.0], method=method, t_out=np.linspace(0.0, tmax, 1001), **kw)
except SimulationInterrupted as exc:
    print("interrupted", exc.t, tmax, signal.getsignal(signal.SIGTERM) == signal.SIG_DFL, flush=True)
    sys.exit(0)
print("finished", flush=True)
sys.exit(1)
"""


@pytest.mark.parametrize("method", ["rk4", "cvodes", "scipy-radau"])
def test_sigterm_ends_a_long_run_when_sigint_is_ignored(method, sigint_ignored):
    """A process started in the background by a script (SIGINT ignored): SIGTERM during a ~20 s run ends it with
    SimulationInterrupted within seconds, and SIGTERM has its default action again afterwards. Bounded: the child
    is killed if it has not ended 60 s after the signal."""
    tests = str(Path(__file__).resolve().parents[1])
    proc = subprocess.Popen([sys.executable, "-c", SIGTERM_CHILD.format(tests=tests, method=method)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()                              # ends at "ready" or when the child exits
        assert line.strip() == "ready", line + proc.stderr.read()
        time.sleep(0.5)
        t0 = time.perf_counter()
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=60)
        elapsed = time.perf_counter() - t0
    finally:
        proc.kill()
        proc.wait()
    assert proc.returncode == 0, (proc.returncode, out, err)       # -15: killed by SIGTERM, 1: not interrupted
    word, t, tmax, restored = out.split()
    assert word == "interrupted" and 0.0 <= float(t) < float(tmax) and restored == "True", out
    assert elapsed < 5.0, elapsed                                  # the child's exit included


def test_limits_are_documented_constants():
    assert monitor.MEMORY_LIMIT_BYTES == 2 * 1024 ** 3 and monitor.MAX_STEPS >= 1e9
