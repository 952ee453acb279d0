"""Energy behaviour of undamped systems, and the period of a simple pendulum.

Pendulum: m = 1 kg, l = 1 m, g = 9.81 m/s^2, 1 rad amplitude; linear oscillator: m = 2 kg,
k = 50 N/m, c = 0 (omega = 5 rad/s), energy 1/2 m v^2 + 1/2 k x^2 in closed form.

References: energy conservation (T + V constant, mbsym's own energy Functions, which the core tests
check against closed forms), and the exact period 4 sqrt(l/g) K(sin^2(theta0/2)) (elliptic integral,
scipy.special.ellipk). rk4 is not symplectic: on a linear oscillator its amplification factor obeys
|R(i omega dt)|^2 = 1 - (omega dt)^6 / 72 + ..., so the energy decays at ~ omega (omega dt)^5 / 72 per
unit time: 7.8e-8 of the swing energy over 60 s at dt = 0.01 s (omega = 3.13 rad/s). Measured
5.8e-8 -> bound 2e-7; halving dt must divide the drift by ~2^5 = 32.
"""

import numpy as np
import pytest

from mbsym.simulate import simulate

from ._reference import pendulum_period

P = {"m": 1.0, "l": 1.0}


def _energy(eom, res, every=20):
    return np.array([eom.kinetic_energy(q, qd, P) + eom.potential_energy(q, P)
                     for q, qd in zip(res.q[::every], res.qd[::every])])


def _relative_drift(eom, dt):
    res = simulate(eom, 60.0, x0={"th": 1.0}, p=P, dt=dt)
    E = _energy(eom, res)
    V_bottom = eom.potential_energy([0.0], P)
    return np.max(np.abs(E - E[0])) / abs(E[0] - V_bottom), res


def test_rk4_energy_drift_small(pend):
    drift, _ = _relative_drift(pend, 0.01)
    assert drift < 2e-7, f"relative energy drift {drift:.3g} over 60 s"
    drift_coarse, _ = _relative_drift(pend, 0.02)
    assert 20.0 < drift_coarse / drift < 45.0, (drift_coarse, drift)


def test_rk4_pendulum_period_matches_elliptic_integral(pend):
    res = simulate(pend, 60.0, x0={"th": 1.0}, p=P, dt=0.01)
    th, t = res.state("th"), res.t
    i = np.flatnonzero((th[:-1] > 0.0) & (th[1:] <= 0.0))
    crossings = t[i] - th[i] * (t[i + 1] - t[i]) / (th[i + 1] - th[i])     # linear, error ~ dt^2 th''
    period = np.mean(np.diff(crossings))
    exact = pendulum_period(1.0, P["l"], 9.81)
    # crossings at the fastest point of the swing (th'' = 0): linear interpolation error ~1e-7 s
    assert abs(period - exact) < 1e-6 * exact, (period, exact)


def test_cvodes_energy_bounded(pend):
    res = simulate(pend, 60.0, x0={"th": 1.0}, p=P, method="cvodes", rtol=1e-10, atol=1e-12)
    E = _energy(pend, res, every=1)
    assert np.max(np.abs(E - E[0])) / abs(E[0] - pend.potential_energy([0.0], P)) < 1e-6


UNDAMPED = {"m": 2.0, "k": 50.0, "c": 0.0}


def _oscillator_energy(res):
    return 0.5 * UNDAMPED["m"] * res.x[:, 1] ** 2 + 0.5 * UNDAMPED["k"] * res.x[:, 0] ** 2


@pytest.mark.parametrize("dt", [0.01, 0.1, 1.0])
def test_newmark_conserves_linear_energy(osc, dt):
    """The average-acceleration rule conserves the energy of a linear undamped system exactly, at any
    step (omega dt = 0.05 ... 5): round-off only (measured 3e-15 ... 2e-14 over 200 s)."""
    res = simulate(osc, 200.0, x0=[1.0, 0.5], p=UNDAMPED, method="newmark", dt=dt)
    E = _oscillator_energy(res)
    assert np.max(np.abs(E - E[0])) / E[0] < 1e-12


def test_generalized_alpha_damps_only_unresolved_frequencies(osc):
    """rho_inf = 0.8: at omega dt = 0.05 it loses < 1e-3 of the energy over 200 s (measured 1.7e-4);
    at omega dt = 5 (unresolved) the spectral radius is 0.968 (0.8 only as omega dt -> inf): the
    energy shrinks by 0.968^2 per step, 2.4e-6 left after 200 steps (bound 1e-4)."""
    fine = _oscillator_energy(simulate(osc, 200.0, x0=[1.0, 0.5], p=UNDAMPED, method="generalized-alpha",
                                       dt=0.01))
    coarse = _oscillator_energy(simulate(osc, 200.0, x0=[1.0, 0.5], p=UNDAMPED, method="generalized-alpha",
                                         dt=1.0))
    assert 0.0 < (fine[0] - fine[-1]) / fine[0] < 1e-3
    assert coarse[-1] / coarse[0] < 1e-4


def test_newmark_pendulum_energy_bounded_without_drift(pend):
    """Nonlinear pendulum, 600 s at dt = 0.01 s: the trapezoidal rule's energy error oscillates,
    O((omega dt)^2) (measured 3.76e-5 of the swing energy), with no secular drift: the largest
    deviation in the second half equals the first half's (to 1 %)."""
    res = simulate(pend, 600.0, x0={"th": 1.0}, p=P, method="newmark", dt=0.01)
    E = _energy(pend, res, every=10)
    swing = E[0] - pend.potential_energy([0.0], P)
    half = E.size // 2
    first, second = (np.max(np.abs(part - E[0])) / swing for part in (E[:half], E[half:]))
    assert first < 1e-4 and second < 1.01 * first, (first, second)
