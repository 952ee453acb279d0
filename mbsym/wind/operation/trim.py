"""Trim: steady operating points of an operating turbine, by root finding on the composed model's graph.

For a wind speed ``U``, :func:`trim` finds the state ``x``, the commands ``(β_c, T_c)`` and the
controller's wind estimate ``Û`` such that

* the composed model's right-hand side (:meth:`OperatingTurbine.dynamics`, the same CasADi
  graph simulations integrate) vanishes for every state except the rotor azimuth, which
  turns at the (unknown) rotor speed: tower and drivetrain at their mean deflection, rotor
  without acceleration, actuators at rest, dynamic inflow at equilibrium;
* the controller's two loops satisfy the conditions of one steady regime and its estimator
  has settled (:mod:`.steady_control`: region 2 TSR tracking or k·ω², 2.5, 3 with constant
  power or torque, minimum pitch with the peak-shaving schedule on the *estimated* wind, the
  set-point smoother, the estimator's bias from its own Cp table).

**Rotor azimuth.** The loads of a rotor described by performance surfaces do not depend on
azimuth, and a rigid three-bladed rotor's gravity and inertia loads on the tower do not
either (its inertia is axisymmetric): then the steady state is an equilibrium and the
residual is evaluated at one azimuth. With flexible blades the structure sees the blade
weight turn with the rotor and the operating state is periodic; the residual is then the
mean of the right-hand side over ``n_azimuth`` equally spaced azimuths (as
:func:`mbsym.linear.steady_rotation`): the mean deflection. The default chooses by
evaluating the model at two azimuths.

**Coordinates without stiffness** (a yaw bearing without spring, an unmoored platform) have no
equilibrium value: they are held at the deck's value and their acceleration must vanish there;
if it does not (a free yaw carries the rotor's reaction torque) the point fails with a message
saying so, never silently.

**Solution.** Each regime of the controller gives a square system; Newton's method with the
exact Jacobian (CasADi AD of the same graph) and a backtracking line search solves it from
a guess on the rotor surfaces (:mod:`.trim_guess`) or, over a sweep of wind speeds, from the
neighbouring solution (continuation). A regime is accepted when the solution also satisfies
its inequalities (the saturated loop pushes into its limit, the active one is within its
limits); otherwise the next regime is tried. Every point carries ``success`` and a
``message`` naming its regime or why none fitted; nothing fails silently.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from ...exceptions import ModelDefinitionError, ParameterError, UnsupportedFeatureError
from .steady_control import Regime, SteadyControl
from .trim_guess import predicted_order, rotor_guess

__all__ = ["TrimPoint", "Trimmer", "trim", "TRIM_TOLERANCE"]

#: Default Newton tolerance: the largest residual row, scaled to the change of the unknowns that
#: would remove it, relative to their size.
TRIM_TOLERANCE = 1e-10
#: A coordinate whose stiffness (per unit mass) is below (2π f)² with this f [Hz] is held (no equilibrium value).
NEUTRAL_FREQUENCY = 0.005
#: Largest acceleration [m/s² or rad/s²] a coordinate held for lack of stiffness may keep at a trim.
HELD_TOLERANCE = 1e-6
_RPM = 30.0 / math.pi
_TORQUE_KINDS = ("track", "upper", "lower", "k2", "hold_min", "hold_rated", "arsat")
_PITCH_KINDS = ("min", "track", "max")


@dataclass(frozen=True)
class TrimPoint:
    """One steady operating point.

    Attributes
    ----------
    wind_speed : float
        Hub-height wind [m/s].
    success : bool
    message : str
        The regime and its meaning, or why no regime fitted.
    regime : str
        The loops' steady regime: ``"2"``, ``"3"``, ``"2.5-saturated"``, ... (:meth:`SteadyControl.regimes`),
        ``""`` on failure.
    region : str
        The usual region name (:meth:`SteadyControl.region`): ``"1.5"``, ``"2"``, ``"2.5"``, ``"3"``.
    peak_shaving : bool
        Whether the pitch is held at a minimum above fine pitch (the peak-shaving schedule acts).
    state : ndarray
        The model's state vector (rotor azimuth at the reference azimuth).
    inputs : ndarray
        ``Wind1VelX``, ``BlPitchCom`` [rad], ``GenTqCom`` [N m], then any other input.
    parameters : dict
        Model parameters by name (with ``rotor_speed`` when GenDOF is off).
    wind_estimate : float
        The controller's settled wind estimate ``Û`` [m/s].
    min_pitch : float
        The controller's minimum pitch at ``Û`` [rad].
    channels : mapping
        Every output channel of the model, OpenFAST names and units (:attr:`units`).
    rhs : ndarray
        The model's right-hand side at the point (mean over the azimuth samples); the rotor
        azimuth's row is the rotor speed, every other row is the trim residual.
    iterations : int
        Newton iterations of the accepted regime.
    seconds : float
        Wall time of this point [s].
    """

    wind_speed: float
    success: bool
    message: str
    regime: str
    state: np.ndarray
    inputs: np.ndarray
    parameters: Mapping[str, float]
    wind_estimate: float
    min_pitch: float
    channels: Mapping[str, float]
    units: Mapping[str, str]
    rhs: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    azimuth_state: str
    region: str = ""
    peak_shaving: bool = False
    iterations: int = 0
    seconds: float = 0.0
    attempts: tuple[str, ...] = field(default=(), repr=False)

    def __getitem__(self, channel: str) -> float:
        """A channel by OpenFAST name (``point["RotSpeed"]`` in rpm)."""
        try:
            return self.channels[channel]
        except KeyError:
            raise KeyError(f"no channel {channel!r}; channels are {sorted(self.channels)}.") from None

    @property
    def residual(self) -> dict[str, float]:
        """The trim residual: the right-hand side of every state except the rotor azimuth, by name."""
        return {n: float(v) for n, v in zip(self.state_names, self.rhs) if n != self.azimuth_state}

    def x(self) -> dict[str, float]:
        """The state by name."""
        return dict(zip(self.state_names, self.state.tolist()))

    def u(self) -> dict[str, float]:
        """The inputs by name."""
        return dict(zip(self.input_names, self.inputs.tolist()))

    def __repr__(self) -> str:
        if not self.success:
            return f"TrimPoint(U={self.wind_speed:g} m/s, failed: {self.message})"
        c = self.channels
        return (f"TrimPoint(U={self.wind_speed:g} m/s, region {self.region}: RotSpeed {c['RotSpeed']:.4f} rpm, "
                f"BldPitch1 {c['BldPitch1']:.3f} deg, GenPwr {c['GenPwr']:.1f} kW, RtAeroFxh {c['RtAeroFxh']:.0f} N, "
                f"TTDspFA {c['TTDspFA']:.4f} m)")


class Trimmer:
    """The trim problem of one model and controller, built once (see the module docstring).

    Parameters
    ----------
    model : OperatingTurbine
    control : SteadyControl, optional
        Default :meth:`SteadyControl.nrel5mw`.
    p : dict, optional, keyword-only
        Model parameters by name (defaults fill the gaps).
    n_azimuth : int, optional, keyword-only
        Azimuth samples of the residual; default 1 if the model's right-hand side does not
        depend on the azimuth (checked), else 12.
    tol : float, optional, keyword-only
        Newton tolerance (:data:`TRIM_TOLERANCE`).
    max_iter : int, optional, keyword-only
        Newton iterations per regime.
    """

    def __init__(self, model, control: SteadyControl | None = None, *, p: Mapping[str, float] | None = None,
                 n_azimuth: int | None = None, tol: float = TRIM_TOLERANCE, max_iter: int = 40) -> None:
        from .model import OperatingTurbine

        if not isinstance(model, OperatingTurbine):
            raise TypeError(f"model must be an OperatingTurbine; got {type(model).__name__}.")
        if getattr(model, "aero", "rotor") == "blade":
            raise UnsupportedFeatureError(
                "trimming the blade-element rung (aero='blade') is not supported: its guesses and regimes read the "
                "rotor-effective surfaces. Trim the same deck with aero='rotor' (OperatingTurbine.from_openfast(fst, "
                "aero='rotor'); `mbsym operating-points` and `mbsym linearize --wind` do), or start a blade-element "
                "simulation from that trim.")
        control = SteadyControl.nrel5mw() if control is None else control
        if not isinstance(control, SteadyControl):
            raise TypeError(f"control must be a SteadyControl (SteadyControl.from_discon(...), .nrel5mw()); got "
                            f"{type(control).__name__}.")
        if not (isinstance(tol, float) and 0 < tol < 1e-2):
            raise ParameterError(f"tol must be a float in (0, 1e-2); got {tol!r}.")
        if isinstance(max_iter, bool) or not isinstance(max_iter, int) or max_iter < 1:
            raise ParameterError(f"max_iter must be an int >= 1; got {max_iter!r}.")
        self.model, self.control, self.tol, self.max_iter = model, control, tol, max_iter
        self.dyn = dyn = model.dynamics()
        self.p = dyn.parameter_vector(p)
        self.par = dict(zip(dyn.parameters, self.p.tolist()))
        _check_gearbox(model, control)
        self._layout()
        if n_azimuth is None:
            n_azimuth = 1 if self._azimuth_independent() else 12
        if isinstance(n_azimuth, bool) or not isinstance(n_azimuth, int) or n_azimuth < 1:
            raise ParameterError(f"n_azimuth must be an int >= 1; got {n_azimuth!r}.")
        self.n_azimuth = n_azimuth
        self._build()

    # ------------------------------------------------------------------ layout of the unknowns
    def _layout(self) -> None:
        dyn, model = self.dyn, self.model
        for name in ("Wind1VelX", "BlPitchCom", "GenTqCom"):
            if name not in dyn.inputs:
                raise ModelDefinitionError(f"the model has no input {name!r}; inputs are {list(dyn.inputs)}.")
        for name in ("GenSpeed", "RotSpeed", "GenPwr", "RtAeroMxh", "GenTq"):
            if name not in dyn.output_names:
                raise ModelDefinitionError(f"the model has no output channel {name!r}.")
        self.i_az = dyn.states.index("GeAz")
        self.i_speed = dyn.states.index("GeAz_d") if model.spins_freely else None
        n_q = model.structure.eom.n_q
        self.held = self._neutral_coordinates()
        self.x_base = dyn.x0                        # held coordinates keep these values (the deck's)
        self.free = [i for i in range(dyn.n_x) if i != self.i_az and i not in self.held]
        self.eq_rows = [i for i in range(dyn.n_x) if i != self.i_az and i - n_q not in self.held]
        self.i_u = {n: dyn.inputs.index(n) for n in ("Wind1VelX", "BlPitchCom", "GenTqCom")}
        self.estimates = self.control.wind_estimator in (1, 2)
        self.n_z = len(self.free) + 2 + (0 if model.spins_freely else 1) + (1 if self.estimates else 0)
        self.out = {n: dyn.output_names.index(n) for n in ("GenSpeed", "RotSpeed", "GenPwr", "RtAeroMxh", "GenTq")}

    @property
    def _sym(self):
        """``ca.SX``, or ``ca.MX`` for a model whose rhs holds MX-only nodes (a linear solve of many DOFs)."""
        return ca.SX if self.dyn.rhs.is_a("SXFunction") else ca.MX

    def _split(self, z, az, U):
        """``(x, u, p, Û)`` expressions from the unknowns ``z`` (SX), azimuth and wind."""
        dyn, n_f = self.dyn, len(self.free)
        sym = self._sym
        x = sym(ca.DM(self.x_base))
        for k, i in enumerate(self.free):
            x[i] = z[k]
        x[self.i_az] = az
        u = sym(ca.DM(dyn.u0))
        u[self.i_u["Wind1VelX"]] = U
        u[self.i_u["BlPitchCom"]] = z[n_f]
        u[self.i_u["GenTqCom"]] = z[n_f + 1]
        k = n_f + 2
        p = sym(ca.DM(self.p))
        if not self.model.spins_freely:
            p[self.dyn.parameters.index("rotor_speed")] = z[k]
            k += 1
        u_est = z[k] if self.estimates else U
        return x, u, p, u_est

    # ------------------------------------------------------------------ the residual Function
    def _build(self) -> None:
        dyn, c, n_f = self.dyn, self.control, len(self.free)
        sym = self._sym
        z = sym.sym("z", self.n_z)
        U, az0 = sym.sym("U"), sym.sym("az0")
        sel = sym.sym("sel", len(_TORQUE_KINDS) + len(_PITCH_KINDS) + 1)
        x, u, p, u_est = self._split(z, az0, U)
        n_az = self.n_azimuth
        xs = ca.repmat(x, 1, n_az)
        for k in range(n_az):
            xs[self.i_az, k] = az0 + 2 * math.pi * k / n_az
        rhs = ca.sum2(dyn.rhs.map(n_az)(xs, ca.repmat(u, 1, n_az), ca.repmat(p, 1, n_az))) / n_az
        y = dyn.outputs(x, u, p)
        gen_speed = y[self.out["GenSpeed"]] / _RPM
        rot_speed = y[self.out["RotSpeed"]] / _RPM
        power = y[self.out["GenPwr"]] * 1e3
        beta_c, torque_c = z[n_f], z[n_f + 1]
        beta_min = c.min_pitch(u_est)
        shift = c.shift(beta_c, beta_min, power)
        t_ref, p_ref = c.torque_reference(u_est, power, shift), c.pitch_reference(shift)
        rows = [rhs[self.eq_rows]]
        t_eq = [c.torque_equation(Regime("", k, "min", ""), speed=gen_speed, torque=torque_c, reference=t_ref)
                for k in _TORQUE_KINDS]
        p_eq = [c.pitch_equation(Regime("", "track", k, ""), speed=gen_speed, pitch=beta_c, min_pitch=beta_min,
                                 reference=p_ref) for k in _PITCH_KINDS]
        nt = len(_TORQUE_KINDS)
        rows.append(sum(sel[i] * e for i, e in enumerate(t_eq)))
        rows.append(sum(sel[nt + i] * e for i, e in enumerate(p_eq)))
        if not self.model.spins_freely:      # the rotor's torque balance (no rotor DOF carries it)
            balance = y[self.out["RtAeroMxh"]] - self.model.gearbox_ratio * y[self.out["GenTq"]] * 1e3
            rows.append(balance / max(c.torque_max, c.rated_torque, 1.0) / self.model.gearbox_ratio)
        if self.estimates:
            on = sel[-1]
            t_scale = c.rated_generator_speed / max(c.torque_max, c.rated_torque, 1.0)
            est = (c.estimator_torque(u_est, rot_speed, beta_c) / c.gearbox_ratio - torque_c) * t_scale
            rows.append(on * est + (1 - on) * (u_est - U))
        r = ca.vertcat(*rows)
        # no cse option: it removes 6 % of the instructions for 1.4 s of construction (NREL 5 MW)
        self.residual = ca.Function("trim_residual", [z, U, az0, sel], [r, ca.jacobian(r, z)],
                                    ["z", "U", "az0", "sel"], ["r", "J"])
        self.signals = ca.Function("trim_signals", [z, U, az0],
                                   [ca.vertcat(gen_speed, rot_speed, power, beta_min, t_ref, p_ref, u_est)])
        ys = dyn.outputs.map(n_az)(xs, ca.repmat(u, 1, n_az), ca.repmat(p, 1, n_az))
        self.point_values = ca.Function("trim_point", [z, U, az0], [x, u, p, rhs, ca.sum2(ys) / n_az])

    def _neutral_coordinates(self) -> list[int]:
        """Coordinates (not the rotor azimuth) without stiffness, held at the deck's value as
        :func:`mbsym.linear.static_equilibrium` does (a free yaw, an unmoored platform surge).

        In still air at the deck's state with the rotor turning, their row and column of
        ∂(accelerations)/∂(coordinates) (the rotor azimuth's left out) stay below
        ``(2π NEUTRAL_FREQUENCY)²``: no restoring force that would give a mode faster than one
        cycle per 200 s (a yaw bearing without spring sees 4e-4 1/s² from gravity; the slowest
        moored floating platforms' surge is ~0.008 Hz, 2.5e-3 1/s²).
        """
        dyn, eom = self.dyn, self.model.structure.eom
        n_q = eom.n_q
        x0 = dyn.x0
        if self.i_speed is not None:
            x0[self.i_speed] = 1.0
        p = dict(zip(dyn.parameters, self.p.tolist()))
        if "air_density" in p:
            p["air_density"] = 1e-12
        q = self._sym.sym("q", n_q)
        acc = dyn.rhs(ca.vertcat(q, x0[n_q:]), dyn.u0, dyn.parameter_vector(p))[n_q:2 * n_q]
        K = np.abs(np.asarray(ca.Function("stiffness", [q], [ca.jacobian(acc, q)])(x0[:n_q]), dtype=float))
        small = K <= (2 * math.pi * NEUTRAL_FREQUENCY) ** 2
        rest = [j for j, c in enumerate(eom.coordinates) if c != "GeAz"]
        return [i for i in rest if small[i, rest].all() and small[rest, i].all()]

    def _azimuth_independent(self) -> bool:
        """Whether the rhs at a spinning state differs between two azimuths by less than 1e-9 (relative)."""
        dyn = self.dyn
        x = dyn.x0.copy()
        if self.i_speed is not None:
            x[self.i_speed] = 1.0
        u = dyn.input_vector({"Wind1VelX": 10.0})
        values = []
        for az in (0.3, 1.7):
            x[self.i_az] = az
            values.append(np.array(dyn.rhs(x, u, self.p), dtype=float).reshape(-1))
        a, b = values
        keep = [i for i in range(dyn.n_x) if i != self.i_az]
        scale = np.maximum(np.abs(a[keep]), 1.0)
        return bool(np.all(np.abs(a[keep] - b[keep]) <= 1e-9 * scale))

    # ------------------------------------------------------------------ solving
    def _selector(self, regime: Regime, estimator_on: bool) -> np.ndarray:
        s = np.zeros(len(_TORQUE_KINDS) + len(_PITCH_KINDS) + 1)
        s[_TORQUE_KINDS.index(regime.torque)] = 1.0
        s[len(_TORQUE_KINDS) + _PITCH_KINDS.index(regime.pitch)] = 1.0
        s[-1] = 1.0 if estimator_on else 0.0
        return s

    def guess(self, regime: Regime, wind_speed: float) -> np.ndarray:
        """Unknowns from the rotor surfaces (:func:`~.trim_guess.rotor_guess`), tower at rest."""
        g = rotor_guess(self.model, self.control, regime, wind_speed, self.par)
        model, dyn = self.model, self.dyn
        if model.spins_freely:
            x = model.initial_state(wind_speed, rotor_speed=g.rotor_speed, pitch=g.pitch, torque=g.torque)
        else:                                # the rotor speed is a parameter, an unknown of the trim
            x = model.initial_state(None, pitch=g.pitch, torque=g.torque)
        for name in dyn.states[model.structure.eom.n_q:2 * model.structure.eom.n_q]:
            if name != "GeAz_d":
                x[dyn.states.index(name)] = 0.0
        for i, name in enumerate(model.structure.eom.coordinates):
            if name != "GeAz" and i not in self.held:
                x[i] = 0.0
        extra = [g.pitch, g.torque] + ([] if model.spins_freely else [g.rotor_speed])
        extra += [wind_speed] if self.estimates else []
        return np.concatenate([x[self.free], extra])

    def _scales(self, z0: np.ndarray) -> np.ndarray:
        c = self.control
        floor = np.full(self.n_z, 1e-2)
        n_f = len(self.free)
        floor[n_f + 1] = 1e-2 * max(c.torque_max, c.rated_torque, 1.0)
        floor[self.free.index(self.dyn.states.index("GenTq"))] = floor[n_f + 1]
        return np.maximum(np.abs(z0), floor)

    def newton(self, z0: np.ndarray, wind_speed: float, regime: Regime, *, estimator_on: bool = True,
               az0: float = 0.0) -> tuple[np.ndarray, int, bool, float]:
        """Damped Newton on one regime: ``(z, iterations, converged, scaled residual)``."""
        sel = self._selector(regime, estimator_on and self.estimates)
        f = lambda z: [np.asarray(v, dtype=float) for v in self.residual(z, wind_speed, az0, sel)]  # noqa: E731
        z = np.asarray(z0, dtype=float).copy()
        r, J = f(z)
        r = r.reshape(-1)
        zs = self._scales(z)
        row = np.max(np.abs(J) * zs[None, :], axis=1)
        row = 1.0 / np.where(row > 0, row, 1.0)
        err = float(np.max(np.abs(r * row))) if np.all(np.isfinite(r)) else np.inf
        for it in range(self.max_iter):
            if err <= self.tol:
                return z, it, True, err
            try:
                dz = np.linalg.solve(J, -r)
            except np.linalg.LinAlgError:
                dz = np.linalg.lstsq(J, -r, rcond=None)[0]
            if not np.all(np.isfinite(dz)):
                return z, it, False, err
            alpha = 1.0
            while True:
                zn = z + alpha * dz
                rn, Jn = f(zn)
                rn = rn.reshape(-1)
                en = float(np.max(np.abs(rn * row))) if np.all(np.isfinite(rn)) else np.inf
                if en < (1.0 - 1e-4 * alpha) * err or alpha < 1e-3:
                    break
                alpha *= 0.5
            if not np.isfinite(en) or en >= err:          # no descent along Newton's direction: give up
                return z, it, False, err
            z, r, J, err = zn, rn, Jn, en
        return z, self.max_iter, err <= self.tol, err

    def solve(self, wind_speed: float, *, start: tuple[str, np.ndarray] | None = None) -> TrimPoint:
        """The operating point at ``wind_speed`` [m/s] (see the module docstring).

        Parameters
        ----------
        wind_speed : float
        start : (regime name, unknowns), optional, keyword-only
            A neighbouring solution to continue from (tried first).
        """
        if isinstance(wind_speed, bool) or not isinstance(wind_speed, (int, float, np.floating)) or \
                not math.isfinite(float(wind_speed)) or wind_speed <= 0:
            raise ParameterError(f"wind_speed must be a positive finite number [m/s]; got {wind_speed!r}.")
        U = float(wind_speed)
        t0 = time.perf_counter()
        order = list(predicted_order(self.model, self.control, U, self.par))
        tries: list[tuple[Regime, np.ndarray | None]] = [(r, None) for r in order]
        if start is not None:                 # continue from the neighbour in its regime, if the surfaces agree
            name, z_start = start
            k = next((i for i, r in enumerate(order) if r.name == name), None)
            if k is not None:
                tries.insert(0 if k == 0 else 1, (order[k], np.asarray(z_start, dtype=float)))
        attempts = []
        for regime, z0 in tries:
            note = "" if z0 is None else " (from the neighbouring point)"
            z0 = self.guess(regime, U) if z0 is None else z0
            result = self._attempt(regime, z0, U)
            attempts.append(result[1] + note)
            if result[0] is not None:
                z, it = result[0]
                return self._point(U, z, regime, True, f"{regime.description} (regime {regime.name})", it,
                                   time.perf_counter() - t0, tuple(attempts))
        z0 = self.guess(order[0], U)
        return self._point(U, z0, None, False, "no steady regime of the controller fits: " + "; ".join(attempts),
                           0, time.perf_counter() - t0, tuple(attempts))

    def _attempt(self, regime: Regime, z0: np.ndarray, U: float):
        """``((z, iterations) or None, note)``: solve one regime and check its inequalities."""
        z, it, ok, err = self.newton(z0, U, regime)
        if ok and self.estimates:
            beta_c, torque_c = z[len(self.free)], z[len(self.free) + 1]
            if not self.control.estimator_in_range(beta_c, torque_c):      # ROSCO's fallback to the hub wind
                z, it2, ok, err = self.newton(z, U, regime, estimator_on=False)
                it += it2
        if not ok:
            return None, f"region {regime.name}: Newton did not converge (scaled residual {err:.2g})"
        s = self._signals(z, U)
        why = self.control.violations(regime, s) + self._held_forces(z, U)
        if why:
            return None, f"region {regime.name}: " + ", ".join(why)
        return (z, it), f"region {regime.name}: accepted"

    def _held_forces(self, z: np.ndarray, U: float) -> list[str]:
        """Held coordinates whose acceleration does not vanish (no equilibrium with them held)."""
        if not self.held:
            return []
        eom = self.model.structure.eom
        rhs = np.asarray(self.point_values(z, U, 0.0)[3], dtype=float).reshape(-1)
        bad = [(eom.coordinates[k], rhs[eom.n_q + k]) for k in self.held if abs(rhs[eom.n_q + k]) > HELD_TOLERANCE]
        return [f"{c} has no stiffness and carries a net acceleration {a:.3g} (m/s² or rad/s²): no equilibrium; "
                "add a spring (e.g. yaw_spring= of the OperatingTurbine) or disable the DOF" for c, a in bad]

    def _signals(self, z: np.ndarray, U: float) -> dict[str, float]:
        v = np.asarray(self.signals(z, U, 0.0), dtype=float).reshape(-1)
        n_f = len(self.free)
        names = ("speed", "rotor_speed", "power", "min_pitch", "torque_reference", "pitch_reference", "estimate")
        out = dict(zip(names, v.tolist()))
        out.update(pitch=float(z[n_f]), torque=float(z[n_f + 1]))
        return out

    def _point(self, U, z, regime, success, message, iterations, seconds, attempts) -> TrimPoint:
        dyn = self.dyn
        x, u, p, rhs, y = (np.asarray(v, dtype=float).reshape(-1) for v in self.point_values(z, U, 0.0))
        s = self._signals(z, U)
        channels = MappingProxyType(dict(zip(dyn.output_names, y.tolist())))
        units = MappingProxyType(dict(zip(dyn.output_names, dyn.output_units)))
        region = self.control.region(regime, s) if regime else ""
        if success:
            message += _table_note(self.model.rotor.table, channels)
        shaving = bool(regime is not None and regime.pitch == "min" and s["min_pitch"] > self.control.fine_pitch + 1e-9)
        return TrimPoint(U, bool(success), message, regime.name if regime else "", x, u,
                         MappingProxyType(dict(zip(dyn.parameters, p.tolist()))), s["estimate"], s["min_pitch"],
                         channels, units, rhs, dyn.states, dyn.inputs, "GeAz", region, shaving, iterations, seconds,
                         attempts)

    def unknowns(self, point: TrimPoint) -> np.ndarray:
        """The unknowns of a solved point (to continue from it)."""
        extra = [point.inputs[self.i_u["BlPitchCom"]], point.inputs[self.i_u["GenTqCom"]]]
        if not self.model.spins_freely:
            extra.append(point.parameters["rotor_speed"])
        if self.estimates:
            extra.append(point.wind_estimate)
        return np.concatenate([point.state[self.free], extra])

    def sweep(self, wind_speeds: Sequence[float]) -> list[TrimPoint]:
        """Operating points over ``wind_speeds`` with continuation from the previous successful point."""
        points, start = [], None
        for U in wind_speeds:
            point = self.solve(U, start=start)
            points.append(point)
            start = (point.regime, self.unknowns(point)) if point.success else None
        return points


def _table_note(table, channels) -> str:
    """A note when the point lies outside the rotor's performance table (the surfaces are extrapolated)."""
    lam, beta = channels.get("RtTSR", float("nan")), math.radians(channels.get("BldPitch1", float("nan")))
    out = []
    if not table.tsr[0] <= lam <= table.tsr[-1]:
        out.append(f"TSR {lam:.3g} outside [{table.tsr[0]:g}, {table.tsr[-1]:g}]")
    if not table.pitch[0] - 1e-12 <= beta <= table.pitch[-1] + 1e-12:
        out.append(f"pitch {math.degrees(beta):.3g} deg outside [{math.degrees(table.pitch[0]):g}, "
                   f"{math.degrees(table.pitch[-1]):g}] deg")
    return f" (outside the rotor's performance table: {', '.join(out)}; the surfaces are extrapolated)" if out else ""


def _check_gearbox(model, control: SteadyControl) -> None:
    n_model = model.gearbox_ratio
    if abs(n_model - control.gearbox_ratio) > 1e-6 * n_model:
        import warnings

        warnings.warn(f"the controller's gearbox ratio (WE_GearboxRatio {control.gearbox_ratio:g}) differs from the "
                      f"structure's ({n_model:g}); the estimator uses the controller's.", UserWarning, stacklevel=3)


def trim(model, wind_speed: float, control: SteadyControl | None = None, *, p: Mapping[str, float] | None = None,
         n_azimuth: int | None = None, tol: float = TRIM_TOLERANCE, max_iter: int = 40) -> TrimPoint:
    """The steady operating point of ``model`` at ``wind_speed`` [m/s] under ``control``.

    Parameters
    ----------
    model : OperatingTurbine
    wind_speed : float
        Hub-height wind [m/s].
    control : SteadyControl, optional
        The controller's steady laws; default the built-in NREL 5 MW's (ROSCO 2.10.6).
    p, n_azimuth, tol, max_iter : optional, keyword-only
        See :class:`Trimmer`.

    Returns
    -------
    TrimPoint
        ``success`` False with a ``message`` when no regime fits.

    Examples
    --------
    >>> from mbsym.wind.operation import OperatingTurbine, trim
    >>> point = trim(OperatingTurbine.nrel5mw(), 8.0)           # doctest: +SKIP
    >>> round(point["RotSpeed"], 2), point.regime                # doctest: +SKIP
    (9.2, '2')
    """
    return Trimmer(model, control, p=p, n_azimuth=n_azimuth, tol=tol, max_iter=max_iter).solve(wind_speed)
