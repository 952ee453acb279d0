"""Energy and period of an undamped simple pendulum (m = 1 kg, l = 1 m, g = 9.81 m/s^2, 1 rad amplitude).

References: energy conservation (T + V constant, mbsym's own energy Functions, which the core tests
check against closed forms), and the exact period 4 sqrt(l/g) K(sin^2(theta0/2)) (elliptic integral,
scipy.special.ellipk). rk4 is not symplectic: on a linear oscillator its amplification factor obeys
|R(i omega dt)|^2 = 1 - (omega dt)^6 / 72 + ..., so the energy decays at ~ omega (omega dt)^5 / 72 per
unit time: 7.8e-8 of the swing energy over 60 s at dt = 0.01 s (omega = 3.13 rad/s). Measured
5.8e-8 -> bound 2e-7; halving dt must divide the drift by ~2^5 = 32.
"""

import numpy as np

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
