"""FullFieldWind in CasADi: the generated C External, the numpy Callback fallback, compiled graphs calling it.

References: :meth:`FullFieldWind.velocity` (numpy; itself checked against OpenFAST in
test_wind_full_field.py) for both CasADi forms, and CasADi's virtual machine for the compiled graph.
The C code repeats the numpy operations in float64 on the same float32 data, so the two agree to
round-off (1e-12 relative; in practice bit for bit).
"""

from __future__ import annotations

import warnings

import casadi as ca
import numpy as np
import pytest

from mbsym import codegen
from mbsym.codegen import CompilationWarning, compile_function, find_compiler
from mbsym.wind.inflow import read_turbsim_bts

from .ifw_reference import CASES, DATA

needs_cc = pytest.mark.skipif(find_compiler() is None, reason="no C compiler on this machine")


@pytest.fixture(autouse=True)
def private_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "ff_cache"))
    monkeypatch.delenv("MBSYM_NO_COMPILE", raising=False)
    monkeypatch.delenv("MBSYM_CC", raising=False)


@pytest.fixture(scope="module")
def field():
    """The periodic TurbSim field with tower points (data/), rotated as InflowWind's box."""
    return read_turbsim_bts(DATA / "tower_periodic.bts").with_rotation(0.2, 0.03)


def _points_and_times():
    pts = np.array(CASES["tower_periodic"]["points"])          # grid, tower, ground, tolerance, upwind points
    return pts, np.array([0.0, 0.37, 7.91, 19.99, 23.456, 61.0])


def _numbers(f, t, pts):
    return np.array(f(t, pts.T)).T


@needs_cc
def test_compiled_external_equals_numpy(field):
    pts, times = _points_and_times()
    f = field.casadi_function(pts.shape[0])
    assert f.class_name() == "External" and f.name().startswith("ffwind_")
    assert f.name_in() == ["t", "xyz"] and f.name_out() == ["uvw"] and f.size_in(1) == (3, 9)
    for t in times:
        ref = field.velocity(t, pts)
        assert np.abs(_numbers(f, t, pts) - ref).max() <= 1e-12 * np.abs(ref).max()


def test_callback_fallback_equals_numpy(field, monkeypatch):
    monkeypatch.setenv("MBSYM_NO_COMPILE", "1")
    pts, times = _points_and_times()
    with warnings.catch_warnings():
        warnings.simplefilter("error", CompilationWarning)       # MBSYM_NO_COMPILE: no warning
        f = field.casadi_function(pts.shape[0])
    assert f.class_name() != "External"
    for t in times:
        assert np.array_equal(_numbers(f, t, pts), field.velocity(t, pts))


def test_no_compiler_warns_and_falls_back(field, monkeypatch):
    monkeypatch.setenv("MBSYM_CC", "no-such-compiler-mbsym")
    with pytest.warns(CompilationWarning, match="No C compiler"):
        f = field.casadi_function(2)
    pts = np.array([[0.0, 1.0, 50.0], [3.0, -2.0, 100.0]])
    assert np.array_equal(_numbers(f, 4.2, pts), field.velocity(4.2, pts))


@needs_cc
def test_outside_the_grid_makes_casadi_raise(field):
    f = field.casadi_function(1)
    with pytest.raises(RuntimeError, match="Evaluation failed"):
        f(1.0, ca.DM([0.0, 0.0, 500.0]))


@needs_cc
def test_missing_data_file_makes_casadi_raise(tmp_path, monkeypatch):
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path / "own"))
    g = read_turbsim_bts(DATA / "tower_periodic.bts").with_rotation(0.0, 0.0123)    # a field of its own
    f = g.casadi_function(1)
    for data in (tmp_path / "own" / "fullfield").glob("*.f32"):
        data.unlink()
    with pytest.raises(RuntimeError, match="Evaluation failed"):
        f(1.0, ca.DM([0.0, 0.0, 90.0]))


@needs_cc
def test_graph_calling_the_external_compiles_and_agrees(field):
    """An SX graph calling the External, compiled by compile_function with the field's C source."""
    pts, times = _points_and_times()
    n = pts.shape[0]
    t, x = ca.SX.sym("t"), ca.SX.sym("x", 3, n)
    wind = field.casadi_function(n)
    g = ca.Function("rotor_wind_test", [t, x], [ca.sum2(wind(t, x)) * 0.5 + t, wind(t, x) ** 2])
    compiled = compile_function(g)
    assert compiled.compiled, compiled.message
    assert (wind.name(), codegen.registered_c_sources(g)[0][1].name) == (wind.name(), f"{wind.name()}.c")
    for ti in times:
        for a, b in zip(compiled.function(ti, pts.T), g(ti, pts.T)):
            assert np.abs(np.array(a) - np.array(b)).max() <= 1e-12 * max(1.0, np.abs(np.array(b)).max())


@needs_cc
def test_finite_difference_derivative_in_time(field):
    """enable_fd: d uvw / dt of the External against a central difference of numpy velocity (piecewise linear
    in time: inside one step both are the step's slope, up to FD round-off ~1e-6)."""
    pts = np.array([[0.0, 10.0, 80.0]])
    f = field.casadi_function(1)
    t = ca.MX.sym("t")
    d = ca.Function("d", [t], [ca.jacobian(f(t, ca.DM(pts.T)), t)])
    t0, h = 3.025, 1e-3                                     # a quarter into a 0.1 s step
    ref = (field.velocity(t0 + h, pts) - field.velocity(t0 - h, pts))[0] / (2 * h)
    assert np.abs(np.array(d(t0)).ravel() - ref).max() <= 1e-4 * max(1.0, np.abs(ref).max())
