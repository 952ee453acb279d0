"""The closed-loop multistep methods "abm4-held" and "ab4-held" (mbsym.simulate.held_multistep).

Model: the held oscillator of test_held_rk4 (a spring-mass-damper whose extra spring and damper form the held part),
in a loop with a discrete controller. References, each independent of the generated loop:

* the loop written out by hand in numpy (RK4 start-up for three samples with the force at every stage, then
  Adams-Bashforth 4 / Adams-Bashforth-Moulton 4 with the coefficients of ElastoDyn's ED_AB4/ED_ABM4, the force
  evaluated every ``every`` samples and extrapolated through the last ``order + 1`` evaluations): equal to
  rounding;
* the closed-form free response of the oscillator (commands constant): the empirical order of convergence;
* the same sampled loop integrated by "rk4" at every stage: the first-order difference the zero-order hold on the
  commands makes to a multistep formula;
* a lightly damped oscillator: the decay rate against exp(-ζ ω t) at ω h inside and outside the stability
  intervals of the methods (AB4 0.43, ABM4 1.05 on the imaginary axis, from their characteristic polynomials).
"""

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import IntegrationError, SimulationOptionError
from mbsym.held import HeldPart
from mbsym.simulate import DiscreteController, simulate

from ._reference import sdof_response
from .test_held_rk4 import GAMMA, KAPPA, C, K, M, _lagrange, _p_controller, held_oscillator

METHODS = ("abm4-held", "ab4-held")


def _hand_loop(method: str, dt: float, n: int, every: int, order: int, x0, gain: float = 1.0) -> np.ndarray:
    """The closed loop of held_oscillator and the P controller (gains × ``gain``) with ``method`` written out."""
    def f(s, u, force):
        return np.array([s[1], (-K * s[0] - C * s[1] + force + u) / M])

    def force_of(s):
        return -KAPPA * s[0] - GAMMA * s[1]

    s, hist, past, out = np.array(x0, float), [], [], []
    for k in range(n):
        t = k * dt
        out.append(s.copy())
        u = gain * (-50.0 * s[0] - 5.0 * s[1])
        if k % every == 0:
            hist = ([(t, force_of(s))] + hist)[:order + 1]
        if len(past) < 3:                      # start-up: RK4, the force evaluated at each stage
            def g(v):
                return f(v, u, force_of(v))
            k1 = g(s)
            k2 = g(s + dt / 2 * k1)
            k3 = g(s + dt / 2 * k2)
            k4 = g(s + dt * k3)
            fn, s = k1, s + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        else:
            fn = f(s, u, _lagrange(hist, t))
            pred = s + dt / 24 * (55 * fn - 59 * past[0] + 37 * past[1] - 9 * past[2])
            if method == "abm4-held":
                fp = f(pred, u, _lagrange(hist, t + dt))
                pred = s + dt / 24 * (9 * fp + 19 * fn - 5 * past[0] + past[1])
            s = pred
        past = [fn] + past[:2]
    out.append(s)
    return np.array(out)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("order, every", [(0, 1), (2, 1), (1, 4), (2, 4)])
def test_equals_the_loop_written_out(method, order, every):
    dt, n = 0.01, 200
    t_out = np.round(np.arange(0, n + 1, 4) * dt, 12)
    res = simulate(held_oscillator(), n * dt, x0=[0.1, 0.0], controller=_p_controller(dt), method=method, dt=dt,
                   t_out=t_out, held_dt=every * dt, held_order=order)
    ref = _hand_loop(method, dt, n, every, order, [0.1, 0.0])[::4]
    # the same arithmetic in another order: rounding only (amplitude 0.1 m)
    np.testing.assert_allclose(res.x, ref, rtol=0, atol=1e-13)
    st = res.statistics
    assert st["method"] == method and "first 3 by RK4" in st["message"]
    # right-hand sides: 4 per start-up step, then 2 (abm4) or 1 (ab4) per step; outputs on samples: no end one
    assert st["n_rhs"] == 3 * 4 + (n - 3) * {"abm4-held": 2, "ab4-held": 1}[method]


def test_start_up_is_rk4_of_the_full_dynamics():
    """Three samples: only the start-up runs, RK4 with the force at every stage, i.e. "rk4" of the same loop."""
    dt = 0.01
    kwargs = dict(x0=[0.1, -0.2], controller=_p_controller(dt), dt=dt, t_out=[0.0, dt, 2 * dt, 3 * dt])
    a = simulate(held_oscillator(), 3 * dt, method="abm4-held", **kwargs)
    b = simulate(held_oscillator(), 3 * dt, method="rk4", **kwargs)
    np.testing.assert_allclose(a.x, b.x, rtol=0, atol=1e-15)


def test_a_shorter_last_sample_is_an_rk4_step():
    """tmax between samples: the last step is shorter; AB4 with that step would use the wrong spacing of its
    history, so it is an RK4 step (with the force at each stage)."""
    dt, n = 0.01, 20
    tmax = n * dt + 0.004
    res = simulate(held_oscillator(), tmax, x0=[0.1, 0.0], controller=_p_controller(dt), method="ab4-held", dt=dt,
                   t_out=[0.0, n * dt, tmax])
    s = _hand_loop("ab4-held", dt, n, 1, 0, [0.1, 0.0])[-1]
    u = -50.0 * s[0] - 5.0 * s[1]

    def g(v):
        return np.array([v[1], (-K * v[0] - C * v[1] - KAPPA * v[0] - GAMMA * v[1] + u) / M])

    h = 0.004
    k1 = g(s)
    k2 = g(s + h / 2 * k1)
    k3 = g(s + h / 2 * k2)
    k4 = g(s + h * k3)
    np.testing.assert_allclose(res.x[-1], s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4), rtol=0, atol=1e-13)


# ------------------------------------------------------------------------ convergence
def _zero_controller(dt: float) -> DiscreteController:
    """Measures the position, commands no force: the loop is the free oscillator (no command jumps)."""
    xc, y = ca.SX.sym("xc", 0), ca.SX.sym("y", 1)
    return DiscreteController(ca.Function("Z", [xc, y], [xc, 0.0 * y[0]]), dt, measurements=["X"], actuates=["f"])


def _free_error(method: str, h: float, order: int, kappa: float = KAPPA, gamma: float = GAMMA) -> float:
    t_out = np.round(np.linspace(0.0, 2.0, 41), 12)
    res = simulate(held_oscillator(kappa, gamma), 2.0, x0=[0.1, 0.0], controller=_zero_controller(h), method=method,
                   dt=h, t_out=t_out, held_order=order)
    x_ref, _ = sdof_response(res.t, M, C + gamma, K + kappa, x0=0.1, v0=0.0)
    return float(np.max(np.abs(res.state("x") - x_ref)))


def _slope(method: str, order: int, **kw) -> tuple[float, np.ndarray]:
    hs = np.array([0.01, 0.005, 0.0025])
    errors = np.array([_free_error(method, h, order, **kw) for h in hs])
    return float(np.polyfit(np.log(hs), np.log(errors), 1)[0]), errors


def test_ab4_is_fourth_order():
    """AB4 reads the held part at t_n only, where it is fresh (evaluated every sample): fourth order against the
    closed form (fitted slope 4 ± 0.3, the declared tolerance of TESTING.md)."""
    slope, errors = _slope("ab4-held", 0)
    assert abs(slope - 4.0) < 0.3, (slope, errors)


def test_abm4_is_fourth_order_without_a_varying_held_part():
    """Nothing in the held part varies (κ = γ = 0, the force is 0): ABM4 itself, fourth order (± 0.3)."""
    slope, errors = _slope("abm4-held", 0, kappa=0.0, gamma=0.0)
    assert abs(slope - 4.0) < 0.3, (slope, errors)


@pytest.mark.parametrize("order, expected", [(0, 1.0), (1, 2.0), (2, 3.0)])
def test_abm4_order_follows_the_extrapolation_at_the_corrector(order, expected):
    """The corrector reads the held part at t_{n+1}, extrapolated with held_order k from the fresh values: an
    error O(h^(k+1)) there, times h per step: the global order is k + 1 (± 0.3) until the method's own 4."""
    slope, errors = _slope("abm4-held", order)
    assert abs(slope - expected) < 0.3, (slope, errors)


def test_zero_order_hold_difference_is_first_order():
    """With a P controller the commands jump at each sample; the history's derivatives were taken under the
    earlier commands, so against the same sampled loop integrated by "rk4" (exact zero-order hold to O(h⁴)) the
    difference falls as h¹ (slope 1 ± 0.3) — the commands act as if varying smoothly across samples."""
    def diff(h):
        kwargs = dict(x0=[0.1, 0.0], controller=_p_controller(h), dt=h, t_out=np.linspace(0.0, 1.0, 11))
        a = simulate(held_oscillator(0.0, 0.0), 1.0, method="ab4-held", **kwargs)
        b = simulate(held_oscillator(0.0, 0.0), 1.0, method="rk4", **kwargs)
        return float(np.max(np.abs(a.x[:, 0] - b.x[:, 0])))

    hs = np.array([0.004, 0.002, 0.001])
    d = np.array([diff(h) for h in hs])
    slope = np.polyfit(np.log(hs), np.log(d), 1)[0]
    assert abs(slope - 1.0) < 0.3, (slope, d)


# ------------------------------------------------------------------------ stability
def _light_oscillator(omega: float, zeta: float, held_damping: bool = True) -> mb.Dynamics:
    """ẍ + 2ζωẋ + ω²x = 0, the damping force as the held part (extrapolated quadratically, as the turbine's
    aerodynamics: what is tested is the method's own stability, not a held stiffness's delay), or nothing held
    (a zero force: the method's characteristic polynomial alone)."""
    x, u, p, z = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 0), ca.SX.sym("z", 1)
    damping = -2 * zeta * omega * x[1]
    part = ca.Function("part", [x, u, p], [damping if held_damping else 0.0 * x[1]])
    rest = -omega ** 2 * x[0] + (0.0 if held_damping else damping)
    rhs_z = ca.Function("rhs_z", [x, u, p, z], [ca.vertcat(x[1], z[0] + rest + u[0])])
    out_z = ca.Function("out_z", [x, u, p, z], [x[0]])
    rhs = ca.Function("rhs", [x, u, p], [rhs_z(x, u, p, part(x, u, p))])
    out = ca.Function("out", [x, u, p], [out_z(x, u, p, part(x, u, p))])
    return mb.Dynamics(rhs, states=["x", "x_d"], inputs=["f"], outputs=out, output_names=["X"],
                       held=HeldPart(part, rhs_z, out_z, "damping"))


def _tail_amplitudes(method: str, omega: float, zeta: float, h: float, periods: int,
                     held_damping: bool = True) -> tuple[float, float]:
    """Largest |x| over the last period of ``periods``, integrated and from the closed form (x0 = 1)."""
    tmax = periods * 2 * np.pi / omega
    n = int(np.ceil(tmax / h))
    res = simulate(_light_oscillator(omega, zeta, held_damping), n * h, x0=[1.0, 0.0], controller=_zero_controller(h),
                   method=method, dt=h, t_out=np.round(np.arange(n + 1) * h, 12), held_order=2)
    x_ref, _ = sdof_response(res.t, 1.0, 2 * zeta * omega, omega ** 2, x0=1.0, v0=0.0)
    tail = slice(-int(np.ceil(2 * np.pi / omega / h)), None)          # the last period
    return float(np.max(np.abs(res.state("x")[tail]))), float(np.max(np.abs(x_ref[tail])))


@pytest.mark.parametrize("method", METHODS)
def test_lightly_damped_mode_at_the_turbine_step(method):
    """A 4 Hz mode, ζ = 0.5 % (above the NREL 5 MW's structural modes), 6.25 ms steps (ω h = 0.157), 30 periods:
    the amplitude equals the closed form's within 2 % (the characteristic polynomials predict +0.27 % for ABM4,
    which is weakly anti-damping on the imaginary axis, and -0.9 % for AB4; measured +0.22 / -0.34 %)."""
    num, ref = _tail_amplitudes(method, 2 * np.pi * 4.0, 0.005, 0.00625, 30)
    assert abs(num / ref - 1.0) < 0.02, (num, ref)


def test_ab4_unstable_beyond_its_interval_abm4_not():
    """ω h = 0.5, ζ = 2 %: outside AB4's stability interval (ω h < 0.43 at this damping; its amplitude grows ~3.8×
    per period), inside ABM4's (< 0.92; it decays, ~0.90× per period; RK4's interval is 2.8). AB4 is reported as
    diverged or found grown; ABM4 decays below its start."""
    omega, h = 50.0, 0.01
    num, _ = _tail_amplitudes("abm4-held", omega, 0.02, h, 20)
    assert num < 0.5, num
    try:
        grown, _ = _tail_amplitudes("ab4-held", omega, 0.02, h, 20)
    except IntegrationError:
        return
    assert grown > 10.0, grown


@pytest.mark.parametrize("method, zeta", [("ab4-held", 0.02), ("abm4-held", 0.02), ("abm4-held", 0.7)])
def test_stability_limit_matches_the_simulated_mode(method, zeta):
    """stability_limit (from the characteristic polynomial) against the loop itself, nothing held (the method
    alone): 5 % below the limit the mode decays over 40 periods, 5 % above it grows beyond its start."""
    from mbsym.simulate.held_multistep import stability_limit

    limit, h = stability_limit(method, zeta), 0.01
    below, _ = _tail_amplitudes(method, 0.95 * limit / h, zeta, h, 40, held_damping=False)
    assert below < 1.0, (limit, below)
    try:
        above, _ = _tail_amplitudes(method, 1.05 * limit / h, zeta, h, 40, held_damping=False)
    except IntegrationError:
        return
    assert above > 1.0, (limit, above)


# ------------------------------------------------------------------------ options
def test_without_a_controller_refused():
    with pytest.raises(SimulationOptionError, match="controller="):
        simulate(held_oscillator(), 0.1, x0=[0.1, 0.0], method="abm4-held", dt=0.01)


def test_without_a_held_part_refused():
    dyn = held_oscillator()
    plain = mb.Dynamics(dyn.rhs, states=dyn.states, inputs=dyn.inputs, outputs=dyn.outputs,
                        output_names=dyn.output_names)
    with pytest.raises(SimulationOptionError, match="declares none"):
        simulate(plain, 0.1, x0=[0.1, 0.0], controller=_p_controller(0.01), method="ab4-held", dt=0.01)


def test_sub_steps_refused():
    with pytest.raises(SimulationOptionError, match="one step per controller sample"):
        simulate(held_oscillator(), 0.1, x0=[0.1, 0.0], controller=_p_controller(0.01), method="abm4-held",
                 dt=0.005)


def test_a_constant_command_law_in_the_loop():
    """A law whose command is the constant 0 (a structural zero in the generated body) leaves the free oscillator:
    "rk4" at 10 ms against the closed form within RK4's error (measured ~1e-7 m; 1e-5 of the 0.1 m amplitude)."""
    t_out = np.round(np.linspace(0.0, 2.0, 41), 12)
    res = simulate(held_oscillator(), 2.0, x0=[0.1, 0.0], controller=_zero_controller(0.01), method="rk4", dt=0.01,
                   t_out=t_out)
    x_ref, _ = sdof_response(res.t, M, C + GAMMA, K + KAPPA, x0=0.1, v0=0.0)
    assert np.max(np.abs(res.state("x") - x_ref)) < 1e-6


def test_python_law_refused():
    ctrl = DiscreteController(lambda t, xc, y: (xc, np.array([-50.0 * y[0] - 5.0 * y[1]])), 0.01,
                              measurements=["X", "x_d"], actuates=["f"])
    with pytest.raises(SimulationOptionError, match="Python"):
        simulate(held_oscillator(), 0.1, x0=[0.1, 0.0], controller=ctrl, method="abm4-held", dt=0.01)
