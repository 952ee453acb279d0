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


@pytest.mark.parametrize("method", list(METHODS))
def test_finite_time_blowup_raises(method):
    with pytest.raises(IntegrationError, match=rf"'{method}'") as info:
        simulate(cubic_blowup(), 3.0, x0=[1.0, 0.0], method=method)
    msg = str(info.value)
    assert "'x'" in msg or "'x_d'" in msg
    assert "step size" in msg
    assert BLOWUP_T - 0.05 < _time_in(msg) < BLOWUP_T + 0.05


@pytest.mark.parametrize("method", list(METHODS))
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
