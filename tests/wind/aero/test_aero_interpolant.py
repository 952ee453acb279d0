"""Spline interpolants of performance surfaces: nodes, scipy agreement, exact derivatives.

References: the table nodes themselves; scipy.interpolate.RectBivariateSpline (an
independent implementation of the same interpolating tensor-product spline); central
finite differences for the gradient and Hessian.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest
from scipy.interpolate import RectBivariateSpline

from mbsym.exceptions import ParameterError
from mbsym.wind.aero import SurfaceSpline, nrel5mw_rotor
from mbsym.wind.deck.performance import PerformanceTable


@pytest.fixture(scope="module")
def table() -> PerformanceTable:
    return nrel5mw_rotor().table  # packaged BEM surfaces, 61 x 46


def nonuniform_table() -> PerformanceTable:
    tsr = np.array([1.0, 1.5, 2.5, 3.0, 4.5, 5.0, 6.5, 9.0, 12.0])
    pitch = np.radians([-4.0, -1.0, 0.0, 3.0, 7.0, 12.0, 20.0])
    t, p = np.meshgrid(tsr, pitch, indexing="ij")
    cp = 0.5 * np.sin(t / 3.0) * np.cos(2.0 * p) - 0.02 * t * p
    return PerformanceTable(tsr=tsr, pitch=pitch, cp=cp, ct=cp + 0.3, cq=cp / tsr[:, None])


@pytest.mark.parametrize("degree, method, tol", [(3, "sx", 1e-12), (5, "sx", 1e-9),
                                                 (3, "bspline", 1e-12)])
def test_table_nodes_are_reproduced(table, degree, method, tol):
    spline = SurfaceSpline.from_table(table, names=("cp", "ct", "cq"), degree=degree,
                                      method=method)
    t, p = np.meshgrid(table.tsr, table.pitch, indexing="ij")
    values = spline.evaluate(t, p)
    for name in ("cp", "ct", "cq"):
        np.testing.assert_allclose(values[name], getattr(table, name), rtol=0, atol=tol)


def test_nonuniform_axes_reproduce_nodes_and_scipy():
    table = nonuniform_table()
    spline = SurfaceSpline.from_table(table)
    t, p = np.meshgrid(table.tsr, table.pitch, indexing="ij")
    np.testing.assert_allclose(spline.evaluate(t, p)["cp"], table.cp, rtol=0, atol=1e-12)
    rng = np.random.default_rng(1)
    x, y = rng.uniform(1.0, 12.0, 50), rng.uniform(table.pitch[0], table.pitch[-1], 50)
    reference = RectBivariateSpline(table.tsr, table.pitch, table.cp, kx=3, ky=3, s=0).ev(x, y)
    np.testing.assert_allclose(spline.evaluate(x, y)["cp"], reference, rtol=0, atol=1e-12)


@pytest.mark.parametrize("degree", [3, 5])
def test_between_nodes_equals_scipy_spline(table, degree):
    spline = SurfaceSpline.from_table(table, degree=degree)
    rng = np.random.default_rng(0)
    x = rng.uniform(table.tsr[0], table.tsr[-1], 200)
    y = rng.uniform(table.pitch[0], table.pitch[-1], 200)
    values = spline.evaluate(x, y)
    for name in ("cp", "ct"):
        reference = RectBivariateSpline(table.tsr, table.pitch, getattr(table, name),
                                        kx=degree, ky=degree, s=0).ev(x, y)
        np.testing.assert_allclose(values[name], reference, rtol=0, atol=1e-9)


@pytest.mark.parametrize("degree", [3, 5])
def test_gradient_and_hessian_match_finite_differences(table, degree):
    spline = SurfaceSpline.from_table(table, degree=degree)
    z = ca.SX.sym("z", 2)
    value = spline(z[0], z[1])["cp"]
    hessian, gradient = ca.hessian(value, z)
    f = ca.Function("f", [z], [value, gradient, hessian])
    rng = np.random.default_rng(2)
    for _ in range(20):
        z0 = np.array([rng.uniform(1.6, 15.4), rng.uniform(-0.07, 0.68)])
        f0, g0, h0 = (np.array(v) for v in f(z0))
        steps = np.array([1e-5, 1e-7])
        g_fd = np.zeros(2)
        h_fd = np.zeros((2, 2))
        for k in range(2):
            e = np.zeros(2)
            e[k] = steps[k]
            g_fd[k] = (float(f(z0 + e)[0]) - float(f(z0 - e)[0])) / (2 * steps[k])
            h_fd[:, k] = (np.array(f(z0 + e)[1]).ravel() - np.array(f(z0 - e)[1]).ravel()) \
                / (2 * steps[k])
        # tolerances: central differences (step^2 error) and round-off (eps / step)
        np.testing.assert_allclose(g0.ravel(), g_fd, rtol=1e-6, atol=1e-8)
        np.testing.assert_allclose(h0, h_fd, rtol=1e-4, atol=1e-6)
        assert abs(h0[0, 1] - h0[1, 0]) < 1e-12  # symmetric


def test_linear_continuation_outside_is_c1(table):
    # Outside the table the edge cells continue linearly: value and slope continuous.
    spline = SurfaceSpline.from_table(table)
    z = ca.SX.sym("z", 2)
    value = spline(z[0], z[1])["ct"]
    f = ca.Function("f", [z], [value, ca.gradient(value, z)])
    for point, axis in (([table.tsr[0], 0.1], 0), ([table.tsr[-1], 0.2], 0),
                        ([8.0, table.pitch[0]], 1), ([8.0, table.pitch[-1]], 1)):
        step = np.zeros(2)
        step[axis] = 1e-9
        v_minus, g_minus = f(np.array(point) - step)
        v_plus, g_plus = f(np.array(point) + step)
        assert abs(float(v_minus) - float(v_plus)) < 1e-7
        np.testing.assert_allclose(np.array(g_minus).ravel(), np.array(g_plus).ravel(),
                                   rtol=1e-6, atol=1e-6)
    # far outside: linear in TSR, finite
    far = spline.evaluate([30.0, 40.0, 50.0], [0.0, 0.0, 0.0])["ct"]
    assert np.all(np.isfinite(far))
    assert abs((far[2] - far[1]) - (far[1] - far[0])) < 1e-9


def test_numbers_and_mx_are_accepted(table):
    spline = SurfaceSpline.from_table(table)
    numeric = spline(7.5, 0.0)["cp"]
    m = ca.MX.sym("m", 2)
    via_mx = ca.Function("g", [m], [spline(m[0], m[1])["cp"]])([7.5, 0.0])
    assert abs(float(ca.evalf(numeric)) - float(via_mx)) < 1e-14


def test_bad_arguments(table):
    with pytest.raises(ParameterError, match="names"):
        SurfaceSpline.from_table(table, names=("cl",))
    with pytest.raises(ParameterError, match="degree"):
        SurfaceSpline.from_table(table, degree=4)
    with pytest.raises(ParameterError, match="method"):
        SurfaceSpline.from_table(table, method="akima")
    with pytest.raises(TypeError, match="PerformanceTable"):
        SurfaceSpline.from_table({"cp": 1})  # type: ignore[arg-type]
    small = PerformanceTable(tsr=[1.0, 2.0, 3.0], pitch=[0.0, 0.1, 0.2, 0.3],
                             cp=np.zeros((3, 4)), ct=np.zeros((3, 4)), cq=np.zeros((3, 4)))
    with pytest.raises(ParameterError, match="needs at least 4 values per axis"):
        SurfaceSpline.from_table(small)
    with pytest.raises(TypeError):
        SurfaceSpline.from_table(table, order=3)  # type: ignore[call-arg]
