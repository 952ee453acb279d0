"""Discrete-time building blocks of the baseline controller, as CasADi SX expressions (private).

Each block returns its output and its next state; ``reset`` (an SX 0/1) re-initializes
the block the way ROSCO does at its first call (filters start at their input, a PI
controller outputs its initial value, a rate limiter passes its reset value).
The filters are ROSCO's Tustin (bilinear) discretizations of

- first order ``H(s) = ω / (s + ω)``;
- second order ``H(s) = ω² / (s² + 2ζω s + ω²)``;
- first-order high-pass ``H(s) = s / (s + ω)``;
- notch ``H(s) = (s² + 2β_num ω s + ω²) / (s² + 2β_den ω s + ω²)``.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

# ROSCO's conversion constants (Constants.f90), used where ROSCO converts, to stay bit-close.
R2D = 57.2957795130
D2R = 0.01745329251
EPS = float(np.finfo(float).eps)


def sat(x, lo, hi):
    """``min(max(x, lo), hi)`` (ROSCO's ``saturate``)."""
    return ca.fmin(ca.fmax(x, lo), hi)


def lpf1(u, last_in, last_out, corner: float, dt: float, reset, initial=None):
    """First-order low-pass filter step → (y, next last_in, next last_out)."""
    init = u if initial is None else initial
    last_in = ca.if_else(reset, init, last_in)
    last_out = ca.if_else(reset, init, last_out)
    a1, a0, b = 2.0 + corner * dt, corner * dt - 2.0, corner * dt
    y = (-a0 * last_out + b * u + b * last_in) / a1
    return y, u, y


def lpf2(u, states, corner: float, damping: float, dt: float, reset):
    """Second-order low-pass filter step; ``states = (in1, in2, out1, out2)`` → (y, next states)."""
    in1, in2, out1, out2 = (ca.if_else(reset, u, s) for s in states)
    c = dt**2 * corner**2
    a2, a1, a0 = c + 4.0 + 4.0 * damping * corner * dt, 2.0 * c - 8.0, c + 4.0 - 4.0 * damping * corner * dt
    y = (c * u + 2.0 * c * in1 + c * in2 - a1 * out1 - a0 * out2) / a2
    return y, (u, in1, y, out1)


def pi(error, kp, ki, lo, hi, dt: float, integral, initial, reset):
    """PI controller with a saturated integrator → (output, next integral)."""
    integral_next = sat(integral + dt * ki * error, lo, hi)
    out = sat(kp * error + integral_next, lo, hi)
    return ca.if_else(reset, initial, out), ca.if_else(reset, initial, integral_next)


def rate_limit(u, last, rate_min: float, rate_max: float, dt: float, reset, reset_value=None):
    """Rate limiter → (output, next last).  On reset the output is ``reset_value`` (default ``u``)."""
    value = u if reset_value is None else reset_value
    rate = sat((u - last) / dt, rate_min, rate_max)
    out = ca.if_else(reset, value, last + rate * dt)
    return out, out


def interp1(grid, values, name: str):
    """Clamped piecewise-linear lookup ``q -> values(q)`` (ROSCO's ``interp1d``) as a Python callable on SX.

    A CasADi ``linear`` interpolant with binary search on the clamped query; measured
    faster than writing the hat functions out in SX (668 vs 5400 instructions for the
    whole controller step) and than the default linear search (2.8 vs 4.3 µs per
    compiled step).
    """
    grid = np.asarray(grid, dtype=float)
    values = np.asarray(values, dtype=float)
    if grid.size == 1:
        return lambda q: ca.SX(float(values[0]))
    table = ca.interpolant(name, "linear", [grid], values, {"lookup_mode": ["binary"]})
    return lambda q: table(sat(q, grid[0], grid[-1]))


def interp2(x_grid, y_grid, data, name: str):
    """Clamped bilinear lookup ``(x, y) -> data[y, x]`` (ROSCO's ``interp2d``; ``data`` rows follow ``y_grid``)."""
    x_grid, y_grid = np.asarray(x_grid, dtype=float), np.asarray(y_grid, dtype=float)
    data = np.asarray(data, dtype=float)
    table = ca.interpolant(name, "linear", [y_grid, x_grid], data.ravel(order="F"),
                           {"lookup_mode": ["binary", "binary"]})
    return lambda x, y: table(ca.vertcat(sat(y, y_grid[0], y_grid[-1]), sat(x, x_grid[0], x_grid[-1])))


def bandpass(u, states, corner, damping: float, dt: float, reset):
    """ROSCO's moving "inverted notch" (a band-pass) step; ``states = (in1, in2, out1, out2)`` → (y, next states).

    Tustin discretization of ``H(s) = ω s / (ζ s² + ω s + ζ ω²)`` (unit gain at ``ω``);
    ``corner`` ω [rad/s] may change every step (negative values count as 0).  On
    reset every state takes the input, as ROSCO's ``NotchFilterSlopes`` does.
    """
    w = ca.fmax(corner, 0.0)
    in1, _, out1, out2 = (ca.if_else(reset, u, s) for s in states)
    b2 = 2.0 * dt * w
    c = damping * dt**2 * w**2
    a2, a1, a0 = c + 2.0 * dt * w + 4.0 * damping, 2.0 * c - 8.0 * damping, c - 2.0 * dt * w + 4.0 * damping
    y = 1.0 / a2 * (b2 * u - b2 * in1 - a1 * out1 - a0 * out2)
    return y, (u, in1, y, out1)


def hpf1(u, last_in, last_out, corner: float, dt: float, reset):
    """First-order high-pass filter step (ROSCO's ``HPFilter``) → (y, next last_in, next last_out).

    On reset both memories take the input, so the output starts at 0 for a constant input.
    """
    last_in = ca.if_else(reset, u, last_in)
    last_out = ca.if_else(reset, u, last_out)
    k = 2.0 / dt
    y = k / (corner + k) * u - k / (corner + k) * last_in - (corner - k) / (corner + k) * last_out
    return y, u, y


def notch(u, states, freq: float, beta_num: float, beta_den: float, dt: float, reset):
    """Notch filter step (ROSCO's ``NotchFilter``, Tustin); ``states = (in1, in2, out1, out2)`` → (y, next states)."""
    in1, in2, out1, out2 = (ca.if_else(reset, u, s) for s in states)
    k, w = 2.0 / dt, freq
    den = k**2 + 2.0 * w * beta_den * k + w**2
    b2 = (k**2 + 2.0 * w * beta_num * k + w**2) / den
    b1 = (2.0 * w**2 - 2.0 * k**2) / den
    b0 = (k**2 - 2.0 * w * beta_num * k + w**2) / den
    a1 = (2.0 * w**2 - 2.0 * k**2) / den
    a0 = (k**2 - 2.0 * w * beta_den * k + w**2) / den
    y = b2 * u + b1 * in1 + b0 * in2 - a1 * out1 - a0 * out2
    return y, (u, in1, y, out1)


def round_float32(x):
    """``x`` rounded to the nearest single-precision number (Veltkamp's split: ``c − (c − x)`` with
    ``c = (2²⁹ + 1)·x`` keeps 24 significant bits), as ROSCO reads the time from its float32 swap array.
    Exact for |x| < 1e300 away from single precision's subnormals; ties may round away from even."""
    c = x * (2.0**29 + 1.0)
    return c - (c - x)


def controller_time(x: dict, nxt: dict, dt: float, reset):
    """ROSCO's ``Time`` [s] at this call: the step count (state ``step_count``, 0 at the first call) times
    ``dt``, rounded to single precision as the host's time is in the swap array (the run starting at t = 0)."""
    n = ca.if_else(reset, 0.0, x["step_count"])
    nxt["step_count"] = n + 1.0
    return round_float32(n * dt)


def sigma(t, t0, t1, y0, y1):
    """ROSCO's ``sigma``: the cubic step from ``y0`` at ``t0`` to ``y1`` at ``t1`` (zero slope at both ends),
    ``y0`` before ``t0`` and ``y1`` after ``t1``; its coefficients as ROSCO's Functions.f90 forms them."""
    d3 = (t0 - t1) ** 3
    a3, a2, a1, a0 = 2.0 / d3, -3.0 * (t0 + t1) / d3, 6.0 * t1 * t0 / d3, (t0 - 3.0 * t1) * t0**2 / d3
    ramp = (a3 * t**3 + a2 * t**2 + a1 * t + a0) * (y1 - y0) + y0
    return ca.if_else(t < t0, y0, ca.if_else(t > t1, y1, ramp))
