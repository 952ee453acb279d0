"""Compiled evaluation (mbsym.codegen): values, the disk cache, the fallback without a compiler.

References: CasADi's own virtual machine evaluating the same Function (the generated C must
reproduce it to round-off), and the simulation results of the virtual machine.
"""

import os
import warnings

import casadi as ca
import numpy as np
import pytest

from mbsym.codegen import (CompilationWarning, clear_disk_cache, compile_function, find_compiler,
                           function_key)
from mbsym.simulate import METHODS, clear_cache, simulate

needs_cc = pytest.mark.skipif(find_compiler() is None, reason="no C compiler on this machine")


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """Every test compiles into its own empty cache (never the user's ~/.cache/mbsym)."""
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("MBSYM_NO_COMPILE", raising=False)
    monkeypatch.delenv("MBSYM_CC", raising=False)
    clear_cache()
    yield
    clear_cache()


def _nonlinear():
    x, p = ca.SX.sym("x", 3), ca.SX.sym("p", 2)
    y = ca.vertcat(ca.sin(x[0]) * p[0] + x[1] ** 3, ca.exp(-x[2] * p[1]) / (1 + x[0] ** 2), ca.atan2(x[1], x[2]))
    return ca.Function("nonlinear_test", [x, p], [y, ca.jacobian(y, x)], ["x", "p"], ["y", "J"])


@needs_cc
def test_compiled_values_equal_the_virtual_machine():
    f = _nonlinear()
    c = compile_function(f)
    assert c.compiled and c.library.exists() and c.function.class_name() == "External"
    rng = np.random.default_rng(1)
    for _ in range(5):
        x, p = rng.normal(size=3), rng.uniform(0.5, 2.0, size=2)
        for a, b in zip(f(x, p), c.function(x, p)):
            np.testing.assert_allclose(np.array(b), np.array(a), rtol=1e-14, atol=1e-15)


@needs_cc
def test_disk_cache_is_reused():
    f = _nonlinear()
    first = compile_function(f)
    second = compile_function(_nonlinear())              # an equal Function built again
    assert not first.cache_hit and second.cache_hit and first.key == second.key
    assert second.library == first.library
    assert second.wall_s < first.wall_s                   # no compiler run
    assert clear_disk_cache() == 1 and not first.library.exists()


def test_key_covers_graph_flags_and_compiler():
    f = _nonlinear()
    x = ca.SX.sym("x")
    other = ca.Function("nonlinear_test", [x], [2 * x])
    assert function_key(f, ("-O1",), "/usr/bin/gcc") == function_key(_nonlinear(), ("-O1",), "/usr/bin/gcc")
    assert function_key(f, ("-O1",), "/usr/bin/gcc") != function_key(f, ("-O2",), "/usr/bin/gcc")
    assert function_key(f, ("-O1",), "/usr/bin/gcc") != function_key(other, ("-O1",), "/usr/bin/gcc")
    assert function_key(f, ("-O1",), "/usr/bin/gcc") != function_key(f, ("-O1",), "/usr/bin/cc")


def test_no_compiler_falls_back_with_a_warning(monkeypatch):
    monkeypatch.setenv("MBSYM_CC", "no-such-compiler-mbsym")
    f = _nonlinear()
    with pytest.warns(CompilationWarning, match="No C compiler found"):
        c = compile_function(f)
    assert not c.compiled and c.function is f and c.library is None


@pytest.mark.skipif(not os.path.exists("/bin/false"), reason="needs /bin/false as a failing compiler")
def test_failed_compilation_falls_back_with_a_warning():
    with pytest.warns(CompilationWarning, match="failed"):
        c = compile_function(_nonlinear(), compiler="/bin/false")
    assert not c.compiled


def test_compilation_can_be_switched_off(monkeypatch):
    monkeypatch.setenv("MBSYM_NO_COMPILE", "1")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = compile_function(_nonlinear())
    assert not c.compiled and "MBSYM_NO_COMPILE" in c.message


@needs_cc
@pytest.mark.parametrize("method", list(METHODS))
def test_simulate_compiled_equals_virtual_machine(method):
    """The double pendulum (nonlinear, mbsym.demo): compiled and VM runs agree to round-off (fixed
    step: 1e-11), or within the tolerance for adaptive methods at rtol = 1e-8, whose step control may
    react to the last bits (cvodes: 638 vs 644 steps, 2e-7 apart; bound 100 rtol = 1e-6)."""
    from mbsym.demo import DEMO_PARAMETERS, double_pendulum

    eom = double_pendulum().equations()
    kw = {"dt": 0.01} if METHODS[method].kind == "fixed-step" else {"rtol": 1e-8, "atol": 1e-10}
    vm = simulate(eom, 3.0, [1.0, -0.5, 0.2, 0.0], p=DEMO_PARAMETERS, method=method, **kw)
    cc = simulate(eom, 3.0, [1.0, -0.5, 0.2, 0.0], p=DEMO_PARAMETERS, method=method, compile=True, **kw)
    assert cc.statistics["compiled"] and not vm.statistics["compiled"]
    bound = 1e-11 if METHODS[method].kind == "fixed-step" else 1e-6
    np.testing.assert_allclose(cc.x, vm.x, rtol=0, atol=bound)


@needs_cc
def test_second_preparation_is_faster_and_identical():
    """Cache reuse across preparations: the in-memory cache emptied, the disk cache still holds the library."""
    from mbsym.demo import DEMO_PARAMETERS, double_pendulum

    eom = double_pendulum().equations()
    args = (eom, 2.0, [1.0, -0.5, 0.2, 0.0])
    first = simulate(*args, p=DEMO_PARAMETERS, method="rk4", compile=True)
    clear_cache()
    second = simulate(*args, p=DEMO_PARAMETERS, method="rk4", compile=True)
    assert second.statistics["prepare_wall_s"] < first.statistics["prepare_wall_s"]
    np.testing.assert_array_equal(second.x, first.x)


def test_simulate_without_compiler_warns_and_uses_the_virtual_machine(monkeypatch, osc_model):
    monkeypatch.setenv("MBSYM_CC", "no-such-compiler-mbsym")
    with pytest.warns(CompilationWarning):
        res = simulate(osc_model, 1.0, x0=[0.1, 0.0], method="rk4", compile=True)
    ref = simulate(osc_model, 1.0, x0=[0.1, 0.0], method="rk4")
    assert not res.statistics["compiled"]
    np.testing.assert_array_equal(res.x, ref.x)


@pytest.fixture
def osc_model():
    """Mass-spring on a prismatic joint, m = 2 kg, k = 50 N/m."""
    import mbsym as mb

    sys = mb.System()
    x = sys.coordinates("x")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("mass", 2.0), axis=[1, 0, 0], coordinate=x))
    sys.add_spring(x, 50.0)
    return sys.equations(name="codegen_oscillator")


def test_compile_must_be_bool(osc_model):
    with pytest.raises(TypeError, match="compile must be True or False"):
        simulate(osc_model, 1.0, compile="yes")

