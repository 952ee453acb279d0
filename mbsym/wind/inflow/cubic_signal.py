"""Hub-height wind signals cubic in time, for InflowWind's ``VelInterpCubic = True`` (:mod:`.cubic`).

- :class:`HermiteTableWind`: a table with slopes, cubic Hermite between its rows, held beyond the ends
  (a full field's hub series: zero slopes; InflowWind's rule for uniform wind with the spline's slopes);
- :class:`CubicUniformHubWind`: the longitudinal hub wind ``(HorSpd + GstSpd) cos(Upflow) cos(WndDir)`` of a
  cubic :class:`~mbsym.wind.inflow.UniformFieldWind`, each column interpolated on its own as InflowWind does.

Both are :class:`~mbsym.wind.inflow.WindSignal`: callables of time for :func:`mbsym.simulate`, with a CasADi
form (the row is found by a linear lookup of the row index, exact at the rows).
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ...exceptions import WindInputError
from .cubic import hermite_value
from .signals import WindSignal

__all__ = ["HermiteTableWind", "CubicUniformHubWind"]


def _hermite_sx(t: ca.SX, time: np.ndarray, values: np.ndarray, slopes: np.ndarray, name: str) -> ca.SX:
    """The Hermite interpolation of :func:`~mbsym.wind.inflow.cubic.hermite_value` as an SX of ``t``."""
    n = time.size
    if n == 1:
        return ca.SX(float(values[0]))
    index = np.arange(n, dtype=float)
    position = ca.interpolant(f"{name}_row", "linear", [time], index)(ca.fmin(ca.fmax(t, time[0]), time[-1]))
    i = ca.fmin(ca.floor(position), n - 2)
    s = position - i

    def at(array, k):
        return ca.interpolant(f"{name}_at", "linear", [index], np.asarray(array, dtype=float))(k)

    h = at(np.append(np.diff(time), 1.0), i)
    c1 = 2.0 * s * s * s - 3.0 * s * s + 1.0
    c2 = (s * s * s - 2.0 * s * s + s) * h
    c3 = -2.0 * s * s * s + 3.0 * s * s
    c4 = (s * s * s - s * s) * h
    return c1 * at(values, i) + c2 * at(slopes, i) + c3 * at(values, i + 1) + c4 * at(slopes, i + 1)


class HermiteTableWind(WindSignal):
    """Wind speed ``speed`` [m/s] with slopes ``slopes`` [m/s²] at ``time`` [s]: cubic Hermite in between,
    held beyond the ends (InflowWind's ``VelInterpCubic`` rule).

    Parameters
    ----------
    time, speed, slopes : array (n,)
        Rows (times strictly increasing), speeds and their time derivatives.
    source : str
        Where it came from (for messages).
    """

    def __init__(self, time, speed, slopes, *, source: str = "table") -> None:
        t = np.array(time, dtype=float).reshape(-1)
        u = np.array(speed, dtype=float).reshape(-1)
        d = np.array(slopes, dtype=float).reshape(-1)
        if t.size < 1 or t.shape != u.shape or t.shape != d.shape:
            raise WindInputError(f"{source}: time, speed and slopes must be 1-D arrays of one length >= 1; got "
                                 f"{t.size}, {u.size} and {d.size}.")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(u)) and np.all(np.isfinite(d))):
            raise WindInputError(f"{source}: times, speeds and slopes must be finite.")
        if np.any(np.diff(t) <= 0.0):
            raise WindInputError(f"{source}: times must strictly increase.")
        for a in (t, u, d):
            a.setflags(write=False)
        self.time, self.speed, self.slopes, self.source = t, u, d, source

    @property
    def knots(self) -> np.ndarray:
        return self.time

    def _table_times(self, t_end: float, dt: float) -> np.ndarray:
        return np.concatenate([self.time, np.arange(0.0, t_end, dt)])      # cubic between rows: sample it

    def sample(self, t) -> np.ndarray:
        return hermite_value(self.time, self.speed, self.slopes, t)

    def _casadi(self, t: ca.SX) -> ca.SX:
        return _hermite_sx(t, self.time, self.speed, self.slopes, "wind_hermite")

    def __repr__(self) -> str:
        return (f"HermiteTableWind({self.source}: {self.time.size} points over [{self.time[0]:g}, "
                f"{self.time[-1]:g}] s, cubic in time)")


class CubicUniformHubWind(WindSignal):
    """The hub wind ``(HorSpd + GstSpd) cos(Upflow) cos(WndDir)`` [m/s] of a cubic uniform field.

    Parameters
    ----------
    field : UniformFieldWind
        With ``cubic=True``.
    """

    def __init__(self, field) -> None:
        if not getattr(field, "cubic", False):
            raise WindInputError("CubicUniformHubWind needs a UniformFieldWind with cubic=True.")
        self.field = field

    @property
    def knots(self) -> np.ndarray:
        return self.field.table.time

    def _table_times(self, t_end: float, dt: float) -> np.ndarray:
        return np.concatenate([self.knots, np.arange(0.0, t_end, dt)])

    def sample(self, t) -> np.ndarray:
        c = self.field.columns_at(np.asarray(t, dtype=float))
        return (np.asarray(c["speed"]) + c["gust_speed"]) * np.cos(c["upflow"]) * np.cos(c["direction"])

    def _casadi(self, t: ca.SX) -> ca.SX:
        from .uniform import COLUMN_NAMES

        f = self.field
        col = {name: _hermite_sx(t, f.table.time, f._column(name), f._slopes[:, k], f"wind_{name}")
               for k, name in enumerate(COLUMN_NAMES) if name in ("speed", "gust_speed", "upflow", "direction")}
        return (col["speed"] + col["gust_speed"]) * ca.cos(col["upflow"]) * ca.cos(col["direction"])

    def __repr__(self) -> str:
        return f"CubicUniformHubWind({self.field.source or 'uniform wind'}: {self.knots.size} rows, cubic in time)"
