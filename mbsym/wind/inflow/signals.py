"""Hub-height wind speed signals U(t): steady, step, ramp, IEC extreme operating gust, tables.

A :class:`WindSignal` is the longitudinal wind speed at hub height [m/s] as a
function of time [s] (what OpenFAST writes as ``Wind1VelX`` at the hub).  Every
signal

- evaluates on a time grid as numpy (``wind(t)``, ``wind.sample(t)``), so it can
  be given to :func:`mbsym.simulate` as a callable input (``inputs={"wind": wind}``);
- gives an exact piecewise-linear table ``wind.table(t_end)`` → ``(grid, values)``
  (the other input form :func:`mbsym.simulate` accepts; smooth signals such as the
  gust are sampled at ``dt``);
- gives a CasADi Function ``wind.to_casadi()`` of time (``"t" -> "U"``) so the wind
  can be evaluated inside a compiled simulation loop;
- lists its ``knots`` (times of kinks or jumps) so adaptive integrators can stop there.

Tables (from files or turbulence) are interpolated linearly and held constant
beyond their ends, as OpenFAST's InflowWind does for uniform wind files.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from numbers import Real

import casadi as ca
import numpy as np

from ...exceptions import WindInputError

__all__ = ["WindSignal", "SteadyWind", "StepWind", "RampWind", "ExtremeOperatingGust",
           "TabulatedWind", "iec_gust_speed"]

#: Rise time [s] used to tabulate an ideal step (tables must be strictly increasing).
STEP_TABLE_RISE = 1e-6


def _number(value, name: str, *, minimum: float | None = None, positive: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (Real, np.integer, np.floating)):
        raise WindInputError(f"{name} must be a number; got {value!r} of type {type(value).__name__}.")
    v = float(value)
    if not math.isfinite(v):
        raise WindInputError(f"{name} must be finite; got {v}.")
    if positive and v <= 0.0:
        raise WindInputError(f"{name} must be greater than 0; got {v:g}.")
    if minimum is not None and v < minimum:
        raise WindInputError(f"{name} must be at least {minimum:g}; got {v:g}.")
    return v


class WindSignal(ABC):
    """Hub-height longitudinal wind speed ``U(t)`` [m/s] of time ``t`` [s]."""

    @abstractmethod
    def sample(self, t) -> np.ndarray:
        """Wind speed [m/s] at the times ``t`` [s] (any shape; same shape back)."""

    @abstractmethod
    def _casadi(self, t: ca.SX) -> ca.SX:
        """The signal as an SX expression of the scalar time ``t``."""

    @property
    def knots(self) -> np.ndarray:
        """Times [s] where the signal has a kink or a jump (empty for smooth signals)."""
        return np.zeros(0)

    def __call__(self, t):
        """Wind speed [m/s] at ``t`` [s]: a float for a scalar time, an array otherwise."""
        out = self.sample(np.asarray(t, dtype=float))
        return float(out) if np.ndim(out) == 0 else out

    def table(self, t_end: float, *, dt: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
        """A linear-interpolation table ``(grid, values)`` covering ``[0, t_end]`` [s].

        Piecewise-linear signals are tabulated exactly at their knots (an ideal
        step rises over :data:`STEP_TABLE_RISE`); smooth parts are sampled every
        ``dt`` [s].  The pair is an input form :func:`mbsym.simulate` accepts.
        """
        t_end = _number(t_end, "t_end", positive=True)
        dt = _number(dt, "dt", positive=True)
        grid = np.unique(np.concatenate([[0.0, t_end], self._table_times(t_end, dt)]))
        grid = grid[(grid >= 0.0) & (grid <= t_end)]
        return grid, self._table_values(grid)

    def _table_times(self, t_end: float, dt: float) -> np.ndarray:
        return self.knots

    def _table_values(self, grid: np.ndarray) -> np.ndarray:
        return self.sample(grid)

    def to_casadi(self, name: str = "wind") -> ca.Function:
        """CasADi Function ``name(t) -> U`` [s → m/s] (SX; usable inside compiled loops)."""
        t = ca.SX.sym("t")
        return ca.Function(name, [t], [self._casadi(t)], ["t"], ["U"])

    def mean(self, t_end: float, *, dt: float = 0.05) -> float:
        """Time average [m/s] over ``[0, t_end]`` (trapezoidal rule on :meth:`table`)."""
        grid, values = self.table(t_end, dt=dt)
        return float(np.trapezoid(values, grid) / (grid[-1] - grid[0]))


class SteadyWind(WindSignal):
    """Constant wind speed ``speed`` [m/s]."""

    def __init__(self, speed: float) -> None:
        self.speed = _number(speed, "speed", minimum=0.0)

    def sample(self, t) -> np.ndarray:
        return np.full(np.shape(t), self.speed)

    def _casadi(self, t: ca.SX) -> ca.SX:
        return ca.SX(self.speed)

    def __repr__(self) -> str:
        return f"SteadyWind(speed={self.speed:g})"


class RampWind(WindSignal):
    """Linear change from ``start_speed`` to ``end_speed`` [m/s] over ``[start, end]`` [s]."""

    def __init__(self, start_speed: float, end_speed: float, start: float, end: float) -> None:
        self.start_speed = _number(start_speed, "start_speed", minimum=0.0)
        self.end_speed = _number(end_speed, "end_speed", minimum=0.0)
        self.start = _number(start, "start", minimum=0.0)
        self.end = _number(end, "end", minimum=0.0)
        if not self.end > self.start:
            raise WindInputError(f"a ramp must end after it starts; got start = {self.start:g} s, "
                                 f"end = {self.end:g} s. Use StepWind for an instantaneous change.")

    @property
    def knots(self) -> np.ndarray:
        return np.array([self.start, self.end])

    def sample(self, t) -> np.ndarray:
        fraction = np.clip((np.asarray(t, dtype=float) - self.start) / (self.end - self.start), 0.0, 1.0)
        return self.start_speed + (self.end_speed - self.start_speed) * fraction

    def _casadi(self, t: ca.SX) -> ca.SX:
        fraction = ca.fmin(ca.fmax((t - self.start) / (self.end - self.start), 0.0), 1.0)
        return self.start_speed + (self.end_speed - self.start_speed) * fraction

    def __repr__(self) -> str:
        return (f"RampWind({self.start_speed:g} -> {self.end_speed:g} m/s over "
                f"[{self.start:g}, {self.end:g}] s)")


class StepWind(WindSignal):
    """Step from ``before`` to ``after`` [m/s] at ``time`` [s] (``U = after`` for ``t >= time``).

    ``rise`` [s] > 0 makes it a ramp of that duration starting at ``time``.
    """

    def __init__(self, before: float, after: float, time: float, *, rise: float = 0.0) -> None:
        self.before = _number(before, "before", minimum=0.0)
        self.after = _number(after, "after", minimum=0.0)
        self.time = _number(time, "time", minimum=0.0)
        self.rise = _number(rise, "rise", minimum=0.0)

    @property
    def knots(self) -> np.ndarray:
        return np.array([self.time, self.time + max(self.rise, STEP_TABLE_RISE)])

    def sample(self, t) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if self.rise == 0.0:
            return np.where(t >= self.time, self.after, self.before)
        fraction = np.clip((t - self.time) / self.rise, 0.0, 1.0)
        return self.before + (self.after - self.before) * fraction

    def _table_values(self, grid: np.ndarray) -> np.ndarray:
        values = self.sample(grid)
        values[grid <= self.time] = self.before  # the tabulated step rises after `time`
        return values

    def _casadi(self, t: ca.SX) -> ca.SX:
        if self.rise == 0.0:
            return ca.if_else(t >= self.time, self.after, self.before)
        fraction = ca.fmin(ca.fmax((t - self.time) / self.rise, 0.0), 1.0)
        return self.before + (self.after - self.before) * fraction

    def __repr__(self) -> str:
        return f"StepWind({self.before:g} -> {self.after:g} m/s at {self.time:g} s, rise={self.rise:g} s)"


#: IEC 61400-1 ed. 3 (2005) Table 1: reference wind speed V_ref [m/s] per turbine class.
IEC_REFERENCE_SPEED = {"I": 50.0, "II": 42.5, "III": 37.5}
#: IEC 61400-1 ed. 3 Table 1: reference turbulence intensity I_ref per category (A+ from ed. 4).
IEC_REFERENCE_TURBULENCE = {"A+": 0.18, "A": 0.16, "B": 0.14, "C": 0.12}
#: Duration T [s] of the extreme operating gust (IEC 61400-1 ed. 3, 6.3.2.2).
EOG_DURATION = 10.5


def iec_gust_speed(hub_speed: float, *, rotor_diameter: float, hub_height: float,
                   turbine_class: str = "I", turbulence_category: str = "B") -> float:
    """Gust magnitude V_gust [m/s] of the IEC 61400-1 ed. 3 extreme operating gust (Eq. 17).

    ``V_gust = min(1.35 (V_e1 − V_hub), 3.3 σ1 / (1 + 0.1 D / Λ1))`` with the normal
    turbulence model ``σ1 = I_ref (0.75 V_hub + 5.6 m/s)``, the one-year extreme speed
    ``V_e1 = 0.8 · 1.4 V_ref`` and the longitudinal scale parameter ``Λ1 = 0.7 z_hub``
    (``z_hub < 60 m``) or 42 m.
    """
    hub_speed = _number(hub_speed, "hub_speed", minimum=0.0)
    diameter = _number(rotor_diameter, "rotor_diameter", positive=True)
    height = _number(hub_height, "hub_height", positive=True)
    if turbine_class not in IEC_REFERENCE_SPEED:
        raise WindInputError(f"turbine_class must be one of {sorted(IEC_REFERENCE_SPEED)}; got {turbine_class!r}.")
    if turbulence_category not in IEC_REFERENCE_TURBULENCE:
        raise WindInputError(f"turbulence_category must be one of {sorted(IEC_REFERENCE_TURBULENCE)}; "
                             f"got {turbulence_category!r}.")
    sigma1 = IEC_REFERENCE_TURBULENCE[turbulence_category] * (0.75 * hub_speed + 5.6)
    scale = 0.7 * height if height < 60.0 else 42.0
    v_e1 = 0.8 * 1.4 * IEC_REFERENCE_SPEED[turbine_class]
    return min(1.35 * (v_e1 - hub_speed), 3.3 * sigma1 / (1.0 + 0.1 * diameter / scale))


class ExtremeOperatingGust(WindSignal):
    """IEC 61400-1 ed. 3 extreme operating gust (EOG, Eq. 18) at hub height.

    ``U(t) = V_hub − 0.37 V_gust sin(3π τ) (1 − cos(2π τ))`` for ``τ = (t − start)/T``
    in ``[0, 1]``, ``U = V_hub`` otherwise, with ``T = 10.5 s``.  ``gust_speed``
    [m/s] is ``V_gust``; if omitted it is computed by :func:`iec_gust_speed` from the
    rotor diameter [m], hub height [m], turbine class and turbulence category.
    """

    def __init__(self, hub_speed: float, *, start: float = 0.0, gust_speed: float | None = None,
                 rotor_diameter: float | None = None, hub_height: float | None = None,
                 turbine_class: str = "I", turbulence_category: str = "B",
                 duration: float = EOG_DURATION) -> None:
        self.hub_speed = _number(hub_speed, "hub_speed", minimum=0.0)
        self.start = _number(start, "start", minimum=0.0)
        self.duration = _number(duration, "duration", positive=True)
        if gust_speed is None:
            if rotor_diameter is None or hub_height is None:
                raise WindInputError("give either gust_speed or both rotor_diameter and hub_height "
                                     "(to compute the IEC gust magnitude).")
            gust_speed = iec_gust_speed(self.hub_speed, rotor_diameter=rotor_diameter, hub_height=hub_height,
                                        turbine_class=turbine_class, turbulence_category=turbulence_category)
        self.gust_speed = _number(gust_speed, "gust_speed", minimum=0.0)

    @property
    def knots(self) -> np.ndarray:
        return np.array([self.start, self.start + self.duration])

    def sample(self, t) -> np.ndarray:
        tau = (np.asarray(t, dtype=float) - self.start) / self.duration
        inside = (tau >= 0.0) & (tau <= 1.0)
        shape = np.sin(3.0 * np.pi * tau) * (1.0 - np.cos(2.0 * np.pi * tau))
        return self.hub_speed - 0.37 * self.gust_speed * np.where(inside, shape, 0.0)

    def _table_times(self, t_end: float, dt: float) -> np.ndarray:
        n = max(int(math.ceil(self.duration / dt)), 8)
        return self.start + np.linspace(0.0, self.duration, n + 1)

    def _casadi(self, t: ca.SX) -> ca.SX:
        tau = (t - self.start) / self.duration
        shape = ca.sin(3.0 * ca.pi * tau) * (1.0 - ca.cos(2.0 * ca.pi * tau))
        return self.hub_speed - 0.37 * self.gust_speed * ca.if_else((tau >= 0) * (tau <= 1), shape, 0.0)

    def __repr__(self) -> str:
        return (f"ExtremeOperatingGust(hub_speed={self.hub_speed:g}, gust_speed={self.gust_speed:.4g}, "
                f"start={self.start:g})")


class TabulatedWind(WindSignal):
    """Wind speed table ``speed`` [m/s] at ``time`` [s]: linear in between, held beyond the ends.

    Attributes
    ----------
    time, speed : ndarray
        The table (read-only).
    source : str
        Where it came from (a file name, ``"kaimal(...)"``), for messages.
    """

    def __init__(self, time, speed, *, source: str = "table") -> None:
        t = np.array(time, dtype=float).reshape(-1)
        u = np.array(speed, dtype=float).reshape(-1)
        if t.size < 1 or t.shape != u.shape:
            raise WindInputError(f"{source}: time and speed must be 1-D arrays of the same length >= 1; "
                                 f"got {t.size} times and {u.size} speeds.")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(u))):
            raise WindInputError(f"{source}: times and speeds must be finite.")
        if np.any(np.diff(t) <= 0.0):
            j = int(np.flatnonzero(np.diff(t) <= 0.0)[0])
            raise WindInputError(f"{source}: times must strictly increase; {t[j + 1]:g} s follows {t[j]:g} s "
                                 f"(entries {j + 1} and {j + 2}).")
        t.setflags(write=False)
        u.setflags(write=False)
        self.time, self.speed, self.source = t, u, source

    @property
    def knots(self) -> np.ndarray:
        return self.time

    def sample(self, t) -> np.ndarray:
        return np.interp(np.asarray(t, dtype=float), self.time, self.speed)

    def _casadi(self, t: ca.SX) -> ca.SX:
        if self.time.size == 1:
            return ca.SX(float(self.speed[0]))
        lookup = ca.interpolant("wind_table", "linear", [self.time], self.speed)
        return lookup(ca.fmin(ca.fmax(t, self.time[0]), self.time[-1]))

    def __repr__(self) -> str:
        return (f"{type(self).__name__}({self.source}: {self.time.size} points over "
                f"[{self.time[0]:g}, {self.time[-1]:g}] s)")
