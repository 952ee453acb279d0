"""Empirical order of accuracy of every method, fitted on a log-log plot (diffrax / scipy practice).

Reference: the closed-form damped oscillator (tests/simulate/_reference.py), m = 2 kg, k = 50 N/m,
c = 0.4 N s/m, x0 = 1 m, v0 = 0.5 m/s.

- Fixed-step methods, over 4 s: steps 0.08 ... 0.01 s (omega dt = 0.4 ... 0.05), in the asymptotic
  range and far above round-off (rk4: errors 3e-3 ... 7e-7 m; second-order methods 1e-1 ... 1e-3 m).
- Adaptive methods, over 20 s: the error at the end time against the mean step 20 s / steps, over a
  tolerance sweep (rtol = 100 atol, 9 values per method, in the window where the method runs at its
  maximum order). Measured at the end time, a step point: the dense output between steps has a
  lower order (Radau's collocation polynomial: fitted 4.0 instead of 5.0). The variable-order
  methods (adams, cvodes, idas, scipy-bdf) reach their maximum order 5 at these tolerances; the
  fitted slopes were 4.83 ... 5.10 over three different windows.
"""

import numpy as np
import pytest

from mbsym.simulate import METHODS, simulate

from ._reference import sdof_response
from .conftest import OSC

#: Methods for any model (rk4-held needs dynamics with a held part: tests/simulate/test_held_rk4.py).
GENERIC = [m for m in METHODS if not METHODS[m].needs_held]

DTS = np.array([0.08, 0.04, 0.02, 0.01])
OFF_GRID = np.linspace(0.0123, 3.97, 37)       # output times between steps (Hermite interpolation)


def _error(res):
    x, v = sdof_response(res.t, OSC["m"], OSC["c"], OSC["k"], x0=1.0, v0=0.5)
    omega = np.sqrt(OSC["k"] / OSC["m"])
    return max(np.max(np.abs(res.state("x") - x)), np.max(np.abs(res.state("x_d") - v)) / omega)


FIXED = [m for m in GENERIC if METHODS[m].kind == "fixed-step"]
ADAPTIVE = [m for m in GENERIC if METHODS[m].kind == "adaptive"]
#: Tolerance windows [rtol exponents]: tight enough for the maximum order; scipy's Python loop looser.
WINDOW = {"scipy-radau": (4, 8), "scipy-bdf": (5, 9)}


@pytest.mark.parametrize("t_out", [None, OFF_GRID], ids=["step grid", "between steps"])
@pytest.mark.parametrize("method", FIXED)
def test_fixed_step_order(osc, method, t_out):
    errors = [_error(simulate(osc, 4.0, x0=[1.0, 0.5], method=method, dt=dt, t_out=t_out)) for dt in DTS]
    slope = np.polyfit(np.log(DTS), np.log(errors), 1)[0]
    assert abs(slope - METHODS[method].order) < 0.3, f"fitted order {slope:.3f}; errors {errors}"


@pytest.mark.parametrize("method", ADAPTIVE)
def test_adaptive_order(osc, method):
    lo, hi = WINDOW.get(method, (7, 11))
    T = 20.0
    x_end, v_end = sdof_response(T, OSC["m"], OSC["c"], OSC["k"], x0=1.0, v0=0.5)
    mean_step, errors = [], []
    for rtol in 10.0 ** -np.arange(lo, hi + 0.01, 0.5):
        res = simulate(osc, T, x0=[1.0, 0.5], method=method, rtol=rtol, atol=rtol * 1e-2, t_out=[0.0, T])
        errors.append(max(abs(res.x[-1, 0] - x_end), abs(res.x[-1, 1] - v_end) / 5.0))
        mean_step.append(T / res.statistics["steps"])
    slope = np.polyfit(np.log(mean_step), np.log(errors), 1)[0]
    assert abs(slope - METHODS[method].order) < 0.3, f"fitted order {slope:.3f}; errors {errors}"


@pytest.mark.parametrize("method", ADAPTIVE)
def test_adaptive_error_follows_tolerance(osc, method):
    """Tightening rtol by 1e3 must cut the error by at least 1e2 (tolerance proportionality)."""
    errors = [_error(simulate(osc, 4.0, x0=[1.0, 0.5], method=method, rtol=r, atol=r * 1e-2))
              for r in (1e-5, 1e-8)]
    assert errors[1] < errors[0] / 100, errors


def test_rk4_loop_in_casadi_equals_a_python_loop():
    """Two implementations of the same scheme (mapaccum of an expanded step vs a numpy loop over
    eom.functions.rhs) agree to round-off on the nonlinear double pendulum (mbsym.demo)."""
    from mbsym.demo import DEMO_PARAMETERS, double_pendulum

    eom = double_pendulum().equations()
    p = eom.parameter_vector(DEMO_PARAMETERS)
    h, n = 0.01, 300
    x = np.array([1.0, -0.5, 0.2, 0.0])
    X = [x]
    f = lambda x: np.asarray(eom.functions.rhs(x, np.zeros(0), p)).reshape(-1)   # noqa: E731
    for _ in range(n):
        k1 = f(x)
        k2 = f(x + h / 2 * k1)
        k3 = f(x + h / 2 * k2)
        k4 = f(x + h * k3)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        X.append(x)
    res = simulate(eom, n * h, X[0], p=DEMO_PARAMETERS, method="rk4", dt=h)
    np.testing.assert_allclose(res.x, np.array(X), rtol=0, atol=1e-11)
