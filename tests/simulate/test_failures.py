"""Failure is loud: divergence and NaN raise IntegrationError naming method, step, time and state.

Cases, each with a known cause:

- rk4 on a stiff spring (m = 2 kg, k = 1e6 N/m: omega = 707 rad/s) at dt = 0.01 s: omega dt = 7.1,
  beyond rk4's stability limit 2.78, so the solution grows by ~100x per step;
- x'' = x^3 from x = 1 at rest: finite-time blow-up at t* = sqrt(2) K(1/2) = 1.8541 s (every method);
- a spring force -sqrt(x): NaN as soon as x < 0 (the free swing gets there at t ~ 1.49 s).
"""

import re

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import IntegrationError
from mbsym.simulate import METHODS, simulate

from .conftest import cubic_blowup, oscillator, sqrt_spring

#: Methods for any model (rk4-held needs dynamics with a held part: tests/simulate/test_held_rk4.py).
GENERIC = [m for m in METHODS if not METHODS[m].needs_held]

BLOWUP_T = 1.8541


def _time_in(message):
    return float(re.search(r"t = ([0-9.eE+-]+) s", message).group(1))


def test_rk4_beyond_stability_raises():
    stiff = oscillator(stiffness=1e6)
    with pytest.raises(IntegrationError) as info:
        simulate(stiff, 3.0, x0=[0.01, 0.0], method="rk4", dt=0.01)
    msg = str(info.value)
    assert "'rk4'" in msg and "dt = 0.01 s" in msg and "t = " in msg
    assert "'x'" in msg or "'x_d'" in msg
    assert "stable only for dt < 0.00393 s" in msg          # 2.78 / 707.1 rad/s
    assert 0.0 < _time_in(msg) < 0.2                          # grows ~100x per step: within ~10 steps


def test_stiff_spring_fine_with_implicit_method():
    stiff = oscillator(stiffness=1e6)
    res = simulate(stiff, 0.5, x0=[0.01, 0.0], method="cvodes", rtol=1e-8, atol=1e-10)
    omega, sigma = np.sqrt(1e6 / 2.0), 0.4 / 4.0
    x_ref = 0.01 * np.exp(-sigma * res.t) * (np.cos(omega * res.t) + sigma / omega * np.sin(omega * res.t))
    assert np.max(np.abs(res.state("x") - x_ref)) < 1e-5      # 0.1 % of the amplitude


@pytest.mark.parametrize("method", GENERIC)
def test_finite_time_blowup_raises(method):
    with pytest.raises(IntegrationError, match=rf"'{method}'") as info:
        simulate(cubic_blowup(), 3.0, x0=[1.0, 0.0], method=method)
    msg = str(info.value)
    assert "'x'" in msg or "'x_d'" in msg
    assert "step size" in msg
    assert BLOWUP_T - 0.05 < _time_in(msg) < BLOWUP_T + 0.05


@pytest.mark.parametrize("method", GENERIC)
def test_nan_rhs_raises(method):
    with pytest.raises(IntegrationError, match=rf"'{method}'") as info:
        simulate(sqrt_spring(), 3.0, x0=[1.0, 0.0], method=method)
    msg = str(info.value)
    assert "'x'" in msg or "'x_d'" in msg
    assert 1.4 < _time_in(msg) < 1.6
    if method == "rk4":
        assert "first non-finite state 'x' = nan" in msg


def test_nan_parameter_is_rejected_before_integrating(osc):
    with pytest.raises(mb.ParameterError, match="'k'"):
        simulate(osc, 1.0, p={"k": float("nan")})


def test_no_nan_ever_returned(osc):
    """Inputs that make the rhs infinite (a huge force) are caught, not returned."""
    with pytest.raises(IntegrationError):
        simulate(osc, 1.0, inputs={"F": 1e300}, method="rk4")


# Stiff, overdamped spring: m = 2 kg, k = 1e6 N/m, c = 2e4 N s/m, eigenvalues -50.25 and -9949.7 1/s
# (stiffness ratio 198). Closed form x = A exp(l1 t) + B exp(l2 t) from x0 = 0.01 m at rest.
STIFF = {"m": 2.0, "k": 1e6, "c": 2e4}


def _stiff_reference(t):
    l1, l2 = np.roots([STIFF["m"], STIFF["c"], STIFF["k"]])
    b = -l1 * 0.01 / (l2 - l1)
    return (0.01 - b) * np.exp(l1 * t) + b * np.exp(l2 * t)


@pytest.mark.parametrize("method", [m for m in GENERIC if METHODS[m].implicit])
def test_implicit_methods_stay_stable_on_the_stiff_spring(osc, method):
    """Implicit methods at dt = 0.01 s (|lambda| dt = 99.5, rk4's limit is 2.78) or rtol 1e-6 finish in a
    bounded number of steps (adaptive: < 400 steps, < 100 Jacobians; measured 166-287 steps). Error
    bounds: adaptive 1e-6 m (100 rtol x 0.01 m); newmark 5e-4 m (the trapezoidal rule is A- but not
    L-stable: the fast mode rings with amplification -0.98 per step; measured 1.3e-4 m);
    generalized-alpha 5e-3 m (rho_inf = 0.8 damps it in ~20 steps; measured 2.1e-3 m)."""
    kind = METHODS[method].kind
    kw = {"dt": 0.01} if kind == "fixed-step" else {"rtol": 1e-6, "atol": 1e-10}
    res = simulate(osc, 3.0, x0=[0.01, 0.0], p=STIFF, method=method, **kw)
    err = np.max(np.abs(res.state("x") - _stiff_reference(res.t)))
    bound = {"newmark": 5e-4, "generalized-alpha": 5e-3}.get(method, 1e-6)
    assert err < bound, f"{method}: max error {err:.3g} m"
    if kind == "adaptive":
        assert res.statistics["steps"] < 400 and res.statistics["n_jac"] < 100, res.statistics


def test_explicit_adaptive_method_is_stability_limited(osc):
    """adams keeps accuracy on the stiff spring only by taking steps below its stability limit:
    more than 30x the steps of BDF (measured 37762 vs 280)."""
    adams = simulate(osc, 3.0, x0=[0.01, 0.0], p=STIFF, method="adams", rtol=1e-6, atol=1e-10)
    bdf = simulate(osc, 3.0, x0=[0.01, 0.0], p=STIFF, method="cvodes", rtol=1e-6, atol=1e-10)
    assert adams.statistics["steps"] > 30 * bdf.statistics["steps"], (adams.statistics, bdf.statistics)


@pytest.mark.parametrize("method", ["newmark", "generalized-alpha"])
def test_newton_failure_is_reported(method):
    """Near the blow-up of x'' = x^3 Newton no longer converges within its 10 iterations: the error
    names the method, time, step size and the Newton iteration (not a silent wrong answer)."""
    with pytest.raises(IntegrationError) as info:
        simulate(cubic_blowup(), 3.0, x0=[1.0, 0.0], method=method, dt=0.02)
    msg = str(info.value)
    assert f"'{method}'" in msg and "dt = 0.02 s" in msg and "Newton iteration did not converge" in msg
    assert BLOWUP_T - 0.1 < _time_in(msg) < BLOWUP_T + 0.05
