"""The method "rk4-held" and the HeldPart split of a Dynamics (mbsym.held).

Model: a spring-mass-damper whose extra spring and damper (an "aerodynamic" force F = -κ x - γ v) form the held
part ``z``: the full system is the damped oscillator with k + κ and c + γ, whose free response is closed form.
Holding F over a step is a first-order error in F's variation (``rk4-held``, order 1), so:

* the error against the closed form falls as h¹ (fitted order 1 ± 0.3 over h = 10, 5, 2.5 ms);
* with κ = γ = 0 nothing varies in z and rk4-held equals rk4 to rounding;
* in a closed loop, the outputs the loop evaluates at the samples from the held part equal the plant's
  outputs evaluated afterwards at the same states and inputs (to rounding), and rows between samples
  are evaluated afterwards.
"""

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import DimensionError, SimulationOptionError
from mbsym.held import HeldPart
from mbsym.simulate import DiscreteController, simulate

from ._reference import sdof_response

M, K, C = 2.0, 80.0, 0.4          # kg, N/m, N s/m
KAPPA, GAMMA = 20.0, 1.6          # N/m, N s/m: the held force


def held_oscillator(kappa: float = KAPPA, gamma: float = GAMMA) -> mb.Dynamics:
    """x = [x, v], u = [f] (an applied force), outputs [x, F, acceleration]."""
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 0)
    z = ca.SX.sym("z", 1)
    force = -kappa * x[0] - gamma * x[1]
    xd_z = ca.vertcat(x[1], (-K * x[0] - C * x[1] + z[0] + u[0]) / M)
    y_z = ca.vertcat(x[0], z[0], xd_z[1])
    part = ca.Function("part", [x, u, p], [force])
    rhs_z = ca.Function("rhs_z", [x, u, p, z], [xd_z])
    out_z = ca.Function("out_z", [x, u, p, z], [y_z])
    rhs = ca.Function("rhs", [x, u, p], [rhs_z(x, u, p, part(x, u, p))])
    out = ca.Function("out", [x, u, p], [out_z(x, u, p, part(x, u, p))])
    return mb.Dynamics(rhs, states=["x", "x_d"], inputs=["f"], outputs=out, output_names=["X", "F", "A"],
                       held=HeldPart(part, rhs_z, out_z, "spring and damper"))


def _error(h: float) -> float:
    res = simulate(held_oscillator(), 4.0, x0=[0.1, 0.0], method="rk4-held", dt=h, t_out=np.linspace(0, 4, 81))
    x_ref, _ = sdof_response(res.t, M, C + GAMMA, K + KAPPA, x0=0.1, v0=0.0)
    return float(np.max(np.abs(res.state("x") - x_ref)))


def test_first_order_convergence_to_the_closed_form():
    hs = np.array([0.01, 0.005, 0.0025])
    errors = np.array([_error(h) for h in hs])
    slope = np.polyfit(np.log(hs), np.log(errors), 1)[0]
    assert abs(slope - 1.0) < 0.3, f"fitted order {slope:.2f}; errors {errors}"
    # at 2.5 ms the holding delays the force by h/2 = 1.25 ms, 0.9 % of a period ω h / 2 = 0.0088 rad: the
    # error stays below 1 % of the 0.1 m amplitude (measured 0.53 %)
    assert errors[-1] < 1e-2 * 0.1


def test_nothing_varying_held_equals_rk4():
    dyn = held_oscillator(0.0, 0.0)
    a = simulate(dyn, 2.0, x0=[0.1, 0.3], method="rk4-held", dt=0.01)
    b = simulate(dyn, 2.0, x0=[0.1, 0.3], method="rk4", dt=0.01)
    np.testing.assert_allclose(a.x, b.x, rtol=0, atol=1e-14)
    assert a.statistics["method"] == "rk4-held"


def test_model_without_held_part_is_refused():
    dyn = held_oscillator()
    plain = mb.Dynamics(dyn.rhs, states=dyn.states, inputs=dyn.inputs)
    with pytest.raises(SimulationOptionError, match="declares none"):
        simulate(plain, 1.0, method="rk4-held", dt=0.01)


def test_held_part_sizes_are_checked():
    dyn = held_oscillator()
    h = dyn.held
    x, u, p, z = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 0), ca.SX.sym("z", 2)
    with pytest.raises(DimensionError, match="z of 2 entries"):
        HeldPart(h.part, ca.Function("r", [x, u, p, z], [x]))
    with pytest.raises(DimensionError, match="4 arguments"):
        HeldPart(h.part, dyn.rhs)
    with pytest.raises(TypeError, match="casadi.Function"):
        HeldPart(h.part, "rhs")
    x3 = ca.SX.sym("x", 3)
    bad = HeldPart(ca.Function("g", [x3, u, p], [x3[0]]), ca.Function("r", [x3, u, p, z[0]], [x3]))
    with pytest.raises(DimensionError, match="sizes"):
        mb.Dynamics(dyn.rhs, states=dyn.states, inputs=dyn.inputs, held=bad)


def test_depends_on_inputs():
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 3), ca.SX.sym("p", 0)
    z = ca.SX.sym("z")
    h = HeldPart(ca.Function("g", [x, u, p], [x[0] * u[2]]), ca.Function("r", [x, u, p, z], [x * z]))
    assert h.depends_on_inputs([2]) and not h.depends_on_inputs([0, 1]) and not h.depends_on_inputs([])


def _p_controller(dt: float) -> DiscreteController:
    xc, y = ca.SX.sym("xc", 0), ca.SX.sym("y", 2)
    law = ca.Function("P", [xc, y], [xc, -50.0 * y[0] - 5.0 * y[1]])
    return DiscreteController(law, dt, measurements=["X", "x_d"], actuates=["f"])


def test_closed_loop_outputs_from_the_held_part_equal_the_outputs():
    dyn = held_oscillator()
    t_out = np.round(np.concatenate([np.arange(0.0, 2.0, 0.05), [2.0]]), 12)       # samples of 0.05 s
    t_out = np.sort(np.concatenate([t_out, [0.512, 1.337]]))                         # and two in between
    res = simulate(dyn, 2.0, x0=[0.1, 0.0], controller=_p_controller(0.05), method="rk4-held", dt=0.05,
                   t_out=t_out)
    again = np.vstack([np.asarray(dyn.outputs(x, u, [])).ravel() for x, u in zip(res.x, res.u)])
    np.testing.assert_allclose(np.asarray(res.y)[:, :3], again, rtol=0, atol=1e-12)
    ref = simulate(dyn, 2.0, x0=[0.1, 0.0], controller=_p_controller(0.05), method="rk4", dt=0.0125, t_out=t_out)
    # the same loop with the force not held (4 sub-steps): rk4-held's first-order error at 50 ms steps
    assert np.max(np.abs(res.state("x") - ref.state("x"))) < 0.05 * 0.1


# ------------------------------------------------------------------------ held over several samples (held_dt)
def _hand_loop(dt: float, n: int, refresh: set, x0) -> np.ndarray:
    """The closed loop of held_oscillator and _p_controller written out: at each sample the P law on the state,
    the force -κx - γv evaluated at the samples in ``refresh`` and held otherwise, one RK4 step per sample."""
    def f(s, u, force):
        return np.array([s[1], (-K * s[0] - C * s[1] + force + u) / M])

    s, force, out = np.array(x0, float), 0.0, []
    for k in range(n):
        out.append(s.copy())
        u = -50.0 * s[0] - 5.0 * s[1]
        if k in refresh:
            force = -KAPPA * s[0] - GAMMA * s[1]
        k1 = f(s, u, force)
        k2 = f(s + dt / 2 * k1, u, force)
        k3 = f(s + dt / 2 * k2, u, force)
        k4 = f(s + dt * k3, u, force)
        s = s + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    out.append(s)
    return np.array(out)


def test_held_over_samples_equals_the_loop_written_out():
    dt, n = 0.01, 200
    t_out = np.round(np.arange(0, n + 1, 4) * dt, 12)                 # every fourth sample: on the hold grid
    res = simulate(held_oscillator(), n * dt, x0=[0.1, 0.0], controller=_p_controller(dt), method="rk4-held",
                   dt=dt, t_out=t_out, held_dt=4 * dt)
    ref = _hand_loop(dt, n, set(range(0, n, 4)), [0.1, 0.0])[::4]
    # the same arithmetic in another order: rounding only
    np.testing.assert_allclose(res.x, ref, rtol=0, atol=1e-13)
    assert res.statistics["held_dt"] == pytest.approx(4 * dt)
    # and it is not the every-sample loop (the hold matters at this κ, γ: ~1e-4 m apart)
    every = _hand_loop(dt, n, set(range(n)), [0.1, 0.0])[::4]
    assert np.max(np.abs(every - ref)) > 1e-5


def test_held_over_samples_refreshes_where_outputs_are_wanted():
    dt, n = 0.01, 100
    t_out = np.round(np.array([0.0, 0.03, 0.04, 0.57, 1.0]), 12)     # samples 3 and 57 are off the hold grid
    res = simulate(held_oscillator(), n * dt, x0=[0.1, 0.0], controller=_p_controller(dt), method="rk4-held",
                   dt=dt, t_out=t_out, held_dt=4 * dt)
    ref = _hand_loop(dt, n, set(range(0, n, 4)) | {3, 57}, [0.1, 0.0])[[0, 3, 4, 57, 100]]
    np.testing.assert_allclose(res.x, ref, rtol=0, atol=1e-13)
    dyn = held_oscillator()
    again = np.vstack([np.asarray(dyn.outputs(x, u, [])).ravel() for x, u in zip(res.x, res.u)])
    np.testing.assert_allclose(np.asarray(res.y)[:-1, :3], again[:-1], rtol=0, atol=1e-12)


def test_held_dt_of_one_sample_is_the_default():
    dt = 0.01
    a = simulate(held_oscillator(), 1.0, x0=[0.1, 0.0], controller=_p_controller(dt), method="rk4-held", dt=dt)
    b = simulate(held_oscillator(), 1.0, x0=[0.1, 0.0], controller=_p_controller(dt), method="rk4-held", dt=dt,
                 held_dt=dt)
    np.testing.assert_array_equal(a.x, b.x)


@pytest.mark.parametrize("kwargs, match", [
    ({"held_dt": 0.025}, "whole multiple"),
    ({"held_dt": -0.02}, "positive"),
    ({"held_dt": 0.02, "method": "rk4"}, "method='rk4-held'"),
    ({"held_dt": 0.02, "dt": 0.005}, "one step per controller sample"),
])
def test_held_dt_is_checked(kwargs, match):
    options = {"method": "rk4-held", "dt": 0.01, **kwargs}
    with pytest.raises(SimulationOptionError, match=match):
        simulate(held_oscillator(), 0.1, x0=[0.1, 0.0], controller=_p_controller(0.01), **options)


def test_held_dt_needs_a_controller():
    with pytest.raises(SimulationOptionError, match="needs controller="):
        simulate(held_oscillator(), 0.1, x0=[0.1, 0.0], method="rk4-held", dt=0.01, held_dt=0.02)


def test_sample_by_sample_loop_equals_the_mapaccum(monkeypatch):
    """An expensive body runs one buffered call per sample instead of a mapaccum (sample_loops.StepLoop): the
    same arithmetic, so the same result to the last bit (forced here on the cheap oscillator)."""
    import importlib

    cl = importlib.import_module("mbsym.simulate.closed_loop")

    dt, n = 0.01, 300                              # > 64 samples: the loop is chunked and timed
    kwargs = dict(x0=[0.1, 0.0], controller=_p_controller(dt), method="rk4-held", dt=dt, held_dt=2 * dt,
                  t_out=np.round(np.arange(0, n + 1, 2) * dt, 12), compile=False)
    monkeypatch.setattr(cl, "STEPWISE_FROM_S", float("inf"))
    a = simulate(held_oscillator(), n * dt, **kwargs)
    monkeypatch.setattr(cl, "STEPWISE_FROM_S", 0.0)
    b = simulate(held_oscillator(), n * dt, **kwargs)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(np.asarray(a.y), np.asarray(b.y))


# ------------------------------------------------------------------------ extrapolated between evaluations (held_order)
def _lagrange(points, t: float) -> float:
    """The polynomial through ``points`` [(time, value), ...] at ``t`` (written out independently)."""
    total = 0.0
    for i, (ti, vi) in enumerate(points):
        w = 1.0
        for j, (tj, _) in enumerate(points):
            if j != i:
                w *= (t - tj) / (ti - tj)
        total += w * vi
    return total


def _extrapolating_loop(dt: float, n: int, every: int, order: int, x0) -> np.ndarray:
    """The closed loop of held_oscillator and _p_controller with the force evaluated every ``every`` samples and
    extrapolated through the last ``order + 1`` evaluations (those there are, at the start) at each RK4 stage
    time."""
    def f(s, u, force):
        return np.array([s[1], (-K * s[0] - C * s[1] + force + u) / M])

    s, hist, out = np.array(x0, float), [], []
    for k in range(n):
        t = k * dt
        out.append(s.copy())
        u = -50.0 * s[0] - 5.0 * s[1]
        if k % every == 0:
            value = -KAPPA * s[0] - GAMMA * s[1]
            hist = ([(t, value)] + hist)[:order + 1]
        F0, Fm, F1 = (_lagrange(hist, t + c) for c in (0.0, dt / 2, dt))
        k1 = f(s, u, F0)
        k2 = f(s + dt / 2 * k1, u, Fm)
        k3 = f(s + dt / 2 * k2, u, Fm)
        k4 = f(s + dt * k3, u, F1)
        s = s + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    out.append(s)
    return np.array(out)


@pytest.mark.parametrize("order, every", [(1, 4), (2, 4), (1, 1), (0, 1)])
def test_extrapolated_held_part_equals_the_loop_written_out(order, every):
    dt, n = 0.01, 200
    t_out = np.round(np.arange(0, n + 1, 4) * dt, 12)
    res = simulate(held_oscillator(), n * dt, x0=[0.1, 0.0], controller=_p_controller(dt), method="rk4-held",
                   dt=dt, t_out=t_out, held_dt=every * dt, held_order=order)
    ref = _extrapolating_loop(dt, n, every, order, [0.1, 0.0])[::4]
    # the same arithmetic in another order: rounding only (amplitude 0.1 m)
    np.testing.assert_allclose(res.x, ref, rtol=0, atol=1e-13)
    if order:
        assert res.statistics["held_order"] == order


def _loop_error(dt: float, order: int) -> float:
    """rk4-held (the force evaluated every sample, extrapolated with ``order``) against rk4 (the force at every
    stage) on the same sampled loop: what holding/extrapolating costs."""
    t_out = np.linspace(0.0, 1.0, 11)
    kwargs = dict(x0=[0.1, 0.0], controller=_p_controller(dt), dt=dt, t_out=t_out)
    a = simulate(held_oscillator(), 1.0, method="rk4-held", held_order=order, **kwargs)
    b = simulate(held_oscillator(), 1.0, method="rk4", **kwargs)
    return float(np.max(np.abs(a.x - b.x)))


def test_extrapolation_order_sets_the_convergence_order():
    """Holding the force is first order in the step, extrapolating linearly second order (fitted slopes within
    ±0.4 over h = 4, 2, 1 ms; the controller samples at the same h in both loops). Quadratic extrapolation is
    third order per step but starts with one held and one linear step (its history fills), a one-off O(h²)
    error: its slope is ≥ 2 - 0.4 and its error below the linear one's at every h."""
    hs = np.array([0.004, 0.002, 0.001])
    errors = {k: np.array([_loop_error(h, k) for h in hs]) for k in (0, 1, 2)}
    slopes = {k: np.polyfit(np.log(hs), np.log(e), 1)[0] for k, e in errors.items()}
    assert abs(slopes[0] - 1.0) < 0.4 and abs(slopes[1] - 2.0) < 0.4, (slopes, errors)
    assert slopes[2] > 1.6 and np.all(errors[2] < errors[1]), (slopes, errors)


@pytest.mark.parametrize("order", [3, -1, 1.0, True])
def test_held_order_is_checked(order):
    with pytest.raises(SimulationOptionError, match="held_order"):
        simulate(held_oscillator(), 0.1, x0=[0.1, 0.0], controller=_p_controller(0.01), method="rk4-held", dt=0.01,
                 held_order=order)


def test_held_order_needs_rk4_held_and_a_controller():
    with pytest.raises(SimulationOptionError, match="rk4-held"):
        simulate(held_oscillator(), 0.1, x0=[0.1, 0.0], controller=_p_controller(0.01), method="rk4", dt=0.01,
                 held_order=1)
    with pytest.raises(SimulationOptionError, match="needs controller="):
        simulate(held_oscillator(), 0.1, x0=[0.1, 0.0], method="rk4-held", dt=0.01, held_order=1)
