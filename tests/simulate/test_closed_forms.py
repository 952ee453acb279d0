"""Every method against closed-form solutions of the mass-spring-damper (tests/simulate/_reference.py).

Model: m = 2 kg, k = 50 N/m, c = 0.4 N s/m (omega_n = 5 rad/s, damping ratio 0.02), force input F.
Tolerances, with where they come from:

- rk4, dt = 0.01 s: global error ~ t * omega * (omega dt)^4 / 120 = 2.6e-6 m over 10 s -> 5e-6 m
  (velocity: times omega -> 2.5e-5 m/s).
- newmark / generalized-alpha, dt = 1e-3 s: second order; the trapezoidal rule's phase error is
  omega (omega dt)^2 / 12 per unit time = 1.0e-4 rad over 10 s, times the 0.117 m amplitude
  = 1.2e-5 m -> 3e-5 m (velocity: times omega -> 1.5e-4 m/s).
- adaptive methods at rtol = 1e-9, atol = 1e-11: the measured global error of these methods on
  this problem is below 100 * rtol (cvodes ~1e-7 m, adams/idas/scipy-bdf ~1e-8 m, Radau ~1e-10 m);
  bound 2e-6 m, 1e-5 m/s. The default tolerances (rtol 1e-6) are checked to 1e-4 m (0.1 % of the
  amplitude).
"""

import numpy as np
import pytest

from mbsym.simulate import METHODS, simulate

from ._reference import ramp_hold_response, sdof_harmonic_response, sdof_response
from .conftest import OSC, two_force_oscillator

#: Methods for any model (rk4-held needs dynamics with a held part: tests/simulate/test_held_rk4.py).
GENERIC = [m for m in METHODS if not METHODS[m].needs_held]

M, K, C = OSC["m"], OSC["k"], OSC["c"]
TMAX = 10.0
SECOND_ORDER = ("newmark", "generalized-alpha")
TIGHT = {m: ({} if m == "rk4" else {"dt": 1e-3} if m in SECOND_ORDER else {"rtol": 1e-9, "atol": 1e-11})
         for m in GENERIC}
TOL_X = {m: (5e-6 if m == "rk4" else 3e-5 if m in SECOND_ORDER else 2e-6) for m in GENERIC}        # [m]
TOL_V = {m: (2.5e-5 if m == "rk4" else 1.5e-4 if m in SECOND_ORDER else 1e-5) for m in GENERIC}    # [m/s]


def _check(res, x_ref, v_ref, method):
    assert np.all(np.isfinite(res.x))
    err_x = np.max(np.abs(res.state("x") - x_ref))
    err_v = np.max(np.abs(res.state("x_d") - v_ref))
    assert err_x < TOL_X[method], f"{method}: max |x - closed form| = {err_x:.3g} m"
    assert err_v < TOL_V[method], f"{method}: max |v - closed form| = {err_v:.3g} m/s"


@pytest.mark.parametrize("method", GENERIC)
def test_free_damped_response(osc, method):
    res = simulate(osc, TMAX, x0=[0.1, -0.3], method=method, **TIGHT[method])
    x_ref, v_ref = sdof_response(res.t, M, C, K, x0=0.1, v0=-0.3)
    _check(res, x_ref, v_ref, method)
    assert res.statistics["method"] == method and res.success


@pytest.mark.parametrize("method", [m for m in GENERIC if METHODS[m].kind == "adaptive"])
def test_default_tolerances(osc, method):
    res = simulate(osc, TMAX, x0=[0.1, -0.3], method=method)
    x_ref, _ = sdof_response(res.t, M, C, K, x0=0.1, v0=-0.3)
    assert res.t.size == 200     # default output grid of adaptive methods
    assert np.max(np.abs(res.state("x") - x_ref)) < 1e-4     # 0.1 % of the 0.1 m amplitude


def test_rk4_default_output_grid_is_every_step(osc):
    res = simulate(osc, 1.0, x0=[0.1, 0.0], method="rk4")
    np.testing.assert_allclose(res.t, np.linspace(0.0, 1.0, 101), rtol=0, atol=1e-12)
    assert res.statistics["steps"] == 100 and res.statistics["n_rhs"] == 400 and res.statistics["dt"] == 0.01


def test_default_path_outputs_every_10_ms_with_its_own_step(osc):
    """Without method/dt: outputs every 0.01 s as the former default, integrated with a larger step
    chosen for accuracy 1e-3 (closed form: the damped oscillator, omega_n = 5 rad/s)."""
    res = simulate(osc, 1.0, x0=[0.1, 0.0])
    np.testing.assert_allclose(res.t, np.linspace(0.0, 1.0, 101), rtol=0, atol=1e-12)
    assert res.statistics["method"] == "rk4" and res.statistics["dt"] > 0.01
    x_ref, _ = sdof_response(res.t, M, C, K, x0=0.1)
    assert np.mean(np.abs(res.state("x") - x_ref)) / np.ptp(x_ref) < 1e-3


def test_rk4_off_grid_outputs_use_hermite_interpolation(osc):
    """Output times between steps (cubic Hermite, O(dt^4)) agree with the closed form as the steps do."""
    t_out = np.sort(np.random.default_rng(0).uniform(0.0, TMAX, 50))
    res = simulate(osc, TMAX, x0=[0.1, -0.3], t_out=t_out, method="rk4")
    x_ref, v_ref = sdof_response(t_out, M, C, K, x0=0.1, v0=-0.3)
    _check(res, x_ref, v_ref, "rk4")
    np.testing.assert_array_equal(res.t, t_out)


STEP_FORCE = 3.0      # [N]
SLOPE = 5.0           # [N/s]
FORCES = {
    "constant dict": ({"F": STEP_FORCE}, {"a0": STEP_FORCE}),
    "constant array": ([STEP_FORCE], {"a0": STEP_FORCE}),
    "ramp on a shared grid": ({"t": [0.0, TMAX], "F": [0.0, SLOPE * TMAX]}, {"a1": SLOPE}),
    "ramp as a (grid, values) pair": ({"F": (np.array([0.0, 4.0, TMAX]), SLOPE * np.array([0.0, 4.0, TMAX]))},
                                      {"a1": SLOPE}),
    "ramp as a vectorized callable": ({"F": lambda t: SLOPE * np.asarray(t)}, {"a1": SLOPE}),
    "ramp as a scalar-only callable": ({"F": lambda t: SLOPE * t if t >= 0.0 else 0.0}, {"a1": SLOPE}),
    "constant callable (one number for all times)": ({"F": lambda t: STEP_FORCE}, {"a0": STEP_FORCE}),
}


@pytest.mark.parametrize("method", GENERIC)
@pytest.mark.parametrize("form", list(FORCES))
def test_forced_response(osc, method, form):
    inputs, force = FORCES[form]
    res = simulate(osc, TMAX, inputs=inputs, method=method, **TIGHT[method])
    x_ref, v_ref = sdof_response(res.t, M, C, K, **force)
    _check(res, x_ref, v_ref, method)
    expected_u = force.get("a0", 0.0) + force.get("a1", 0.0) * res.t
    np.testing.assert_allclose(res.u[:, 0], expected_u, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("method", GENERIC)
def test_ramp_then_hold_table(osc, method):
    """A table with a kink at t1 = 2 s: closed form by superposition of two ramps."""
    t1 = 2.0
    inputs = {"t": [0.0, t1, TMAX], "F": [0.0, SLOPE * t1, SLOPE * t1]}
    res = simulate(osc, TMAX, inputs=inputs, method=method, **TIGHT[method])
    x_ref, v_ref = ramp_hold_response(res.t, M, C, K, SLOPE, t1)
    _check(res, x_ref, v_ref, method)


def test_rk4_samples_inputs_at_stage_times(osc):
    """A ramp with a coarse step (omega dt = 0.25) keeps rk4's own error, ~ t omega (omega dt)^4 / 120
    times the 0.02 m transient = 3e-5 m; holding u over each step would add ~ slope dt / (2 k)
    = 2.5e-3 m. Bound 1e-4 m."""
    res = simulate(osc, TMAX, inputs={"F": lambda t: SLOPE * np.asarray(t)}, dt=0.05)
    x_ref, _ = sdof_response(res.t, M, C, K, a1=SLOPE)
    assert np.max(np.abs(res.state("x") - x_ref)) < 1e-4


F0, W = 10.0, 3.0       # harmonic force F0 sin(W t) [N, rad/s]


@pytest.mark.parametrize("method", GENERIC)
def test_callable_input_between_coarse_output_times(osc, method):
    """A callable force that varies between the output times t_out = [0, 5, 10] s. Until the fix the
    SUNDIALS methods interpolated it linearly between output times: x(10) = -0.1985 m instead of
    -0.2873 m (closed form; rk4 and scipy-radau agreed). Now callables are sampled independently of
    t_out (cubic spline on >= 2000 intervals, error ~1e-9 N): the TIGHT tolerances hold."""
    t_out = [0.0, 5.0, TMAX]
    res = simulate(osc, TMAX, inputs={"F": lambda t: F0 * np.sin(W * t)}, method=method, t_out=t_out,
                   **TIGHT[method])
    x_ref, v_ref = sdof_harmonic_response(res.t, M, C, K, F0, W)
    assert x_ref[-1] == pytest.approx(-0.28727, abs=1e-5)
    _check(res, x_ref, v_ref, method)
    if METHODS[method].kind == "adaptive" and not method.startswith("scipy"):
        assert res.statistics["input_samples"] >= 2001


@pytest.mark.parametrize("method", ["cvodes", "idas", "adams"])
def test_callable_and_table_inputs_together(method):
    """Two forces on one mass: a ramp-then-hold table (exact, grid knot at t1) and a harmonic callable
    (spline); closed form by superposition, TIGHT tolerances. Checks that each input keeps its own
    representation (the callable is in the second column)."""
    t1 = 2.0
    eom = two_force_oscillator()
    inputs = {"t": [0.0, t1, TMAX], "F": [0.0, SLOPE * t1, SLOPE * t1], "G": lambda t: F0 * np.sin(W * t)}
    res = simulate(eom, TMAX, inputs=inputs, method=method, t_out=np.linspace(0.0, TMAX, 11), **TIGHT[method])
    x1, v1 = ramp_hold_response(res.t, M, C, K, SLOPE, t1)
    x2, v2 = sdof_harmonic_response(res.t, M, C, K, F0, W)
    _check(res, x1 + x2, v1 + v2, method)
    np.testing.assert_allclose(res.u[:, 1], F0 * np.sin(W * res.t), rtol=0, atol=1e-12)
