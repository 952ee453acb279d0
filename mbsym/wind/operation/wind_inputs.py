"""The wind a blade-element rotor sees, as inputs of the composed model.

A blade-element rotor needs the wind at every blade node's *current* position, so the wind enters
the graph as a function of position; what stays an input of the :class:`mbsym.Dynamics` depends on
the kind of wind:

* :class:`UniformWindInputs` — InflowWind's steady (``WindType = 1``) and uniform (``WindType = 2``)
  wind: the hub-height columns are inputs (:data:`UNIFORM_INPUTS`), and the wind at a point follows
  InflowWind's power-law and linear shears, direction and upflow
  (:func:`mbsym.wind.inflow.uniform_velocity_expr`): smooth, so linear models have the hub wind and
  the linear shears as inputs;
* :class:`FieldWindInputs` — a full field (TurbSim ``.bts``, ``WindType = 3``): the only input is the
  field's time ``WindTime`` [s] (a simulation feeds ``t``); the field is interpolated inside the graph
  by a compiled CasADi External (:meth:`mbsym.wind.inflow.FullFieldWind.casadi_function`), as
  InflowWind does (Taylor's frozen turbulence, bilinear in y–z, linear in time).
"""

from __future__ import annotations

from typing import Any, Mapping

import casadi as ca
import numpy as np

__all__ = ["UniformWindInputs", "FieldWindInputs", "UNIFORM_INPUTS", "FIELD_INPUTS"]

#: Uniform-wind inputs: name -> (column of ``uniform_velocity_expr``, unit).
UNIFORM_INPUTS = {
    "Wind1VelX": ("speed", "m/s"),            # InflowWind's HorSpd: horizontal hub-height speed (propagation direction)
    "WindDir": ("direction", "rad"),
    "WindVertVel": ("vertical_speed", "m/s"),
    "HLinShr": ("horizontal_shear", "-"),
    "VShrExp": ("power_law_exponent", "-"),
    "VLinShr": ("linear_vertical_shear", "-"),
    "Upflow": ("upflow", "rad"),
    "GustSpd": ("gust_speed", "m/s"),
}
#: Full-field inputs: the field's time.
FIELD_INPUTS = {"WindTime": "s"}


class UniformWindInputs:
    """InflowWind's uniform wind with its hub-height columns as model inputs.

    Parameters
    ----------
    ref_height : float
        InflowWind's ``RefHt`` / ``RefHt_Uni`` [m] (the hub-height of the columns).
    ref_length : float
        ``RefLength`` [m] of the linear shears (InflowWind's default for steady wind: the rotor diameter).
    defaults : dict, optional
        Default input values by name (e.g. the deck's power-law exponent).
    propagation_direction, upflow_angle : float, optional
        InflowWind's ``PropagationDir`` and ``VFlowAng`` [rad]: the rotation of the whole wind box.
    """

    kind = "uniform"

    def __init__(self, ref_height: float, ref_length: float, defaults: Mapping[str, float] | None = None, *,
                 propagation_direction: float = 0.0, upflow_angle: float = 0.0) -> None:
        self.ref_height, self.ref_length = float(ref_height), float(ref_length)
        self.propagation_direction, self.upflow_angle = float(propagation_direction), float(upflow_angle)
        self.field = None                  # the UniformFieldWind these inputs came from (from_field), if any
        self.defaults = {n: 0.0 for n in UNIFORM_INPUTS}
        self.defaults.update(dict(defaults or {}))
        unknown = sorted(set(self.defaults) - set(UNIFORM_INPUTS))
        if unknown:
            raise ValueError(f"unknown uniform-wind inputs {unknown}; expected {list(UNIFORM_INPUTS)}.")

    @property
    def inputs(self) -> tuple[str, ...]:
        return tuple(UNIFORM_INPUTS)

    def units(self) -> dict[str, str]:
        return {n: u for n, (_, u) in UNIFORM_INPUTS.items()}

    def velocity(self, points: Any, U: Mapping[str, Any]) -> Any:
        """Wind velocity [m/s] (3 x N, ground axes) at the points (3 x N) [m]."""
        from ..inflow import uniform_velocity_expr

        columns = {col: U[name] for name, (col, _) in UNIFORM_INPUTS.items()}
        return uniform_velocity_expr(columns, points, ref_height=self.ref_height, ref_length=self.ref_length,
                                     propagation_direction=self.propagation_direction, upflow_angle=self.upflow_angle)

    def path_rate(self, points: Any, velocities: Any, U: Mapping[str, Any]) -> Any:
        """Rate of the wind [m/s²] (3 x N) seen by points moving with ``velocities`` (3 x N) [m/s]: its change
        across their motion, exact (the columns are inputs: their own change in time is not in the graph, so a
        simulation's time-varying uniform wind contributes nothing here)."""
        points = ca.SX(points) if not isinstance(points, ca.SX) else points
        probe = ca.SX.sym("p", points.size1(), points.size2())
        w = self.velocity(probe, U)
        return ca.substitute(ca.jtimes(w, ca.vec(probe), ca.vec(velocities)), probe, points)

    @classmethod
    def from_field(cls, field) -> "UniformWindInputs":
        """The inputs of a :class:`~mbsym.wind.inflow.UniformFieldWind` (its columns at t = 0 as defaults)."""
        at0 = field.columns_at(0.0)
        defaults = {name: float(at0[col]) for name, (col, _) in UNIFORM_INPUTS.items()}
        out = cls(field.reference_height, field.reference_length, defaults,
                  propagation_direction=field.propagation_direction, upflow_angle=field.upflow_angle)
        out.field = field
        return out

    def signals(self, wind) -> dict[str, Any]:
        """Input signals of a simulation: ``wind`` is the hub speed (number, WindSignal or callable of t [s]),
        or a :class:`~mbsym.wind.inflow.UniformFieldWind` whose columns become the inputs (functions of time),
        or None: the field these inputs came from (:meth:`from_field`), else :attr:`defaults`; inputs not
        given keep :attr:`defaults`."""
        out: dict[str, Any] = dict(self.defaults)
        wind = self.field if wind is None else wind
        if wind is None:
            return out
        if hasattr(wind, "columns_at"):
            for name, (col, _) in UNIFORM_INPUTS.items():
                out[name] = lambda t, col=col: wind.columns_at(t)[col]
        else:
            out["Wind1VelX"] = wind
        return out

    def __repr__(self) -> str:
        return f"UniformWindInputs(ref_height={self.ref_height:g}, ref_length={self.ref_length:g})"


class FieldWindInputs:
    """A full wind field evaluated inside the graph; the input is the field's time ``WindTime`` [s].

    Parameters
    ----------
    field : FullFieldWind
        E.g. :func:`mbsym.wind.inflow.read_turbsim_bts`.
    """

    kind = "field"

    def __init__(self, field) -> None:
        self.field = field
        self.defaults = {"WindTime": 0.0}
        self._functions: dict[int, ca.Function] = {}

    @property
    def inputs(self) -> tuple[str, ...]:
        return tuple(FIELD_INPUTS)

    def units(self) -> dict[str, str]:
        return dict(FIELD_INPUTS)

    def velocity(self, points: Any, U: Mapping[str, Any]) -> Any:
        n = int(points.size2())
        if n not in self._functions:
            self._functions[n] = self.field.casadi_function(n)
        return self._functions[n](U["WindTime"], points)

    def path_rate(self, points: Any, velocities: Any, U: Mapping[str, Any]) -> Any:
        """Rate of the wind [m/s²] (3 x N) seen by points moving with ``velocities`` (3 x N) [m/s]: the change of
        the field along their (straight) path over one time step ``dt`` of the field, centred on now, per second.

        The field is known at its own time step only (linear in time and bilinear in space between samples), so
        its rate is taken at that resolution: a central difference over ``dt`` is continuous in time, where the
        exact derivative of the interpolation jumps at every sample and grid line. Within ``dt / 2`` of the
        field's first or last slice (a non-periodic field, at the point's Taylor-advected time) the difference
        becomes one-sided, so it never reaches beyond the data."""
        f = self.field
        h, n = float(f.dt), points.size2()
        from ..inflow.field import rotation_to_wind

        along = ca.DM(rotation_to_wind(f.propagation_direction, f.upflow_angle)[0]).T if f.rotated else \
            ca.DM([[1.0, 0.0, 0.0]])                                                 # wind direction (1 x 3)
        ahead, behind = 0.5 * h * ca.DM.ones(1, n), 0.5 * h * ca.DM.ones(1, n)
        if not f.periodic:
            ref = ca.repmat(ca.DM([0.0, 0.0, float(f.reference_height)]), 1, n)
            x = ca.mtimes(along, points - ref)                                         # wind-frame x [m]
            tau = U["WindTime"] + (float(f.initial_x) - x) / float(f.mean_speed)       # the point's slice time [s]
            speed = ca.fmax(1.0 - ca.mtimes(along, velocities) / float(f.mean_speed), 0.1)   # dτ/dt on the path
            margin = 1e-6                                                                # [s]: rounding at the ends
            ahead = ca.fmin(ahead, ca.fmax((float(f.total_time) - tau) / speed - margin, 0.0))
            behind = ca.fmin(behind, ca.fmax(tau / speed - margin, 0.0))
        # a time shift s of a point is a shift of -URef s along the wind (Taylor's frozen turbulence), so every
        # point keeps the one field time of the External call
        drift = velocities - float(f.mean_speed) * ca.repmat(along.T, 1, n)
        w_ahead = self.velocity(points + drift * ca.repmat(ahead, 3, 1), U)
        w_behind = self.velocity(points - drift * ca.repmat(behind, 3, 1), U)
        return (w_ahead - w_behind) / ca.repmat(ca.fmax(ahead + behind, 1e-9), 3, 1)

    def signals(self, wind=None) -> dict[str, Any]:
        """Input signals of a simulation: the field's time is the simulation time. ``wind`` must be None or this
        field (the field is part of the model)."""
        if wind is not None and wind is not self.field:
            from ...exceptions import WindInputError

            raise WindInputError("this model carries its full wind field (wind=... at construction); simulate it "
                                 "with wind=None, or build a model with the other field.")
        return {"WindTime": lambda t: t}

    def sample(self, t: Any, points: np.ndarray) -> np.ndarray:
        """Numeric velocities (N, 3) [m/s] at times ``t`` [s] and points (N, 3) [m]."""
        return self.field.velocity(t, points)

    def __repr__(self) -> str:
        return f"FieldWindInputs({self.field!r})"
