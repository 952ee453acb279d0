"""Bounded resources and observable long runs (issue 11.3-11.4): refused before any work, interruptible,
reporting progress, and chunked without changing the result.

The checks are exact (typed errors, bitwise equality of chunked and one-piece runs) or timed with generous
bounds for a loaded 2-core machine (Ctrl-C must end a run within a second; asserted below 3 s).
"""

import io
import os
import signal
import threading
import time

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


def _interrupt_after(seconds):
    def fire():
        time.sleep(seconds)
        os.kill(os.getpid(), signal.SIGINT)
    threading.Thread(target=fire, daemon=True).start()


@pytest.mark.parametrize("method", ["rk4", "cvodes", "scipy-radau"])
def test_ctrl_c_ends_a_long_run_within_a_second(method):
    """SIGINT during a run that would take minutes: SimulationInterrupted (a KeyboardInterrupt) soon after."""
    import scipy.integrate  # noqa: F401 - imported on first use by scipy-radau: not inside the timed window

    pend = pendulum()
    kw = {"rk4": dict(dt=1e-4), "cvodes": dict(rtol=1e-12, atol=1e-14), "scipy-radau": dict(rtol=1e-10)}[method]
    simulate(pend, 0.1, x0=[1.0, 0.0], method=method, **kw)          # prepared Functions cached
    _interrupt_after(0.5)
    t0 = time.perf_counter()
    with pytest.raises(SimulationInterrupted, match=r"interrupted at t = [0-9.e+]+ s") as info:
        simulate(pend, 1e5, x0=[1.0, 0.0], method=method, t_out=np.linspace(0.0, 1e5, 1001), **kw)
    elapsed = time.perf_counter() - t0
    assert elapsed < 3.0, elapsed
    assert isinstance(info.value, KeyboardInterrupt) and 0.0 <= info.value.t < 1e5


def test_interrupted_run_carries_the_outputs_so_far(monkeypatch):
    monkeypatch.setattr(fixed, "CHUNK_WALL_S", 0.01)
    pend = pendulum()
    simulate(pend, 0.1, x0=[1.0, 0.0], method="rk4", dt=1e-4)
    _interrupt_after(0.8)
    with pytest.raises(SimulationInterrupted) as info:
        simulate(pend, 1e5, x0=[1.0, 0.0], method="rk4", dt=1e-4, t_out=np.linspace(0.0, 1e5, 100001))
    partial = info.value.partial
    if partial is not None:                                    # the first output lies past t reached otherwise
        assert partial.t[-1] <= info.value.t and partial.x.shape == (partial.t.size, 2)
        assert partial.statistics["message"] == "interrupted"


def test_limits_are_documented_constants():
    assert monitor.MEMORY_LIMIT_BYTES == 2 * 1024 ** 3 and monitor.MAX_STEPS >= 1e9
