"""Set-points of a turbine NMPC: rated values, the region-2 optimum and the steady reference operation.

:class:`SetPoints` holds the rated generator speed and power, the minimum generator speed (from
the controller settings, :class:`~mbsym.wind.control.BaselineSettings`) and the tip-speed ratio
of the rotor's best power coefficient at fine pitch (from the rotor's own surfaces). Its speed
schedule is ``ω_ref(U) = clip(λ* U N / R, ω_min, ω_rated)``.

:func:`reference_table` solves, on a grid of steady winds, the **steady states** of the prediction
model that follow that schedule: the rotor at ``ω_ref(U)``, the tower and inflow at rest, the
pitch at fine pitch with the torque balancing the rotor (regions 2 and 2.5), or above rated the
torque at ``P_rated / (η ω_rated)`` with the pitch balancing (region 3). The NMPC's references
(generator speed, electrical power, tower-base fore-aft moment) are interpolated in that table at
each stage's wind, so speed, power and load references are consistent with each other and with the
model (no conflicting targets between regions).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ...exceptions import ModelDefinitionError

__all__ = ["SetPoints", "ReferenceTable", "reference_table", "reference_state", "REFERENCE_CHANNELS"]

#: Channels tabulated by :func:`reference_table` (OpenFAST units).
REFERENCE_CHANNELS = ("GenSpeed", "GenPwr", "TwrBsMyt", "BldPitch1", "GenTq", "TTDspFA", "RtVAvgxh")


@dataclass(frozen=True)
class SetPoints:
    """Rated values and the region-2 optimum of a turbine.

    Attributes
    ----------
    rated_generator_speed : float
        [rad/s] (ROSCO ``PC_RefSpd``).
    min_generator_speed : float
        [rad/s] (``VS_MinOMSpd``).
    rated_power : float
        Electrical [W] (``VS_RtPwr``).
    efficiency : float
        Generator efficiency [-].
    optimal_tsr, max_cp : float
        Tip-speed ratio of the best power coefficient at fine pitch and that coefficient (the
        rotor's own surfaces).
    radius : float
        Rotor radius [m].
    gearbox_ratio : float
    fine_pitch : float
        [rad].
    min_pitch_winds, min_pitch_values : tuple of float
        The controller's peak-shaving minimum pitch (ROSCO ``PS_WindSpeeds`` [m/s], ``PS_BldPitchMin`` [rad],
        with ``PS_Mode`` 1); empty without peak shaving. Used by :func:`reference_table` with
        ``peak_shaving=True``.
    """

    rated_generator_speed: float
    min_generator_speed: float
    rated_power: float
    efficiency: float
    optimal_tsr: float
    max_cp: float
    radius: float
    gearbox_ratio: float
    fine_pitch: float = 0.0
    min_pitch_winds: tuple = ()
    min_pitch_values: tuple = ()

    @classmethod
    def from_settings(cls, settings, rotor) -> "SetPoints":
        """From :class:`~mbsym.wind.control.BaselineSettings` and the rotor (:class:`RotorAero`)."""
        tsr = np.linspace(3.0, 12.0, 901)
        pitch = float(settings.fine_pitch)
        cp = rotor.steady(10.0, tsr * 10.0 / rotor.radius, pitch)["cp"]
        i = int(np.argmax(cp))
        shaving = bool(getattr(settings, "peak_shaving", False))
        winds = tuple(float(w) for w in settings.min_pitch_wind_speeds) if shaving else ()
        values = tuple(float(b) for b in settings.min_pitch_schedule) if shaving else ()
        return cls(float(settings.pitch_reference_speed), float(settings.min_generator_speed),
                   float(settings.rated_power), float(settings.generator_efficiency), float(tsr[i]), float(cp[i]),
                   float(rotor.radius), abs(float(settings.gearbox_ratio)), pitch, winds, values)

    def min_pitch(self, wind: float) -> float:
        """The lowest pitch of steady operation at the wind [m/s]: fine pitch, or the peak-shaving minimum
        (interpolated, ends held) where that is higher [rad]."""
        if not self.min_pitch_winds:
            return self.fine_pitch
        return max(self.fine_pitch, float(np.interp(wind, self.min_pitch_winds, self.min_pitch_values)))

    @property
    def rated_torque(self) -> float:
        """Generator torque at rated power and speed [N m]."""
        return self.rated_power / (self.efficiency * self.rated_generator_speed)

    def generator_speed(self, wind) -> np.ndarray:
        """Scheduled generator speed [rad/s] at the wind [m/s]."""
        w = self.optimal_tsr * np.asarray(wind, dtype=float) / self.radius * self.gearbox_ratio
        return np.clip(w, self.min_generator_speed, self.rated_generator_speed)


@dataclass(frozen=True)
class ReferenceTable:
    """Steady reference operation on a wind grid (see :func:`reference_table`).

    Attributes
    ----------
    winds : ndarray
        [m/s], increasing.
    channels : dict of str to ndarray
        :data:`REFERENCE_CHANNELS` at each wind (OpenFAST units).
    states : ndarray (n_winds, n_x)
        Steady states of the prediction model's control form.
    """

    winds: np.ndarray
    channels: dict = field(repr=False)
    states: np.ndarray = field(repr=False)

    def __call__(self, name: str, wind) -> np.ndarray:
        """Channel ``name`` interpolated at the wind [m/s] (held beyond the grid)."""
        return np.interp(wind, self.winds, self.channels[name])

    def state(self, wind: float) -> np.ndarray:
        """Steady state interpolated at the wind [m/s]."""
        return np.array([np.interp(wind, self.winds, col) for col in self.states.T])


def _balance(prediction, fixed: str, unknown: str):
    """``(rootfinder, free)``: Newton on the balance of the free states and the rotor with ``fixed`` given.

    Parameters of the rootfinder: ``[wind, generator speed, fixed value, the other states (guess), p]``.
    """
    key = ("reference_balance", fixed)
    cache = prediction.__dict__.setdefault("_cache", {})
    if key in cache:
        return cache[key]
    dyn = prediction.control
    states = dyn.states
    free = [s for s in ("Sg", "Sw", "Hv", "R", "P", "Y", "TFA1", "TFA2", "TSS1", "TSS2", "DrTr", "DBEMT_w", "DBEMT_v")
            if s in states]
    S = ca.SX if dyn.rhs.is_a("SXFunction") else ca.MX
    z = S.sym("z", len(free) + 1)
    par = S.sym("par", 3 + dyn.n_x + dyn.n_p)
    wind, omega, value, base, p = par[0], par[1], par[2], par[3:3 + dyn.n_x], par[3 + dyn.n_x:]
    x = [base[i] for i in range(dyn.n_x)]
    x[states.index("GeAz_d")] = omega
    x[states.index(fixed)] = value
    for i, s in enumerate(free):
        x[states.index(s)] = z[i]
    x[states.index(unknown)] = z[-1]
    for s in states:                                   # at rest: every structural speed but the rotor's
        if s.endswith("_d") and s != "GeAz_d":
            x[states.index(s)] = 0.0
    xv = ca.vertcat(*x)
    xd = dyn.rhs(xv, ca.vertcat(wind, 0.0, 0.0), p)
    rows = [s + "_d" if s + "_d" in states else s for s in free] + ["GeAz_d"]
    res = ca.vertcat(*[xd[states.index(r)] for r in rows])
    g = ca.Function("balance", [z, par], [res])
    root = ca.rootfinder("reference_state", "newton", g, {"abstol": 1e-10, "max_iter": 50, "error_on_fail": False})
    state = ca.Function("balance_state", [z, par], [xv])
    cache[key] = (root, g, state, free)
    return cache[key]


def reference_state(prediction, setpoints: SetPoints, wind: float, *, p=None, guess=None,
                    peak_shaving: bool = False) -> np.ndarray:
    """The steady state of the prediction model's control form on the speed schedule at a wind [m/s].

    Region 2 (and 2.5): fine pitch (with ``peak_shaving``: :meth:`SetPoints.min_pitch`, the controller's
    peak-shaving minimum where higher), the torque balancing the rotor; if that power exceeds the
    rated power, region 3: the rated torque, the pitch balancing. The platform, tower, drivetrain and inflow
    states are solved for rest (Newton's method with the exact Jacobian).

    Raises
    ------
    ModelDefinitionError
        If Newton's method finds no balance.
    """
    dyn = prediction.control
    pv = dyn.parameter_vector(p)
    states = dyn.states
    omega = float(setpoints.generator_speed(wind)) / setpoints.gearbox_ratio
    base = dyn.x0.copy() if guess is None else np.asarray(guess, dtype=float).copy()

    def solve(fixed: str, value: float, unknown: str, start: float) -> np.ndarray:
        root, g, state, free = _balance(prediction, fixed, unknown)
        par = np.concatenate([[wind, omega, value], base, pv])
        z0 = [base[states.index(s)] for s in free] + [start]
        sol = np.asarray(root(z0, par), dtype=float).ravel()
        residual = np.asarray(g(sol, par), dtype=float).ravel()
        if not np.all(np.isfinite(sol)) or np.max(np.abs(residual)) > 1e-6 * (1.0 + np.abs(sol).max()):
            raise ModelDefinitionError(f"no steady reference state of the prediction model at {wind:g} m/s "
                                       f"(rotor speed {omega:.4g} rad/s, {fixed} = {value:.4g}).")
        return np.asarray(state(sol, par), dtype=float).ravel()

    torque0 = base[states.index("GenTq")] if guess is not None else \
        setpoints.rated_torque * min(1.0, (wind / 11.4) ** 2)
    pitch = setpoints.min_pitch(wind) if peak_shaving else setpoints.fine_pitch
    x = solve("BlPitch", pitch, "GenTq", torque0)
    power = setpoints.efficiency * x[states.index("GenTq")] * omega * setpoints.gearbox_ratio
    if power > setpoints.rated_power:
        x = solve("GenTq", setpoints.rated_torque, "BlPitch", max(base[states.index("BlPitch")], 0.05))
    return x


def reference_table(prediction, setpoints: SetPoints, *, p=None, winds=None,
                    peak_shaving: bool = False) -> ReferenceTable:
    """Steady reference operation of the prediction model on a wind grid (default 3-30 m/s by 0.25 m/s); with
    ``peak_shaving`` the pitch held at or above the controller's peak-shaving minimum (:func:`reference_state`)."""
    winds = np.arange(3.0, 30.001, 0.25) if winds is None else np.asarray(winds, dtype=float)
    dyn = prediction.control
    rows, states, guess = [], [], None
    names = dyn.output_names
    for u in winds:
        x = reference_state(prediction, setpoints, float(u), p=p, guess=guess, peak_shaving=peak_shaving)
        guess = x
        y = dyn.output_value(x, [u, 0.0, 0.0], p)
        rows.append([y[names.index(c)] for c in REFERENCE_CHANNELS])
        states.append(x)
    table = np.array(rows)
    return ReferenceTable(winds, {c: table[:, i] for i, c in enumerate(REFERENCE_CHANNELS)}, np.array(states))
