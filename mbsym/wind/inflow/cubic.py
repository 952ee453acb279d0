"""InflowWind's cubic interpolation of the wind in time (``VelInterpCubic = True``), OpenFAST v5.0.0.

Facts from ``modules/inflowwind/src/IfW_FlowField.f90`` and ``InflowWind.f90`` (v5.0.0), restated:

**Uniform wind** (``WindType`` 1, 2; ``UniformField_InterpCubic``): at initialisation
(``IfW_UniformField_CalcAccel``) each column ``y`` of the file (the direction after its unwrapping)
gets a slope ``y'`` at every row from a *clamped* cubic spline through the rows (first derivative
zero at the first and the last row; rows may be unevenly spaced). The slope of a row is the
derivative, at its left end, of the spline piece that starts there; the last row's slope is set to
0. The slopes are rounded to single precision (``real(..., SiKi)``). Between rows ``i`` and ``i+1``
(``h = t_{i+1} - t_i``, ``s = (t - t_i) / h``) a column is the cubic Hermite polynomial

    y(t) = (2s³ - 3s² + 1) y_i + (s³ - 2s² + s) h y'_i + (3s² - 2s³) y_{i+1} + (s³ - s²) h y'_{i+1};

before the first row and from the last row on the rows' values are held (as the linear rule).
Steady wind (one row) is unchanged. The velocity at a point then follows from the interpolated
columns exactly as with linear interpolation (:mod:`mbsym.wind.inflow.uniform`).

**Full fields** (``Grid3D``: ``WindType`` 3, 4, 5, 7; ``Grid3DField_GetVelAccCubic``): the cell and
its spatial weights are those of linear interpolation (same ``GetBoundsT``, also at the ends and for
periodic fields), the spatial interpolation is done at the cell's two times (``P_lo``, ``P_hi``) and
the Hermite polynomial above joins them with the slopes ``PP_lo``, ``PP_hi`` of the cell's corners
(``h = dt``, ``s = (ξ_t + 1) / 2``); a HAWC/native Bladed mean profile is added after
(``AddMeanAfterInterp``). In an OpenFAST v5.0.0 run the slopes are not what InflowWind computes at
initialisation (``IfW_Grid3DField_CalcAccel``): ``IfW_FlowField_GetVelAcc`` fetches the corner slopes
only when accelerations are output (``CalcAccel = OutputAccel``, which no OpenFAST glue code sets),
so its local ``AccCell`` is used uninitialised. Measured against the v5.0.0 binary (tests/wind/inflow,
``ifw_reference.py``): ``u`` and ``v`` everywhere and all components along the tower (2-D cells) come out
with zero slopes to OpenFAST's 9 digits; ``w`` in 3-D cells differs by up to 0.8 m/s (stack contents; NaN
in other builds: OpenFAST pull request #3428, fixed in 5.0.1). mbsym uses **zero slopes** for all three
components: ``v = C1 P_lo + C3 P_hi`` (a smooth step between the samples; the velocity's time
derivative is zero at every sample). (Even when accelerations are output, v5.0.0 sets all slopes to zero
for files with fewer than 3 tower points: its ``NTGrids < 3`` test.)

**Where InflowWind drops it**: for linearization (``Linearize = True``: "Cubic interpolation of wind velocity
is disabled for linearization") and field types it does not implement (it prints and goes on linearly).
"""

from __future__ import annotations

import numpy as np

__all__ = ["uniform_slopes", "hermite_weights", "hermite_value", "smooth_step_coordinate"]


def uniform_slopes(time: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Slopes of the columns at the rows, as InflowWind's ``IfW_UniformField_CalcAccel``.

    Parameters
    ----------
    time : array (n,)
        Row times [s], strictly increasing.
    values : array (n,) or (n, k)
        Column values at the rows (any unit ``U``).

    Returns
    -------
    ndarray
        Slopes [U/s], the shape of ``values``: a clamped cubic spline (zero slope at both ends),
        the derivative at the left end of each piece, the last row 0, rounded to float32 (then float64).
        Fewer than 3 rows: zeros.
    """
    x = np.asarray(time, dtype=float)
    y = np.asarray(values, dtype=float)
    flat = y.reshape(x.size, -1)
    n = x.size
    dy = np.zeros_like(flat)
    if n < 3:
        return dy.reshape(y.shape)
    d2 = np.zeros_like(flat)                                 # InflowWind's dy2 (second derivatives)
    u = np.zeros_like(flat)
    d2[0] = -0.5
    u[0] = 3.0 * (flat[1] - flat[0]) / (x[1] - x[0]) ** 2     # zero first derivative at the first row
    for i in range(1, n - 1):
        sig = (x[i] - x[i - 1]) / (x[i + 1] - x[i - 1])
        p = sig * d2[i - 1] + 2.0
        d2[i] = (sig - 1.0) / p
        u[i] = (6.0 * ((flat[i + 1] - flat[i]) / (x[i + 1] - x[i]) - (flat[i] - flat[i - 1]) / (x[i] - x[i - 1]))
                / (x[i + 1] - x[i - 1]) - sig * u[i - 1]) / p
    un = -3.0 * (flat[n - 1] - flat[n - 2]) / (x[n - 1] - x[n - 2]) ** 2   # zero first derivative at the last
    d2[n - 1] = (un - 0.5 * u[n - 2]) / (0.5 * d2[n - 2] + 1.0)
    for i in range(n - 2, -1, -1):
        d2[i] = d2[i] * d2[i + 1] + u[i]
        h = x[i + 1] - x[i]
        slope = (flat[i + 1] - flat[i]) / h - h * (d2[i] / 3.0 + d2[i + 1] / 6.0)
        dy[i] = slope.astype(np.float32)                      # real(..., SiKi)
    return dy.reshape(y.shape)


def hermite_weights(s):
    """The cubic Hermite weights ``(C1, C2/h, C3, C4/h)`` at the fraction ``s`` in [0, 1] of an interval.

    ``y = C1 y_0 + C2 y'_0 + C3 y_1 + C4 y'_1`` with ``C2 = (s³ - 2s² + s) h``, ``C4 = (s³ - s²) h``
    (InflowWind's ``UniformField_InterpCubic`` and ``Grid3DField_GetVelAccCubic``).
    """
    s = np.asarray(s, dtype=float)
    c1 = 2.0 * s * s * s - 3.0 * s * s + 1.0
    c2 = s * s * s - 2.0 * s * s + s
    c3 = -2.0 * s * s * s + 3.0 * s * s
    c4 = s * s * s - s * s
    return c1, c2, c3, c4


def hermite_value(table_time: np.ndarray, values: np.ndarray, slopes: np.ndarray, t) -> np.ndarray:
    """InflowWind's ``UniformField_InterpCubic`` of one column at times ``t`` [s].

    Parameters
    ----------
    table_time : array (n,)
        Row times [s].
    values, slopes : array (n,)
        The column and its slopes (:func:`uniform_slopes`) [U], [U/s].
    t : float or array
        Times [s].

    Returns
    -------
    ndarray
        The column at ``t`` [U], the shape of ``t``: rows held before the first and from the last row on.
    """
    x = np.asarray(table_time, dtype=float)
    tt = np.asarray(t, dtype=float)
    out = np.empty(tt.shape)
    flat_t, flat_o = tt.reshape(-1), out.reshape(-1)
    if x.size == 1:
        flat_o[:] = values[0]
        return out
    before, after = flat_t < x[0], flat_t >= x[-1]
    flat_o[before], flat_o[after] = values[0], values[-1]
    inside = ~(before | after)
    ti = flat_t[inside]
    i = np.searchsorted(x, ti, side="right")              # first row with time > t (InflowWind's search)
    h = x[i] - x[i - 1]
    c1, c2, c3, c4 = hermite_weights((ti - x[i - 1]) / h)
    flat_o[inside] = c1 * values[i - 1] + c2 * h * slopes[i - 1] + c3 * values[i] + c4 * h * slopes[i]
    return out


def smooth_step_coordinate(xt: np.ndarray) -> np.ndarray:
    """The time coordinate in [-1, 1] that makes linear interpolation give the zero-slope Hermite step.

    A full field's cubic interpolation (module docstring) weighs the cell's two times by ``C1`` and
    ``C3 = 3s² - 2s³`` (``s = (ξ + 1) / 2``); returned is ``2 C3 - 1`` [-].
    """
    s = (np.asarray(xt, dtype=float) + 1.0) / 2.0
    return 2.0 * (-2.0 * s * s * s + 3.0 * s * s) - 1.0
