"""Closed-form references for the simulation tests (numpy and scipy only; no mbsym code).

- ``sdof_response``: the damped single-degree-of-freedom oscillator
  ``m x'' + c x' + k x = a0 + a1 t`` (underdamped), from the textbook solution:
  a particular solution ``A + B t`` plus the homogeneous
  ``exp(-sigma t) (C1 cos(wd t) + C2 sin(wd t))`` fitted to ``x(0), x'(0)``.
- ``sdof_harmonic_response``: the same oscillator under ``F0 sin(w t)``; particular solution
  ``A sin(w t) + B cos(w t)`` with ``[k - m w^2, -c w; c w, k - m w^2] [A; B] = [F0; 0]``, plus the
  homogeneous solution fitted to ``x(0), x'(0)``.
- ``pendulum_period``: the exact period of a simple pendulum of amplitude
  ``theta0``, ``T = 4 sqrt(l / g) K(sin^2(theta0 / 2))`` (complete elliptic
  integral of the first kind, parameter m = k^2, as in ``scipy.special.ellipk``).
"""

from __future__ import annotations

import numpy as np
from scipy.special import ellipk


def sdof_response(t, m, c, k, x0=0.0, v0=0.0, a0=0.0, a1=0.0):
    """Displacement [m] and velocity [m/s] of ``m x'' + c x' + k x = a0 + a1 t``; underdamped only."""
    t = np.asarray(t, dtype=float)
    sigma = c / (2.0 * m)
    wd = np.sqrt(k / m - sigma**2)
    B = a1 / k
    A = (a0 - c * B) / k
    C1 = x0 - A
    C2 = (v0 - B + sigma * C1) / wd
    e, cs, sn = np.exp(-sigma * t), np.cos(wd * t), np.sin(wd * t)
    x = A + B * t + e * (C1 * cs + C2 * sn)
    v = B + e * ((-sigma * C1 + wd * C2) * cs + (-sigma * C2 - wd * C1) * sn)
    return x, v


def sdof_harmonic_response(t, m, c, k, F0, w, x0=0.0, v0=0.0):
    """Displacement [m] and velocity [m/s] of ``m x'' + c x' + k x = F0 sin(w t)``; underdamped only."""
    t = np.asarray(t, dtype=float)
    a, b = k - m * w * w, c * w
    A, B = F0 * a / (a * a + b * b), -F0 * b / (a * a + b * b)
    sigma = c / (2.0 * m)
    wd = np.sqrt(k / m - sigma**2)
    C1 = x0 - B
    C2 = (v0 - A * w + sigma * C1) / wd
    e, cs, sn = np.exp(-sigma * t), np.cos(wd * t), np.sin(wd * t)
    x = A * np.sin(w * t) + B * np.cos(w * t) + e * (C1 * cs + C2 * sn)
    v = (A * w * np.cos(w * t) - B * w * np.sin(w * t)
         + e * ((-sigma * C1 + wd * C2) * cs + (-sigma * C2 - wd * C1) * sn))
    return x, v


def ramp_hold_response(t, m, c, k, slope, t1):
    """Response from rest to ``F = slope * min(t, t1)``: a ramp minus a delayed ramp (superposition)."""
    t = np.asarray(t, dtype=float)
    x, v = sdof_response(t, m, c, k, a1=slope)
    late = t > t1
    xd, vd = sdof_response(t[late] - t1, m, c, k, a1=slope)
    x[late] -= xd
    v[late] -= vd
    return x, v


def pendulum_period(theta0, length, g):
    """Exact period [s] of a simple pendulum released from rest at ``theta0`` [rad]."""
    return 4.0 * np.sqrt(length / g) * ellipk(np.sin(theta0 / 2.0) ** 2)
