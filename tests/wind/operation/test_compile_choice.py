"""When ``simulate_turbine`` compiles the closed loop by default.

``mbsym.wind.operation.simulation._compile_pays_off``.

The rule: more than ``COMPILE_FROM_SAMPLES`` controller samples, or fewer whose right-hand sides would take longer in
CasADi's virtual machine (one evaluation timed, ``RHS_PER_SAMPLE`` per sample, times the runs) than compiling is
estimated to take. Checked with a stand-in plant whose right-hand side takes a known time and a fixed compile
estimate, so the decision's arithmetic is exact; and with the built-in turbine, whose evaluation is milliseconds.
"""

from __future__ import annotations

import time

import numpy as np
import pytest

from mbsym import codegen
from mbsym.wind.operation import simulation as sim


class _SlowPlant:
    """A right-hand side of ``seconds`` per evaluation."""

    n_u = 1

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds

    def rhs(self, x, u, p):
        time.sleep(self.seconds)
        return x

    def parameter_vector(self, p):
        return np.zeros(0)


@pytest.fixture
def compiler_here(monkeypatch):
    monkeypatch.setattr(codegen, "compiler_command", lambda *a, **k: "cc")
    monkeypatch.setattr(codegen, "compile_disabled", lambda: False)
    monkeypatch.setattr(codegen, "estimate_compile_seconds", lambda f: 1.0)


def test_a_slow_plant_compiles_short_runs(compiler_here):
    plant = _SlowPlant(0.02)                     # 0.08 s per sample in the virtual machine; compiling 1 s
    assert sim._compile_pays_off(plant, 20, np.zeros(2), None)            # ~1.6 s > 1 s
    assert not sim._compile_pays_off(plant, 5, np.zeros(2), None)         # ~0.4 s < 1 s
    assert sim._compile_pays_off(plant, 5, np.zeros(2), None, runs=4)     # a sweep's four cases: ~1.6 s


def test_many_samples_compile_without_timing(compiler_here):
    plant = _SlowPlant(10.0)                     # would take 10 s if it were timed
    t0 = time.perf_counter()
    assert sim._compile_pays_off(plant, sim.COMPILE_FROM_SAMPLES + 1, np.zeros(2), None)
    assert time.perf_counter() - t0 < 1.0


def test_no_compiler_no_compilation(monkeypatch):
    monkeypatch.setattr(codegen, "compiler_command", lambda *a, **k: None)
    assert not sim._compile_pays_off(_SlowPlant(0.0), 1e9, np.zeros(2), None)


def test_the_builtin_turbine_keeps_short_runs_in_the_virtual_machine():
    # the NREL 5 MW with three DOFs: ~1 ms per evaluation against ~15 s of compiling: 600 samples stay in the VM
    from mbsym.wind.operation.deck import builtin_deck

    if codegen.compiler_command() is None or codegen.compile_disabled():
        pytest.skip("no compiler: nothing is compiled anyway")
    model = builtin_deck().model()
    dyn = model.dynamics()
    x0 = dyn.state_vector(model.initial_state(10.0))
    assert not sim._compile_pays_off(dyn, 600, x0, None)
