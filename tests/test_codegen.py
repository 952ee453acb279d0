"""Compiled evaluation (mbsym.codegen): values, the disk cache and its size bound, the fallback without a compiler.

References: CasADi's own virtual machine evaluating the same Function (the generated C must
reproduce it to round-off), and the simulation results of the virtual machine.
"""

import os
import platform
import shutil
import time
import warnings

import casadi as ca
import numpy as np
import pytest

from mbsym.codegen import (COMPILE_TIMEOUT_S, DEFAULT_FLAGS, CompilationWarning, cache_dir, clear_disk_cache,
                           compile_function, compiler_command, find_compiler, function_key)
from mbsym.codegen_cache import DEFAULT_LIMIT_MB, limit_bytes, prune, usage
from mbsym.exceptions import OptionError
from mbsym.simulate import METHODS, clear_cache, simulate

#: Methods for any model (rk4-held needs dynamics with a held part: tests/simulate/test_held_rk4.py).
GENERIC = [m for m in METHODS if not METHODS[m].needs_held]

needs_cc = pytest.mark.skipif(find_compiler() is None, reason="no C compiler on this machine")


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """Every test compiles into its own empty cache (never the user's ~/.cache/mbsym)."""
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("MBSYM_NO_COMPILE", raising=False)
    monkeypatch.delenv("MBSYM_CC", raising=False)
    monkeypatch.delenv("MBSYM_CACHE_MAX_MB", raising=False)
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
    assert clear_disk_cache() == 1 and not first.library.exists()


@needs_cc
def test_long_compilations_are_announced(monkeypatch):
    # Within `announcing`, a compilation estimated beyond ANNOUNCE_FROM_S is said before it starts (the threshold
    # lowered to below any estimate here); a library found in the disk cache is not announced, nor anything outside.
    import mbsym.codegen as codegen

    monkeypatch.setattr(codegen, "ANNOUNCE_FROM_S", -1.0)
    said = []
    with codegen.announcing(said.append):
        compile_function(_nonlinear())
        compile_function(_nonlinear())                     # the cached library: nothing to say
    assert said == [f"compiling nonlinear_test to C (~{codegen.estimate_compile_seconds(_nonlinear()):.0f} s "
                    "estimated, once: cached on disk)"]
    clear_disk_cache()
    compile_function(_nonlinear())
    assert len(said) == 1


def test_key_covers_graph_flags_and_compiler():
    f = _nonlinear()
    x = ca.SX.sym("x")
    other = ca.Function("nonlinear_test", [x], [2 * x])
    assert function_key(f, ("-O1",), "/usr/bin/gcc") == function_key(_nonlinear(), ("-O1",), "/usr/bin/gcc")
    assert function_key(f, ("-O1",), "/usr/bin/gcc") != function_key(f, ("-O2",), "/usr/bin/gcc")
    assert function_key(f, ("-O1",), "/usr/bin/gcc") != function_key(other, ("-O1",), "/usr/bin/gcc")
    assert function_key(f, ("-O1",), "/usr/bin/gcc") != function_key(f, ("-O1",), "/usr/bin/cc")
    # every word of the command counts ("gcc -DFOO" used to share entries with "gcc")
    assert function_key(f, ("-O1",), "/usr/bin/gcc -DFOO") != function_key(f, ("-O1",), "/usr/bin/gcc")
    assert function_key(f, ("-O1",), "/usr/bin/gcc -DFOO") == function_key(f, ("-O1",), ("/usr/bin/gcc", "-DFOO"))


def test_key_covers_the_platform(monkeypatch):
    f = _nonlinear()
    key = function_key(f, ("-O1",), "/usr/bin/gcc")
    monkeypatch.setattr(platform, "machine", lambda: "other-machine")
    assert function_key(f, ("-O1",), "/usr/bin/gcc") != key


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
    """MBSYM_NO_COMPILE is checked before any work: the Function is not even serialized."""
    monkeypatch.setenv("MBSYM_NO_COMPILE", "1")
    f = _nonlinear()

    def no_serialize(*args, **kwargs):
        raise AssertionError("serialize() called although compilation is off")

    monkeypatch.setattr(ca.Function, "serialize", no_serialize)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = compile_function(f)
    assert not c.compiled and c.function is f and "MBSYM_NO_COMPILE" in c.message


@needs_cc
@pytest.mark.skipif(shutil.which("env") is None, reason="needs env as a compiler wrapper")
def test_compiler_command_of_several_words(monkeypatch):
    """MBSYM_CC = "env <cc>" (as "ccache gcc"): the whole command runs (running "env -O1 ..." failed) and
    the library is cached under its own key, not the plain compiler's."""
    plain, cc = compile_function(_nonlinear()), find_compiler()
    monkeypatch.setenv("MBSYM_CC", f"env {cc}")
    assert compiler_command() == (shutil.which("env"), cc)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        wrapped = compile_function(_nonlinear())
    assert wrapped.compiled and not wrapped.cache_hit and wrapped.key != plain.key
    x, p = np.array([0.3, -0.2, 0.5]), np.array([1.5, 0.7])
    for a, b in zip(plain.function(x, p), wrapped.function(x, p)):
        np.testing.assert_array_equal(np.array(a), np.array(b))


@needs_cc
def test_library_that_does_not_load_is_rebuilt():
    """A truncated library at the cache path (an interrupted copy, another ABI): deleted, rebuilt once,
    no warning; values as the virtual machine's."""
    f = _nonlinear()
    key = function_key(f, DEFAULT_FLAGS, compiler_command())
    library = cache_dir() / f"{f.name()}_{key[:20]}.so"
    library.parent.mkdir(parents=True)
    library.write_bytes(b"\x7fELF truncated")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        c = compile_function(f)
    assert c.compiled and not c.cache_hit and c.library == library and library.stat().st_size > 100
    x, p = np.array([0.3, -0.2, 0.5]), np.array([1.5, 0.7])
    for a, b in zip(f(x, p), c.function(x, p)):
        np.testing.assert_allclose(np.array(b), np.array(a), rtol=1e-14, atol=1e-15)


def test_clear_disk_cache_removes_stale_build_directories():
    """Build directories older than the compile timeout are left-overs of interrupted builds; a fresh one
    may belong to a build running in another process and stays."""
    folder = cache_dir()
    stale, fresh = folder / "mbsym_cg_stale", folder / "mbsym_cg_fresh"
    for d in (stale, fresh):
        d.mkdir(parents=True)
        (d / "f.c").write_text("int x;")
    (folder / "f_0123.so").write_bytes(b"")
    old = time.time() - 2 * COMPILE_TIMEOUT_S
    os.utime(stale, (old, old))
    assert clear_disk_cache() == 1
    assert not stale.exists() and fresh.exists() and not (folder / "f_0123.so").exists()


@needs_cc
@pytest.mark.parametrize("method", GENERIC)
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
@pytest.mark.parametrize("method", ["rk4", "cvodes", "scipy-radau"])
def test_second_preparation_loads_from_disk_and_is_identical(method):
    """Cache reuse across preparations: the in-memory cache emptied, the disk cache still holds the
    libraries (statistics: disk_cache_hit); a third run hits the in-memory cache (nothing loaded)."""
    from mbsym.demo import DEMO_PARAMETERS, double_pendulum

    eom = double_pendulum().equations()
    args = (eom, 2.0, [1.0, -0.5, 0.2, 0.0])
    first = simulate(*args, p=DEMO_PARAMETERS, method=method, compile=True)
    clear_cache()
    second = simulate(*args, p=DEMO_PARAMETERS, method=method, compile=True)
    third = simulate(*args, p=DEMO_PARAMETERS, method=method, compile=True)
    assert first.statistics["disk_cache_hit"] is False and not first.statistics["cache_hit"]
    assert second.statistics["disk_cache_hit"] is True and not second.statistics["cache_hit"]
    assert third.statistics["disk_cache_hit"] is None and third.statistics["cache_hit"]
    np.testing.assert_array_equal(second.x, first.x)
    np.testing.assert_array_equal(third.x, first.x)


@needs_cc
@pytest.mark.skipif(shutil.which("env") is None, reason="needs env as a compiler wrapper")
def test_prepared_functions_are_keyed_on_the_compiler(monkeypatch, osc_model):
    """Another compiler command compiles anew (no in-memory hit on the other compiler's Functions)."""
    first = simulate(osc_model, 1.0, x0=[0.1, 0.0], method="rk4", compile=True)
    monkeypatch.setenv("MBSYM_CC", f"env {find_compiler()}")
    other = simulate(osc_model, 1.0, x0=[0.1, 0.0], method="rk4", compile=True)
    assert not other.statistics["cache_hit"] and other.statistics["disk_cache_hit"] is False
    np.testing.assert_array_equal(other.x, first.x)


@needs_cc
def test_compiled_outputs_equal_the_virtual_machine(osc_model):
    """Model outputs through the mapped, compiled output Function: equal to the VM's to round-off."""
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 0), ca.SX.sym("p", 0)
    f = ca.Function("y", [x, u, p], [ca.vertcat(ca.sin(x[0]), x[0] * x[1]), x[1] ** 2])

    class Model:
        eom = osc_model
        output_names = ("s", "xv", "v2")

        def output_function(self):
            return f

    vm = simulate(Model(), 1.0, x0=[0.1, 0.0], method="rk4")
    cc = simulate(Model(), 1.0, x0=[0.1, 0.0], method="rk4", compile=True)
    np.testing.assert_allclose(cc.y, vm.y, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(vm.output("xv"), vm.state("x") * vm.state("x_d"), rtol=1e-14)


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
    with pytest.raises(TypeError, match="compile must be True, False or None"):
        simulate(osc_model, 1.0, compile="yes")



_EXTERNAL_C = r"""
typedef double casadi_real;
typedef long long int casadi_int;
static const casadi_int sp[] = {2, 1, 0, 2, 0, 1};
int mbsym_test_ext(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, int mem) {
  const casadi_real* x = arg[0];
  if (!res[0]) return 0;
  res[0][0] = x[0] * x[1] + SHIFT;
  res[0][1] = x[0] - x[1];
  return 0;
}
casadi_int mbsym_test_ext_n_in(void) { return 1; }
casadi_int mbsym_test_ext_n_out(void) { return 1; }
const casadi_int* mbsym_test_ext_sparsity_in(casadi_int i) { return sp; }
const casadi_int* mbsym_test_ext_sparsity_out(casadi_int i) { return sp; }
"""


@needs_cc
def test_registered_c_source_is_compiled_with_a_graph_that_calls_it(tmp_path):
    """A hand-written CasADi External called from SX: compile_function compiles its registered source into the
    same library (reference: the uncompiled graph); editing the source changes the cache key."""
    import subprocess

    from mbsym.codegen import register_c_source, registered_c_sources

    src = tmp_path / "ext.c"
    src.write_text("#define SHIFT 1.5\n" + _EXTERNAL_C)
    lib = tmp_path / "ext.so"
    subprocess.run([find_compiler(), "-shared", "-fPIC", "-o", str(lib), str(src)], check=True)
    ext = ca.external("mbsym_test_ext", str(lib))
    x = ca.SX.sym("x", 2)
    g = ca.Function("calls_ext", [x], [ca.sin(ext(x)) + x])
    register_c_source("mbsym_test_ext", src)
    assert registered_c_sources(g) == [("mbsym_test_ext", src.absolute())]
    c = compile_function(g)
    assert c.compiled and not c.cache_hit
    assert np.allclose(np.array(c.function([0.3, -2.0])), np.array(g([0.3, -2.0])), rtol=0, atol=1e-15)
    key = function_key(g)
    src.write_text("#define SHIFT 2.5\n" + _EXTERNAL_C)
    assert function_key(g) != key
    with pytest.raises(ValueError, match="C identifier"):
        register_c_source("not a name", src)
    with pytest.raises(ValueError, match="not found"):
        register_c_source("mbsym_test_missing", tmp_path / "none.c")


@pytest.mark.skipif(os.name != "posix" or shutil.which("sh") is None or shutil.which("pgrep") is None,
                    reason="process groups, sh and pgrep")
def test_a_compiler_past_its_time_limit_is_killed_with_its_children():
    """``gcc`` stopped at the time limit left ``cc1`` running (14.5 GB, a full core, on a 1385-state model): the
    whole process group goes now. A shell whose child outlives it stands in for the compiler."""
    import subprocess
    import time

    from mbsym.codegen import _run_compiler

    marker = "31.7391"
    with pytest.raises(subprocess.TimeoutExpired):
        _run_compiler(["sh", "-c", f"sleep {marker} & wait"], 0.5)
    time.sleep(0.2)
    left = subprocess.run(["pgrep", "-f", f"sleep {marker}"], capture_output=True, text=True)
    assert left.stdout.strip() == ""
    assert _run_compiler(["sh", "-c", "echo oops >&2; exit 3"], 10.0) == (3, "oops\n")


# ---- the cache's size bound (mbsym.codegen_cache): least recently used first. References: file sizes and
# modification times set here (the order and the bytes pruning must reach are known exactly), and the
# compiler's own libraries for the end-to-end checks.

def _library(folder, name, size, age_s):
    path = folder / name
    path.write_bytes(b"\0" * size)
    t = time.time() - age_s
    os.utime(path, (t, t))
    return path


def test_prune_deletes_least_recently_used_down_to_ninety_percent(tmp_path):
    libs = [_library(tmp_path, f"f{i}_0123.so", 1000, age_s=100 - i) for i in range(10)]     # f0 oldest
    other = _library(tmp_path, "notes.txt", 5000, age_s=1000)
    removed = prune(tmp_path, limit=6000)
    # 10000 bytes above a 6000-byte bound: the oldest go until 5400 (90 %) are left, i.e. five
    assert removed == libs[:5]
    assert [p for _, _, p in usage(tmp_path)] == libs[5:]
    assert other.exists()                      # not a library: never touched
    assert prune(tmp_path, limit=6000) == []   # within the bound: nothing more


def test_prune_keeps_the_library_just_built(tmp_path):
    libs = [_library(tmp_path, f"g{i}.so", 1000, age_s=10 - i) for i in range(3)]
    removed = prune(tmp_path, keep=libs[0], limit=1500)
    assert libs[0].exists() and removed == libs[1:]


def test_stale_build_directories_go_running_ones_stay(tmp_path):
    stale, running = tmp_path / "mbsym_cg_old", tmp_path / "mbsym_cg_new"
    for d in (stale, running):
        d.mkdir()
        (d / "big.c").write_text("int x;")
    t = time.time() - 3600
    os.utime(stale, (t, t))
    prune(tmp_path, limit=1e9, stale_after=1200)
    assert not stale.exists() and running.exists()


def test_limit_from_the_environment(monkeypatch):
    assert limit_bytes() == DEFAULT_LIMIT_MB * 1e6
    monkeypatch.setenv("MBSYM_CACHE_MAX_MB", "250")
    assert limit_bytes() == 250e6
    monkeypatch.setenv("MBSYM_CACHE_MAX_MB", "inf")
    assert limit_bytes() == float("inf")
    for bad in ("0", "-5", "lots", "nan"):
        monkeypatch.setenv("MBSYM_CACHE_MAX_MB", bad)
        with pytest.raises(OptionError, match="MBSYM_CACHE_MAX_MB.*positive number of megabytes"):
            limit_bytes()


def _function(name, k):
    x = ca.SX.sym("x")
    return ca.Function(name, [x], [ca.sin(x) * k + x ** 2])


@needs_cc
def test_compile_function_keeps_the_cache_within_its_bound(monkeypatch, tmp_path):
    first = compile_function(_function("lru_a", 1.0))
    size = first.library.stat().st_size
    monkeypatch.setenv("MBSYM_CACHE_MAX_MB", str(1.5 * size / 1e6))       # room for one library
    second = compile_function(_function("lru_b", 2.0))
    assert second.compiled and second.library.exists()
    assert not first.library.exists()                                        # the least recently used went
    # loading from the cache counts as a use: the loaded library outlives a newer, unused one
    third = compile_function(_function("lru_c", 3.0))
    assert not second.library.exists() and third.library.exists()
    t = time.time() - 100
    os.utime(third.library, (t, t))
    again = compile_function(_function("lru_c", 3.0))
    assert again.cache_hit and again.library.stat().st_mtime > t + 50


@needs_cc
def test_a_bad_bound_is_refused_before_any_work(monkeypatch, tmp_path):
    monkeypatch.setenv("MBSYM_CACHE_MAX_MB", "-1")
    with pytest.raises(OptionError, match="MBSYM_CACHE_MAX_MB"):
        compile_function(_function("lru_bad", 1.0))
    assert not (tmp_path / "cache").exists() or not any((tmp_path / "cache").iterdir())
