"""The operating turbine driven by its *measured* pitch and generator torque: the model parameter identification fits.

:class:`MeasuredInputTurbine` rewrites an :class:`~.model.OperatingTurbine` (same CasADi graph,
nothing derived again) so that the measured collective pitch and generator torque of a record are
inputs: the actuator states are replaced by the measured values (``BlPitch = BlPitchMeas``,
``BlPitch_d = 0``, ``GenTq = GenTqMeas``), so the controller and the actuators are out of the loop and
no controller model can bias a structural estimate. The aerodynamics (rotor-effective surfaces and
dynamic inflow, or the blade-element rotor) and the wind (``Wind1VelX``, the measured hub wind) stay.
In ElastoDyn, without PitchDOF, the blade pitch is an angle ServoDyn sets (its rate moves no DOF), so
``BlPitch_d = 0`` is what OpenFAST does too.

The rotor azimuth ``GeAz`` is dropped when no right-hand side depends on it (rotor-effective
aerodynamics: loads averaged over the azimuth, an axisymmetric rotor; checked numerically at
construction): it is then neither a state nor estimated, and the azimuth channels (``Q_GeAz``,
``Azimuth``) are not outputs. Otherwise (blade-element rotor) it stays a state, started from the data,
never estimated (:attr:`MeasuredInputTurbine.fixed_states`), and its channels wrap
(:data:`PERIODS`).

:meth:`MeasuredInputTurbine.inputs_from` reads the inputs off a record (OpenFAST channel names and
units), :meth:`MeasuredInputTurbine.trim` gives the steady state at a record's first inputs (the
rotor speed, tower deflections and inflow states that balance them), which is where an
identification starts. A blade-element rotor is balanced at the record's azimuth: a root in the structure's
positions and the rotor speed only, its wake and airfoil states (hundreds to thousands) at equilibrium with
the inflow they give.
"""

from __future__ import annotations

from typing import Any, Mapping

import casadi as ca
import numpy as np

from ...dynamics import Dynamics
from ...exceptions import DataError, ModelDefinitionError, SolverError

__all__ = ["MeasuredInputTurbine", "MEASURED_INPUTS", "PERIODS", "match_channel", "channel_listing"]

#: Inputs replacing the commands: name -> (unit, data channels read in order of preference, to SI factors).
MEASURED_INPUTS = {"BlPitchMeas": "rad", "GenTqMeas": "N m"}
#: Wrapped channels: name -> period in the channel's unit.
PERIODS = {"Q_GeAz": 2 * np.pi, "Azimuth": 360.0}
_AZIMUTH_CHANNELS = ("Q_GeAz", "Azimuth")
#: Data channels of each input and their accepted units -> factor to SI.
_SOURCES = {
    "Wind1VelX": (("Wind1VelX",), {"m/s": 1.0}),
    "BlPitchMeas": (("BldPitch1", "BlPitch1", "BlPitch"), {"deg": np.pi / 180, "rad": 1.0}),
    "GenTqMeas": (("GenTq",), {"kN-m": 1e3, "kNm": 1e3, "kN m": 1e3, "N-m": 1.0, "Nm": 1.0, "N m": 1.0}),
}


class MeasuredInputTurbine:
    """An operating turbine whose pitch and generator torque are measured inputs (module docstring).

    Parameters
    ----------
    turbine : OperatingTurbine
        The turbine (its structure, aerodynamics, inflow and wind inputs are kept). Collective pitch.

    Attributes
    ----------
    turbine : OperatingTurbine
    fixed_states : tuple of str
        States an identification must not estimate (the azimuth, when it is kept).

    Raises
    ------
    TypeError
        ``turbine`` is not an OperatingTurbine.
    ModelDefinitionError
        Individual pitch (one measured pitch per blade is not supported yet).

    Examples
    --------
    >>> from mbsym.wind.operation import OperatingTurbine
    >>> from mbsym.wind.operation.measured import MeasuredInputTurbine
    >>> m = MeasuredInputTurbine(OperatingTurbine.nrel5mw(dynamic_inflow=False))
    >>> m.dynamics().inputs
    ('Wind1VelX', 'BlPitchMeas', 'GenTqMeas')
    >>> m.dynamics().states
    ('TFA1', 'TSS1', 'TFA1_d', 'TSS1_d', 'GeAz_d')
    """

    def __init__(self, turbine) -> None:
        from .model import OperatingTurbine

        if not isinstance(turbine, OperatingTurbine):
            raise TypeError(f"turbine must be an OperatingTurbine; got {type(turbine).__name__}.")
        if turbine.pitch != "collective":
            raise ModelDefinitionError("MeasuredInputTurbine supports collective pitch only; build the turbine with "
                                       "pitch='collective'.")
        self.turbine = turbine
        full = turbine.dynamics()
        self.full = full
        self.wind_inputs = tuple(n for n in full.inputs if n not in turbine.command_names)
        actuators = ("BlPitch", "BlPitch_d", "GenTq")
        keep_azimuth = "GeAz" in full.states and _depends_on_azimuth(full)
        self.states = tuple(s for s in full.states if s not in actuators and (s != "GeAz" or keep_azimuth))
        self.fixed_states = ("GeAz",) if keep_azimuth else ()
        self._dynamics = self._build(full, keep_azimuth)

    # ------------------------------------------------------------------ model
    def _build(self, full: Dynamics, keep_azimuth: bool) -> Dynamics:
        S = ca.SX if full.rhs.is_a("SXFunction") and full.outputs.is_a("SXFunction") else ca.MX
        inputs = (*self.wind_inputs, *MEASURED_INPUTS)
        z, u, p = S.sym("x", len(self.states)), S.sym("u", len(inputs)), S.sym("p", full.n_p)
        Z = {n: z[i] for i, n in enumerate(self.states)}
        U = {n: u[i] for i, n in enumerate(inputs)}
        Z.update(BlPitch=U["BlPitchMeas"], BlPitch_d=0.0, GenTq=U["GenTqMeas"])
        Z.setdefault("GeAz", 0.0)
        x = ca.vertcat(*[Z[s] for s in full.states])
        demand = ca.vertcat(*[U["BlPitchMeas"] if n == "BlPitchCom" else U["GenTqMeas"] if n == "GenTqCom" else U[n]
                              for n in full.inputs])          # actuators at rest at the measured values
        xd = full.rhs(x, demand, p)
        rhs = ca.vertcat(*[xd[full.states.index(s)] for s in self.states])
        y_all = full.outputs(x, demand, p)
        keep = [i for i, n in enumerate(full.output_names) if keep_azimuth or n not in _AZIMUTH_CHANNELS]
        y = ca.vertcat(*[y_all[i] for i in keep])
        opts = {"cse": True} if S is ca.SX else {}
        name = f"{full.name}_measured_inputs"
        f = ca.Function(f"{name}_rhs", [z, u, p], [rhs], ["x", "u", "p"], ["xd"], opts)
        h = ca.Function(f"{name}_outputs", [z, u, p], [y], ["x", "u", "p"], ["y"], opts)
        units = None if full.output_units is None else [full.output_units[i] for i in keep]
        x0 = [full.x0[full.states.index(s)] for s in self.states]
        u0 = [_default_input(full, n) for n in inputs]
        state_units = dict(zip(full.states, full.state_units))
        input_units = {**dict(zip(full.inputs, full.input_units)), **MEASURED_INPUTS}
        return Dynamics(f, states=self.states, inputs=inputs, parameters=full.parameters, defaults=dict(full.defaults),
                        outputs=h, output_names=[full.output_names[i] for i in keep], output_units=units, x0=x0,
                        u0=u0, name=name, state_units=[state_units.get(s, "") for s in self.states],
                        input_units=[input_units.get(n, "") for n in inputs])

    def dynamics(self) -> Dynamics:
        """The model as an :class:`mbsym.Dynamics` (states :attr:`states`; inputs the wind's, then
        ``BlPitchMeas`` [rad], ``GenTqMeas`` [N m] on the high-speed shaft)."""
        return self._dynamics

    def resolve_parameter(self, key: str):
        """An ElastoDyn key or descriptive name of the structure (:meth:`TurbineModel.resolve_parameter`)."""
        return self.turbine.structure.resolve_parameter(key)

    # ------------------------------------------------------------------ data
    def inputs_from(self, record: Any) -> np.ndarray:
        """Inputs (N, n_u) in SI units from a record's channels (OpenFAST names and units).

        ``record``: an object with ``time``, ``names``, ``data`` (N, n_channels) and optionally ``units``
        (:func:`mbsym.wind.analysis.compare.read_csv`), or a dict of arrays (then OpenFAST units
        are assumed: deg, kN-m). The hub wind, pitch and torque come from the record; a blade-element
        model's other uniform-wind inputs (direction, shears) from the deck's wind at the record's times. Raises :class:`~mbsym.exceptions.DataError` naming a missing channel
        or an unknown unit.
        """
        names, columns, units = _columns(record)
        deck_wind = self.turbine.wind.signals(None) if self.turbine.wind is not None else {}
        out = []
        for name in self._dynamics.inputs:
            channels, factors = _SOURCES.get(name, ((name,), {}))
            found = next((m for m in (match_channel(names, c) for c in channels) if m is not None), None)
            if found is None and name in deck_wind and name not in _SOURCES:
                out.append(_signal(deck_wind[name], _time(record)))       # the deck's wind (InflowWind columns)
                continue
            if found is None:
                raise DataError(f"input {name!r} needs one of the data channels {list(channels)}; the record has "
                                f"{channel_listing(names)}. Record the channel, or build the model with its wind as "
                                "inputs the record has.")
            unit = units.get(found)
            if factors and unit is not None and unit not in factors:
                raise DataError(f"channel {found!r} is in {unit!r}; expected one of {list(factors)}.")
            default = next(iter(factors.values()), 1.0)
            out.append(columns[found] * (factors.get(unit, default) if factors else 1.0))
        U = np.column_stack(out).astype(float)
        if not np.all(np.isfinite(U)):
            raise DataError("the measured inputs (wind, pitch, torque) must be finite at every sample.")
        return U

    def initial_state_from(self, record: Any, u0: np.ndarray) -> np.ndarray:
        """The trim at the record's first inputs ``u0``, with the record's first ``Q_<s>``/``QD_<s>`` values as
        the guess (and the azimuth, when kept, from ``Q_GeAz``): where :func:`mbsym.identify` starts."""
        names, columns, _ = _columns(record)
        guess = {}
        for s in self._dynamics.states:
            ch = match_channel(names, f"QD_{s[:-2]}" if s.endswith("_d") else f"Q_{s}")
            if ch is not None:
                guess[s] = float(columns[ch][0])
        return self.trim(u0, guess=guess)

    def trim(self, u: np.ndarray, *, guess: Mapping[str, float] | None = None,
             p: Mapping[str, float] | None = None) -> np.ndarray:
        """The steady state at inputs ``u`` (SI): ``rhs(x, u) = 0`` for every state but the azimuth (blade-element
        rotor: the structure's and the rotor speed's rates, the wake and airfoil states at their equilibrium).

        ``guess``: states by name (e.g. the measured ``GeAz_d``, tower deflections). The rotor speed
        is the one where the measured generator torque balances the aerodynamic torque. Raises
        :class:`~mbsym.exceptions.SolverError` (with advice) when no steady state is found.
        """
        from scipy.optimize import root

        dyn = self._dynamics
        u = dyn.input_vector(np.asarray(u, dtype=float))
        pv = dyn.parameter_vector(p)
        x = dyn.x0.copy()
        for k, v in dict(guess or {}).items():
            if k in dyn.states:
                x[dyn.states.index(k)] = float(v)
        if self.turbine.aero == "blade":
            return self._trim_blade(x, u, p)
        free = [i for i, s in enumerate(dyn.states) if s not in self.fixed_states]
        free_inflow = self._inflow_guess(x, u, p)
        for k, v in free_inflow.items():
            x[dyn.states.index(k)] = v
        scale = np.maximum(np.abs(x[free]), 1e-3)

        def residual(z):
            xx = x.copy()
            xx[free] = z * scale
            return np.asarray(dyn.rhs(xx, u, pv), dtype=float).reshape(-1)[free] / scale

        sol = root(residual, x[free] / scale, method="hybr", options={"xtol": 1e-12})
        x[free] = sol.x * scale
        bad = float(np.max(np.abs(residual(sol.x)))) if free else 0.0
        if not np.isfinite(bad) or bad > 1e-6:
            raise SolverError(f"no steady state at the record's first inputs {dict(zip(dyn.inputs, u.round(6)))} "
                              f"(largest scaled rate {bad:.2e}): start the record where the turbine is steady, or "
                              "give the initial state (x0=) and estimate it (estimate_x0).")
        return x

    def _trim_blade(self, x: np.ndarray, u: np.ndarray, p) -> np.ndarray:
        """Blade-element rotor: the structure's positions and the rotor speed that balance the inputs at the
        guess's azimuth, every wake and airfoil state at its equilibrium with that inflow.

        The unknowns are the structural coordinates' positions (but the azimuth) and the rotor speed, their
        velocities at rest; the wake and unsteady-airfoil states are not unknowns of the root but follow from
        the blade's inflow (:meth:`~.model.OperatingTurbine.initial_state`'s equilibrium) at every step, so the
        root has a few unknowns however many nodes the blades have.
        """
        from scipy.optimize import root

        dyn, t = self._dynamics, self.turbine
        coords = [c for c in t.structure.eom.coordinates if c != "GeAz" and c in dyn.states]
        spin = [dyn.states.index("GeAz_d")] if "GeAz_d" in dyn.states else []    # GenDOF off: a set speed
        unknown = [dyn.states.index(c) for c in coords] + spin
        balance = [dyn.states.index(f"{c}_d") for c in coords] + spin
        wind = {n: float(u[dyn.inputs.index(n)]) for n in self.wind_inputs}
        full = self.full
        x = x.copy()
        x[[dyn.states.index(f"{c}_d") for c in coords]] = 0.0
        scale = np.maximum(np.abs(x[unknown]), 1e-2)

        def state(z: np.ndarray) -> np.ndarray:
            xx = x.copy()
            xx[unknown] = z * scale
            values = dict(zip(dyn.states, xx))
            values.update(BlPitch=float(u[dyn.inputs.index("BlPitchMeas")]), BlPitch_d=0.0,
                          GenTq=float(u[dyn.inputs.index("GenTqMeas")]))
            values.update(t.wake_equilibrium({s: values.get(s, 0.0) for s in full.states}, wind, p))
            return np.array([values[s] for s in dyn.states])

        def residual(z: np.ndarray) -> np.ndarray:
            xx = state(z)
            return np.asarray(dyn.rhs(xx, u, dyn.parameter_vector(p)), dtype=float).reshape(-1)[balance] / scale

        z0 = x[unknown] / scale
        if not unknown:                                  # nothing moves: the wake at equilibrium is the trim
            return state(z0)
        sol = root(residual, z0, method="hybr", options={"xtol": 1e-12})
        bad = float(np.max(np.abs(residual(sol.x))))
        if not np.isfinite(bad) or bad > 1e-6:
            raise SolverError(f"no balance of the blade-element rotor at the record's first inputs "
                              f"{dict(zip(dyn.inputs, u.round(6)))} (largest scaled acceleration {bad:.2e}): start "
                              "the record where the turbine is steady, or give the initial state (x0=) and estimate "
                              "it (estimate_x0).")
        return state(sol.x)

    def _inflow_guess(self, x: np.ndarray, u: np.ndarray, p) -> dict[str, float]:
        """Inflow states at equilibrium with the state guess (rotor-effective model with inflow states)."""
        t = self.turbine
        dyn = self._dynamics
        if t.aero == "blade" or (t.dynamic_inflow is None and not t.inflow_lag):
            return {}
        values = dict(zip(dyn.states, x))
        full = self.full
        xf = np.array([values.get(s, 0.0) for s in full.states])
        xf[full.states.index("BlPitch")] = u[dyn.inputs.index("BlPitchMeas")]
        xf[full.states.index("GenTq")] = u[dyn.inputs.index("GenTqMeas")]
        wind = u[dyn.inputs.index("Wind1VelX")]
        full_x = t.initial_state(wind, rotor_speed=values.get("GeAz_d"),
                                 pitch=float(xf[full.states.index("BlPitch")]), p=p)
        names = ("DBEMT_w", "DBEMT_v") if t.dynamic_inflow is not None else ("RotThrustLag", "RotTorqLag")
        return {n: float(full_x[full.states.index(n)]) for n in names if n in dyn.states}

    def __repr__(self) -> str:
        return f"MeasuredInputTurbine({self.turbine!r}, states={list(self.states)})"


def _default_input(full: Dynamics, name: str) -> float:
    if name == "BlPitchMeas":
        return float(full.u0[full.inputs.index("BlPitchCom")])
    if name == "GenTqMeas":
        return float(full.u0[full.inputs.index("GenTqCom")])
    return float(full.u0[full.inputs.index(name)])


def _depends_on_azimuth(full: Dynamics) -> bool:
    """Whether the right-hand side changes with the azimuth ``GeAz`` (two random azimuths, spinning rotor)."""
    rng = np.random.default_rng(0)
    x = full.x0.copy()
    x[full.states.index("GeAz_d")] = 1.2
    u = full.u0.copy()
    if "Wind1VelX" in full.inputs:
        u[full.inputs.index("Wind1VelX")] = 12.0
    a, b = x.copy(), x.copy()
    a[full.states.index("GeAz")], b[full.states.index("GeAz")] = 0.3, float(rng.uniform(1.0, 5.5))
    fa, fb = full.rhs_value(a, u), full.rhs_value(b, u)
    keep = [i for i, s in enumerate(full.states) if s != "GeAz"]
    return not np.allclose(fa[keep], fb[keep], rtol=1e-9, atol=1e-9)


def match_channel(names, wanted: str) -> str | None:
    """The record's name of channel ``wanted``: exact, else ignoring case (OpenFAST's channel names are
    case-insensitive and its output repeats the OutList's spelling, e.g. ``Wind1Velx``); None if absent."""
    if wanted in names:
        return wanted
    folded = wanted.casefold()
    return next((n for n in sorted(names) if n.casefold() == folded), None)


def channel_listing(names, limit: int = 12) -> str:
    """A short listing of a record's channels for an error message."""
    names = sorted(names)
    if len(names) <= limit:
        return str(names)
    return f"{len(names)} channels ({', '.join(names[:limit])}, ...)"


def _time(record: Any) -> np.ndarray:
    t = record.get("time") if isinstance(record, Mapping) else getattr(record, "time", None)
    if t is None:
        raise DataError("the record has no time; the deck's wind inputs are read at the record's times.")
    return np.asarray(t, dtype=float).reshape(-1)


def _signal(value: Any, t: np.ndarray) -> np.ndarray:
    """A wind input (number or function of time) at the times ``t``."""
    if callable(value):
        return np.array([float(value(float(s))) for s in t])
    return np.full(t.size, float(value))


def _columns(record: Any) -> tuple[set, dict, dict]:
    """(names, name -> column, name -> unit or None) of a record."""
    if isinstance(record, Mapping):
        cols = {str(k): np.asarray(v, dtype=float).reshape(-1) for k, v in record.items()}
        return set(cols), cols, {}
    names = tuple(getattr(record, "names", ()))
    data = getattr(record, "data", None)
    data = np.asarray(getattr(record, "values", np.zeros((0, 0))) if data is None else data, dtype=float)
    if not names or data.ndim != 2 or data.shape[1] != len(names):
        raise DataError(f"a record must be a dict of arrays or have names and data (N, n_channels); got "
                        f"{type(record).__name__}.")
    units = {n: (u or None) for n, u in zip(names, getattr(record, "units", None) or [None] * len(names))}
    return set(names), {n: data[:, i] for i, n in enumerate(names)}, units
