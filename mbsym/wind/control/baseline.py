"""Our baseline wind-turbine controller: the ROSCO scheme as one discrete-time CasADi Function.

``BaselineController(settings).function`` maps ``(xc, y) -> (xc_next, u)`` once per
sample time ``dt``; ``u`` is held over the next ``dt`` (zero-order hold), as OpenFAST
holds a DISCON library's commands.  ``x0`` is a constant: the first call (state
``first = 1``) initializes every block from the first measurements, as ROSCO does
at its first call, so no measurement is needed to build ``x0``.

Measurements ``y`` (SI units, :attr:`BaselineController.measurement_names`):

=============  =======  ================================================================
``GenSpeed``   rad/s    generator speed (pitch PI error, torque control)
``RotSpeed``   rad/s    rotor speed (wind-speed estimator)
``BldPitch1``  rad      blade pitch, read at the first call only (afterwards, as in ROSCO,
                        the controller uses its own previous command)
``GenPwr``     W        electrical power (set-point smoother)
``Wind1VelX``  m/s      hub-height wind speed: initializes the estimator (and is the
                        estimate itself with ``wind_estimator = 0`` or out of its range)
=============  =======  ================================================================

Commands ``u``: ``BlPitchCom`` [rad] (collective pitch demand), ``GenTqCom`` [N m]
(generator torque demand, >= 0).

With individual pitch control (``settings.ipc_mode > 0``, ROSCO's ``IPC_ControlMode``;
see :mod:`.ipc`) the measurements grow by ``RootMyc1``, ``RootMyc2``, ``RootMyc3``
[N m] (blade-root out-of-plane moments) and ``Azimuth`` [rad] (rotor azimuth), after
the five above (:data:`IPC_MEASUREMENTS`), and the commands are ``BlPitchCom1``,
``BlPitchCom2``, ``BlPitchCom3`` [rad], ``GenTqCom`` [N m] (:data:`IPC_COMMANDS`).  The
controller's pitch then is, as in ROSCO, the mean of its three previous commands
(at the first call: ``BldPitch1`` for every blade).  Wire signals by name with
:attr:`BaselineController.measurements` and :attr:`BaselineController.commands`.

One step, in ROSCO 2.10.6's order (ROSCO's own source and docs were read to learn
the scheme; the code is ours):

1. filters: generator and rotor speed (first- or second-order low-pass; the generator
   speed then through the notch filters ``F_GenSpdNotch_Ind``, ROSCO's Tustin notch); the
   previous wind estimate (``F_WECornerFreq``); the previous torque demand and the
   previous pitch demand (second order, damping 0.7, corners ``F_LPFCornerFreq``
   and ``F_LPFCornerFreq/4``);
2. wind-speed estimator (``WE_Mode 2``): ROSCO's extended Kalman filter on the
   states (rotor speed, turbulent wind, mean wind) with the rotor torque from the
   Cp table, process noise for a turbulence intensity of 18 % over a length
   scale of 6 rotor radii, measurement noise 0.02 (rad/s)², and the first-order
   poles ``WE_FOPoles``; it falls back to the low-pass-filtered hub wind (corner
   ``F_WECornerFreq/10``) when pitch, torque or speed leave the Cp table's range,
   and restarts on re-entry;
3. set-points: pitch reference speed ``PC_RefSpd`` raised by a negative smoother
   shift; torque reference ``TSRopt·Ŭ/R·N`` (``VS_ControlMode 2``) or ``(P/VS_GenEff/VS_Rgn2K)^(1/3)``
   from the measured power ``P`` (``VS_ControlMode 3``, power-based TSR tracking) low-pass filtered
   (``F_VSRefSpdCornerFreq``), limited to [``VS_MinOMSpd``, ``VS_RefSpd``] and lowered
   by a positive smoother shift; region-3 pitch threshold ``PC_MinPit + PC_Switch``;
4. set-point smoother (``SS_Mode 1``): shift ``((β − β_min)/0.524·SS_VSGain −
   (P_rated − P)/P_rated·SS_PCGain)·PC_RefSpd``, low-pass filtered (``F_SSCornerFreq``);
5. torque: a PI on the speed error saturated at [``VS_MinTq``, min(P_rated/(η ω), ``VS_MaxTq``)]
   (constant power above rated; ``VS_RtTq`` for constant torque) — or with
   ``VS_ControlMode 1`` the state machine k·ω² / PI in regions 1.5 and 2.5 /
   constant power or torque in region 3 — then the rate limit ``VS_MaxRat``;
6. pitch: the gain-scheduled PI (gains interpolated at the filtered pitch) between
   the previous minimum pitch and ``PC_MaxPit``; the minimum pitch is ``PC_FinePit``
   or, with peak shaving (``PS_Mode``), ``PS_BldPitchMin`` at the filtered wind
   estimate; saturation and the rate limits ``PC_MinRat``/``PC_MaxRat``; the tower
   damper's increment (``TD_Mode 1``, :mod:`.tower`) is added before the blades' saturation.

The power reference (``PRC_Mode`` 1, 2 with constant ratings, :mod:`.power_reference`) changes
the set-points of 3, the smoother's rated power in 4, the torque limit in 5 and the minimum pitch in 6;
the start-up (``SU_Mode 1``, :mod:`.startup`, after 2) changes its speed and torque ratings by stage; the
shut-down (``SD_Mode 1``, :mod:`.shutdown`, checked before 2) latches and then replaces the torque law's
output in 5 and each blade's rate-limited pitch demand in 6 by its ramps. Both read ROSCO's time, which
the controller counts from its first call (state ``step_count``, t = 0 there) in single precision.

Differences from the library: ROSCO receives single-precision measurements and
its time step in single precision (pass ``dt=float(numpy.float32(dt))`` to
reproduce it to the last bits); its estimator falls back to the filtered hub wind
on NaN (not reproduced); the nacelle-vane correction of the filtered hub wind is
taken as 1 (no yaw error); and ROSCO switches its estimator off (and restarts the
EKF one step later) when the pitch is below the Cp table's range by any amount,
which happens on rounding residuals of ~1e-20 rad when the rate-limited pitch
reaches fine pitch — we count pitch within :data:`RANGE_TOLERANCE` (1e-12 rad) of
the range as inside.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ...exceptions import DimensionError, ParameterError
from . import power_reference as prc
from . import tower
from ._blocks import controller_time, interp1, lpf1, lpf2, notch, pi, rate_limit, sat
from .estimator import RANGE_TOLERANCE, wind_estimate  # noqa: F401 (re-exported)
from .ipc import IPC_DIAGNOSTICS, ipc_states, ipc_step
from .settings import BaselineSettings
from .shutdown import shutdown_measurements, shutdown_pitch, shutdown_rates, shutdown_states, shutdown_torque
from .startup import startup_ratings, startup_states
from .tower import TRANSLATIONAL_MEASUREMENTS  # noqa: F401 (re-exported)

__all__ = ["BaselineController", "MEASUREMENTS", "COMMANDS", "IPC_MEASUREMENTS", "IPC_COMMANDS",
           "FLOATING_MEASUREMENTS"]

#: Measurement names and units, in the order of ``y``.
MEASUREMENTS = {"GenSpeed": "rad/s", "RotSpeed": "rad/s", "BldPitch1": "rad", "GenPwr": "W", "Wind1VelX": "m/s"}
#: Command names and units, in the order of ``u``.
COMMANDS = {"BlPitchCom": "rad", "GenTqCom": "N m"}
#: Measurements with individual pitch control (``ipc_mode > 0``), in the order of ``y``.
IPC_MEASUREMENTS = {**MEASUREMENTS, "RootMyc1": "N m", "RootMyc2": "N m", "RootMyc3": "N m", "Azimuth": "rad"}
#: Commands with individual pitch control, in the order of ``u``.
IPC_COMMANDS = {"BlPitchCom1": "rad", "BlPitchCom2": "rad", "BlPitchCom3": "rad", "GenTqCom": "N m"}
#: Measurements the rotational floating feedback adds after the others (``floating_mode = 2``): the nacelle's
#: pitching acceleration about the shaft's lateral axis (OpenFAST's ``NcIMURAys``, ServoDyn's record 83).
FLOATING_MEASUREMENTS = tower.ROTATIONAL_MEASUREMENTS
#: (:data:`TRANSLATIONAL_MEASUREMENTS`, from :mod:`.tower`) Measurements the translational floating feedback
#: (``floating_mode = 1``) and the tower damper (``tower_damper_mode = 1``) add after the others: the tower
#: top's fore-aft and side-side accelerations in the tower-top axes (ServoDyn's records 53, 54) and the nacelle
#: yaw (record 37), which ROSCO turns into the nacelle's fore-aft acceleration ``ax cos(yaw) + ay sin(yaw)``.
#: Internal signals of the floating feedback, after :data:`DIAGNOSTICS` (``floating_mode = 2``; with
#: ``floating_mode = 1``: ``FA_AccF``, ``FA_vel``, ``Fl_PitCom``).
FLOATING_DIAGNOSTICS = ("NacIMU_FA_AccF", "NacIMU_FA_vel", "Fl_PitCom")
TRANSLATIONAL_DIAGNOSTICS = ("FA_AccF", "FA_vel", "Fl_PitCom")
#: Internal signals of the tower damper (``tower_damper_mode = 1``), last: the high-pass filtered fore-aft
#: acceleration [m/s²] and the pitch increment [rad].
TOWER_DAMPER_DIAGNOSTICS = ("FA_AccHPF", "FA_PitCom")
#: Internal signals of the shut-down (``shutdown_mode = 1``) and the start-up (``startup_mode = 1``), last.
SHUTDOWN_DIAGNOSTICS = ("SD_Trigger", "SD_Stage")
STARTUP_DIAGNOSTICS = ("SU_Stage", "PRC_R_Speed", "PRC_R_Torque")
#: Internal signals of :attr:`BaselineController.diagnostics`.
DIAGNOSTICS = ("GenSpeedF", "RotSpeedF", "WE_Vw", "WE_Vw_F", "WE_Op", "PC_MinPit", "PC_RefSpd", "PC_SpdErr",
               "PC_KP", "PC_KI", "PC_PitComT", "VS_RefSpd", "VS_SpdErr", "SS_DelOmegaF", "VS_State", "Cp_op")


#: Units of the controller's states by name (SI; filter states hold last inputs and outputs of the signal
#: filtered; the EKF's state is [rotor speed, turbulent wind, mean wind], its covariance and gain follow;
#: "-": the first-call and estimator-on flags).
_EKF_X = ("rad/s", "m/s", "m/s")
STATE_UNITS = {
    "first": "-", "estimator_on": "-", "gen_speed_filter": "rad/s", "rot_speed_filter": "rad/s",
    "estimate_filter": "m/s", "torque_filter": "N m", "pitch_filter": "rad", "hub_wind_filter": "m/s",
    "wind_estimate": "m/s", "reference_filter": "rad/s", "smoother_filter": "rad/s", "last_power": "W",
    "min_pitch": "rad", "pitch_integral": "rad", "torque_integral": "N m", "torque_last": "N m",
    "pitch_total_last": "rad", "pitch_last": "rad", "pitch_command_last": "rad", "root_filter": "N m",
    "ipc_integral": "rad", "ipc_filter": "rad", "floating_lowpass": "rad/s^2", "floating_highpass": "rad/s^2",
    "floating_integral": "rad/s", "actuator_filter": "rad", "speed_notch": "rad/s",
    "tower_damper_highpass": "m/s^2", "tower_damper_integral": "rad", "power_reference_filter": "m/s",
    "step_count": "-", "shutdown_trigger": "-", "shutdown_stage": "-", "shutdown_stage_start": "s",
    "shutdown_pitch_filter": "rad", "shutdown_yaw_filter": "-", "shutdown_speed_filter": "rad/s",
    "shutdown_pitch": "rad", "shutdown_torque": "N m", "startup_stage": "-", "startup_stage_start": "s",
    "startup_rotor_filter": "rad/s",
    "ekf_x": _EKF_X,
    "ekf_P": ("rad^2/s^2", "rad m/s^2", "rad m/s^2", "rad m/s^2", "m^2/s^2", "m^2/s^2", "rad m/s^2", "m^2/s^2",
              "m^2/s^2"),                                                # (x_i)(x_j)
    "ekf_K": ("-", "m/rad", "m/rad"),                                    # x_i per measured rotor speed [rad/s]
}


def state_unit(name: str) -> str:
    """Unit of a controller state ``name`` (``"ekf_x[1]"``, ``"floating_notch1[0]"`` ...), "" if unknown."""
    base, _, index = name.partition("[")
    base = "floating_highpass" if base.startswith("floating_notch") else \
        "speed_notch" if base.startswith("speed_notch") else base
    unit = STATE_UNITS.get(base, "")
    return unit[int(index.rstrip("]"))] if isinstance(unit, tuple) else unit


class _States:
    """Named slots of the state vector."""

    def __init__(self) -> None:
        self.names: list[str] = []
        self.x0: list[float] = []

    def add(self, name: str, n: int = 1, x0: float = 0.0) -> None:
        self.names += [name] if n == 1 else [f"{name}[{i}]" for i in range(n)]
        self.x0 += [x0] * n

    def bind(self, x: ca.SX) -> dict[str, ca.SX]:
        out, i = {}, 0
        while i < len(self.names):
            base = self.names[i].split("[")[0]
            n = sum(1 for nm in self.names if nm.split("[")[0] == base)
            out[base] = x[i] if n == 1 else x[i:i + n]
            i += n
        return out


class BaselineController:
    """The ROSCO control scheme as a discrete-time CasADi Function (see the module docstring).

    Parameters
    ----------
    settings : BaselineSettings
        All numbers; build them with :meth:`from_discon` or the tuning functions of
        :mod:`mbsym.wind.control.tuning`.

    Attributes
    ----------
    function : casadi.Function
        ``(xc, y) -> (xc_next, u)``, SX, one controller step.
    dt : float
        Sample time [s].
    x0 : ndarray
        Initial controller state (constant; the first call initializes).
    measurements, commands : tuple of str
        Names of the entries of ``y`` and ``u`` (units: :data:`MEASUREMENTS`,
        :data:`COMMANDS`; with IPC :data:`IPC_MEASUREMENTS`, :data:`IPC_COMMANDS`).
    measurement_names, command_names : tuple of str
        The same (older names).
    state_names, diagnostic_names : tuple of str
        Names of the states and of the diagnostics.
    diagnostics : casadi.Function
        ``(xc, y) -> d`` with the internal signals :data:`DIAGNOSTICS` of the same step
        (followed by :data:`~.ipc.IPC_DIAGNOSTICS` with IPC).

    Examples
    --------
    >>> from mbsym.wind.control import BaselineController
    >>> ctrl = BaselineController.from_discon("DISCON.IN", dt=0.00625)  # doctest: +SKIP
    >>> x, u = ctrl.function(ctrl.x0, [116.6, 1.2025, 0.0075, 3.46e6, 10.0])  # doctest: +SKIP
    """

    # names without IPC (class level, as before); instances set their own
    measurement_names = tuple(MEASUREMENTS)
    command_names = tuple(COMMANDS)

    def __init__(self, settings: BaselineSettings) -> None:
        if not isinstance(settings, BaselineSettings):
            raise TypeError(f"settings must be a BaselineSettings; got {type(settings).__name__}.")
        self.settings = settings
        self.dt = settings.dt
        self.ipc = settings.ipc_mode > 0
        self.floating = settings.floating_mode > 0
        measured = tuple(IPC_MEASUREMENTS if self.ipc else MEASUREMENTS)
        translational = settings.floating_mode == 1
        self.measurements = self.measurement_names = measured + tower.extra_measurements(settings) + \
            shutdown_measurements(settings)
        self.commands = self.command_names = tuple(IPC_COMMANDS if self.ipc else COMMANDS)
        self.diagnostic_names = DIAGNOSTICS + (IPC_DIAGNOSTICS if self.ipc else ()) + \
            ((TRANSLATIONAL_DIAGNOSTICS if translational else FLOATING_DIAGNOSTICS) if self.floating else ()) + \
            (TOWER_DAMPER_DIAGNOSTICS if settings.tower_damper_mode else ()) + \
            (SHUTDOWN_DIAGNOSTICS if settings.shutdown_mode else ()) + (STARTUP_DIAGNOSTICS if settings.startup_mode
                                                                        else ())
        states = self._layout()
        x = ca.SX.sym("xc", len(states.names))
        y = ca.SX.sym("y", len(self.measurements))
        x_next, u, diag = self._step(states.bind(x), y)
        order = [x_next[name] for name in dict.fromkeys(nm.split("[")[0] for nm in states.names)]
        xn = ca.vertcat(*[ca.vec(v) for v in order])
        self.state_names = tuple(states.names)
        self.state_units = tuple(state_unit(n) for n in self.state_names)
        if translational:           # the filters carry m/s² and the integral m/s
            self.state_units = tuple(u.replace("rad/s^2", "m/s^2").replace("rad/s", "m/s")
                                     if n.startswith("floating_") else u
                                     for n, u in zip(self.state_names, self.state_units))
        self.x0 = np.array(states.x0)
        self.x0.setflags(write=False)
        self.function = ca.Function("baseline_controller", [x, y], [xn, ca.vertcat(*u)], ["xc", "y"],
                                    ["xc_next", "u"], {"cse": True})
        self.diagnostics = ca.Function("baseline_diagnostics", [x, y], [ca.vertcat(*diag)], ["xc", "y"], ["d"],
                                       {"cse": True})

    @classmethod
    def from_discon(cls, discon, *, dt: float, performance=None) -> BaselineController:
        """Configure from a ROSCO ``DISCON.IN`` (see :meth:`BaselineSettings.from_discon`)."""
        return cls(BaselineSettings.from_discon(discon, dt=dt, performance=performance))

    # ------------------------------------------------------------------ layout
    def _layout(self) -> _States:
        s = self.settings
        st = _States()
        st.add("first", x0=1.0)
        speed_states = 2 if s.speed_filter_order == 1 else 4
        st.add("gen_speed_filter", speed_states)
        for k in range(len(s.speed_notch_freqs)):
            st.add(f"speed_notch{k + 1}", 4)
        st.add("rot_speed_filter", speed_states)
        st.add("estimate_filter", 2)
        st.add("torque_filter", 4)
        st.add("pitch_filter", 4)
        st.add("hub_wind_filter", 2)
        st.add("wind_estimate")
        st.add("estimator_on", x0=1.0)
        st.add("ekf_x", 3)
        st.add("ekf_P", 9)
        st.add("ekf_K", 3)
        st.add("reference_filter", 2)
        st.add("smoother_filter", 2)
        st.add("last_power")
        st.add("min_pitch")
        st.add("pitch_integral")
        st.add("torque_integral", 1 if s.torque_mode in (2, 3) else 4)
        st.add("torque_last")
        st.add("pitch_total_last")
        blades = 3 if self.ipc else 1
        st.add("pitch_last", blades)
        st.add("pitch_command_last", blades)
        if self.ipc:
            ipc_states(st, s)
        if self.floating:
            st.add("floating_lowpass", 4)
            st.add("floating_highpass", 2)
            for k in range(len(s.tower_notch_freqs)):
                st.add(f"floating_notch{k + 1}", 4)
            st.add("floating_integral")
        if s.actuator_mode:
            st.add("actuator_filter", (2 if s.actuator_mode == 1 else 4) * blades)
        if s.tower_damper_mode:
            st.add("tower_damper_highpass", 2)
            st.add("tower_damper_integral")
        if s.power_reference_mode == 1:
            st.add("power_reference_filter", 2)
        if s.shutdown_mode or s.startup_mode:
            st.add("step_count")
        if s.shutdown_mode:
            shutdown_states(st, s)
        if s.startup_mode:
            startup_states(st, s)
        return st

    # ------------------------------------------------------------------ one step
    def _step(self, x: dict, y: ca.SX):
        s, dt = self.settings, self.dt
        r = x["first"]
        gen_speed, rot_speed, pitch_meas, power_meas, hub_wind = (y[i] for i in range(5))
        nxt: dict[str, ca.SX] = {"first": ca.SX(0.0)}

        # --- initialization values (ROSCO SetParameters at its first call) and inputs of this call
        if self.ipc:    # ROSCO's pitch: the mean of the blades' previous commands (first call: measured)
            last = x["pitch_command_last"]
            pitch = ca.if_else(r, (1.0 / 3.0) * (pitch_meas + pitch_meas + pitch_meas),
                               (1.0 / 3.0) * (last[0] + last[1] + last[2]))
        else:
            pitch = ca.if_else(r, pitch_meas, x["pitch_command_last"])
        pitch_blade1 = ca.if_else(r, pitch_meas, x["pitch_command_last"][0])
        torque0 = ca.if_else(gen_speed > 0.98 * s.pitch_reference_speed, s.rated_torque,
                             ca.fmin(s.rated_torque, s.region2_gain * gen_speed**2))
        last_torque = ca.if_else(r, torque0, x["torque_last"])
        last_estimate = ca.if_else(r, hub_wind, x["wind_estimate"])
        shift_prev = ca.if_else(r, 0.0, x["smoother_filter"][1])
        power = ca.if_else(r, torque0 * gen_speed * s.generator_efficiency, power_meas)

        # --- 1. filters
        gen_f, nxt["gen_speed_filter"] = self._speed_filter(gen_speed, x["gen_speed_filter"], r)
        for k, (w, bn, bd) in enumerate(zip(s.speed_notch_freqs, s.speed_notch_beta_num, s.speed_notch_beta_den)):
            gen_f, st = notch(gen_f, _split4(x[f"speed_notch{k + 1}"]), w, bn, bd, dt, r)     # ROSCO's order
            nxt[f"speed_notch{k + 1}"] = ca.vertcat(*st)
        rot_f, nxt["rot_speed_filter"] = self._speed_filter(rot_speed, x["rot_speed_filter"], r)
        est_f, a, b = lpf1(last_estimate, *_split2(x["estimate_filter"]), s.estimate_filter_corner, dt, r)
        nxt["estimate_filter"] = ca.vertcat(a, b)
        torque_f, t_states = lpf2(last_torque, _split4(x["torque_filter"]), s.speed_filter_corner, 0.7, dt, r)
        nxt["torque_filter"] = ca.vertcat(*t_states)
        pitch_f, p_states = lpf2(pitch, _split4(x["pitch_filter"]), 0.25 * s.speed_filter_corner, 0.7, dt, r)
        nxt["pitch_filter"] = ca.vertcat(*p_states)
        if self.floating:
            acc_f = tower.floating_filter(s, dt, x, nxt, r, tower.floating_signal(s, self.measurements, y, r))
        if s.tower_damper_mode:
            fa_signal = tower.fore_aft_acceleration(self.measurements, y, r)
            fa_pitch, fa_acc = tower.tower_damper(s, dt, x, nxt, r, fa_signal)

        # --- shut-down check (ROSCO's Shutdown, before the estimator): trigger latch, stage and ramp rates
        time = controller_time(x, nxt, dt, r) if s.shutdown_mode or s.startup_mode else None
        self._shutdown = None
        if s.shutdown_mode:
            yaw = y[self.measurements.index("YawErr")] if s.shutdown_on_yaw_error else None
            self._shutdown = shutdown_rates(s, dt, x, nxt, r, time, pitch, gen_speed, yaw)

        # --- 2. wind-speed estimate
        estimate, op, cp_op = wind_estimate(s, dt, x, nxt, r, rot_f, pitch, torque_f, hub_wind, last_estimate)

        # --- 3. set-points (power reference: ROSCO's ratings, PRC_Mode 2, or speed table, PRC_Mode 1)
        r_speed, r_torque, r_pitch = prc.ratings(s)
        if s.startup_mode:     # ROSCO's Startup: the ratings by stage
            r_speed, r_torque, su_stage = startup_ratings(s, dt, x, nxt, r, time, rot_speed, r_speed, r_torque)
        prc_speed = prc.scheduled_speed(s, dt, x, nxt, r, estimate)
        ref_pitch_speed = s.pitch_reference_speed * r_speed if prc_speed is None else prc_speed
        ref_pitch_speed = ref_pitch_speed - ca.fmin(shift_prev, 0.0)
        pitch_error = ref_pitch_speed - gen_f
        if s.torque_mode == 2:
            tsr_ref = s.optimal_tsr * estimate / s.rotor_radius * s.gearbox_ratio
        elif s.torque_mode == 3:       # power-based TSR tracking (ROSCO's ControllerBlocks): the measured power
            tsr_ref = (ca.fmax(power, 0.0) / s.generator_efficiency / s.region2_gain) ** (1.0 / 3.0)
        else:
            tsr_ref = ca.SX(s.rated_generator_speed)
        ref, a, b = lpf1(tsr_ref, *_split2(x["reference_filter"]), s.reference_filter_corner, dt, r)
        nxt["reference_filter"] = ca.vertcat(a, b)
        ref = sat(ref, s.min_generator_speed, s.rated_generator_speed * r_speed)
        ref = ref if prc_speed is None else prc_speed
        ref = ref - ca.fmax(shift_prev, 0.0)
        ref = ca.fmax(ref, s.min_generator_speed)
        torque_error = ref - gen_f
        region3_pitch = x["min_pitch"] + s.region3_pitch_margin

        # --- 4. set-point smoother
        if s.setpoint_smoothing:
            shift = ((pitch - x["min_pitch"]) / 0.524 * s.smoother_torque_gain
                     - (s.rated_power * (r_speed * r_torque * r_pitch) - x["last_power"]) / s.rated_power
                     * s.smoother_power_gain) \
                * s.pitch_reference_speed
            shift_f, a, b = lpf1(shift, *_split2(x["smoother_filter"]), s.smoother_corner, dt, r)
            nxt["smoother_filter"] = ca.vertcat(a, b)
        else:
            shift_f = ca.SX(0.0)
            nxt["smoother_filter"] = ca.SX.zeros(2)

        # --- 5. torque
        torque, state_code = self._torque(x, nxt, r, gen_f, torque_error, pitch, region3_pitch, last_torque,
                                          r_torque)
        nxt["last_power"] = power

        # --- 6. pitch
        kp = interp1(s.schedule_pitch, s.schedule_kp, "pc_kp")(pitch_f)
        ki = interp1(s.schedule_pitch, s.schedule_ki, "pc_ki")(pitch_f)
        lo, hi = x["min_pitch"], s.pitch_max
        if s.startup_mode:     # before the start (stage -1) the PI's limits are the pitch: it holds
            lo, hi = ca.if_else(su_stage == -1, pitch, lo), ca.if_else(su_stage == -1, pitch, hi)
        total, nxt["pitch_integral"] = pi(pitch_error, kp, ki, lo, hi, dt, x["pitch_integral"], pitch_blade1, r)
        if self.ipc:
            ipc_pitch, ipc_diag = ipc_step(s, dt, x, nxt, r, [y[5], y[6], y[7]], y[8], rot_f, estimate, pitch)
        if s.peak_shaving:    # ROSCO's PitchSaturation: the higher of peak shaving and the pitch rating's pitch
            min_pitch = interp1(s.min_pitch_wind_speeds, s.min_pitch_schedule, "ps_min")(est_f)
            rating_pitch = prc.rating_min_pitch(s)
            min_pitch = ca.fmax(min_pitch if rating_pitch is None else ca.fmax(min_pitch, rating_pitch), s.fine_pitch)
        else:
            min_pitch = ca.SX(s.fine_pitch)
        nxt["min_pitch"] = min_pitch
        if self.floating:       # ROSCO's FloatingFeedback: −Kp × the integrated, filtered acceleration
            gain = interp1(s.floating_wind_speeds, s.floating_kp, "fl_kp")(est_f)
            fl_pitch, velocity = tower.floating_pitch(s, dt, x, nxt, r, acc_f, gain)
            total = total + fl_pitch
        total = sat(total, min_pitch, s.pitch_max)
        total, nxt["pitch_total_last"] = rate_limit(total, x["pitch_total_last"], s.pitch_rate_min,
                                                    s.pitch_rate_max, dt, r, pitch)
        demand = sat(total + fa_pitch if s.tower_damper_mode else total, min_pitch, s.pitch_max)
        if self.ipc:
            commands = self._blade_commands(x, nxt, r, demand + ca.vertcat(*ipc_pitch), min_pitch, pitch_meas)
        else:
            commands = self._blade_commands(x, nxt, r, demand, min_pitch, pitch)

        diag = [gen_f, rot_f, estimate, est_f, op, min_pitch, ref_pitch_speed, pitch_error, kp, ki, total, ref,
                torque_error, shift_f, state_code, cp_op] + (ipc_diag if self.ipc else []) + \
            ([acc_f, velocity, fl_pitch] if self.floating else []) + \
            ([fa_acc, fa_pitch] if s.tower_damper_mode else []) + \
            (list(self._shutdown[0::3]) if s.shutdown_mode else []) + \
            ([su_stage, r_speed, r_torque] if s.startup_mode else [])
        return nxt, commands + [ca.fmax(torque, 0.0)], diag

    def _blade_commands(self, x, nxt, r, demand, min_pitch, reset_pitch):
        """Per blade: (IPC_SatMode 1: saturate again,) rate limit, hardware saturation, rate limit."""
        s, dt = self.settings, self.dt
        if self.ipc and s.ipc_saturation_mode == 1:
            demand = sat(demand, min_pitch, s.pitch_max)
        demand, nxt["pitch_last"] = rate_limit(demand, x["pitch_last"], s.pitch_rate_min, s.pitch_rate_max,
                                               dt, r, reset_pitch)
        if self._shutdown is not None:     # ROSCO's PitCom_SD: after the trip, the ramp replaces the demand
            trigger, rate = self._shutdown[0], self._shutdown[1]
            demand = shutdown_pitch(x, nxt, r, trigger, rate, dt, demand)
        demand = self._actuator_model(x, nxt, r, demand)
        command = sat(demand, s.pitch_min, s.pitch_max)
        command, nxt["pitch_command_last"] = rate_limit(command, x["pitch_command_last"], s.pitch_rate_min,
                                                        s.pitch_rate_max, dt, r, reset_pitch)
        return [command[k] for k in range(command.shape[0])]

    def _actuator_model(self, x, nxt, r, demand):
        """ROSCO's pitch actuator model (``PA_Mode`` 1, 2): a low-pass filter on every blade's command."""
        s, dt = self.settings, self.dt
        if s.actuator_mode == 0:
            return demand
        n = demand.shape[0]
        states = x["actuator_filter"]
        if s.actuator_mode == 1:
            out, a, b = lpf1(demand, states[0:n], states[n:2 * n], s.actuator_corner, dt, r)
            nxt["actuator_filter"] = ca.vertcat(a, b)
            return out
        out, st = lpf2(demand, tuple(states[k * n:(k + 1) * n] for k in range(4)), s.actuator_corner,
                       s.actuator_damping, dt, r)
        nxt["actuator_filter"] = ca.vertcat(*st)
        return out

    def _speed_filter(self, signal, states, r):
        s = self.settings
        if s.speed_filter_order == 1:
            y, a, b = lpf1(signal, states[0], states[1], s.speed_filter_corner, self.dt, r)
            return y, ca.vertcat(a, b)
        y, st = lpf2(signal, _split4(states), s.speed_filter_corner, s.speed_filter_damping, self.dt, r)
        return y, ca.vertcat(*st)

    def _torque(self, x, nxt, r, gen_f, error, pitch, region3_pitch, last_torque, rating):
        """ROSCO's VariableSpeedControl (modes 1, 2 and 3) and its state machine; ``rating``: ``PRC_R_Torque``."""
        s, dt = self.settings, self.dt
        const_power_torque = (s.rated_power / s.generator_efficiency) / gen_f * rating
        max_torque = ca.fmin(const_power_torque, s.torque_max) if s.constant_power else ca.SX(s.rated_torque * rating)
        if s.torque_mode in (2, 3):
            torque, nxt["torque_integral"] = pi(error, s.torque_kp, s.torque_ki, s.torque_min, max_torque, dt,
                                                x["torque_integral"], last_torque, r)
            code = ca.SX(7.0)
        else:
            torque, code = self._torque_state_machine(x, nxt, r, gen_f, error, pitch, region3_pitch, last_torque,
                                                      const_power_torque)
        if self._shutdown is not None:     # ROSCO's GenTq_SD: after the trip, the ramp replaces the law
            torque = shutdown_torque(s, x, nxt, r, self._shutdown[0], self._shutdown[2], dt, torque)
        torque = sat(torque, s.torque_min, ca.fmin(s.torque_max, max_torque))
        torque, nxt["torque_last"] = rate_limit(torque, x["torque_last"], -s.torque_rate_max, s.torque_rate_max,
                                                dt, r)
        return torque, code

    def _torque_state_machine(self, x, nxt, r, gen_f, error, pitch, region3_pitch, last_torque, cp_torque):
        s, dt = self.settings, self.dt
        ar_i, br_i, ar_prev, br_prev = (x["torque_integral"][i] for i in range(4))
        max_om_tq = s.region2_gain * s.rated_generator_speed**2
        min_om_tq = s.region2_gain * s.min_generator_speed**2
        region3 = 5.0 if s.constant_power else 4.0
        # state machine (uses the previous PI outputs; at the first call: region 3 or 2 by pitch)
        state = ca.if_else(pitch >= region3_pitch, region3,
                           ca.if_else(ar_prev >= max_om_tq * 1.01, 3.0,
                                      ca.if_else((gen_f < s.rated_generator_speed) * (br_prev >= min_om_tq), 2.0,
                                                 ca.if_else(br_prev < min_om_tq, 1.0, 0.0))))
        state = ca.if_else(r, ca.if_else(pitch >= region3_pitch, region3, 2.0), state)
        ar, ar_i = pi(error, s.torque_kp, s.torque_ki, max_om_tq, s.region25_torque_max, dt, ar_i, max_om_tq, r)
        br, br_i = pi(s.min_generator_speed - gen_f, s.torque_kp, s.torque_ki, s.torque_min, min_om_tq, dt, br_i,
                      min_om_tq, r)
        nxt["torque_integral"] = ca.vertcat(ar_i, br_i, ar, br)
        k_omega2 = s.region2_gain * gen_f**2
        region3_torque = cp_torque if s.constant_power else ca.SX(s.rated_torque)
        torque = ca.if_else(state == 1.0, br, ca.if_else(state == 2.0, k_omega2, ca.if_else(
            state == 3.0, ar, ca.if_else(state >= 4.0, region3_torque, last_torque))))
        return torque, state

    # ------------------------------------------------------------------ numeric helpers
    def run(self, measurements, *, x0=None, compiled: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Run the controller open loop over a sequence of measurements (one row per step).

        Parameters
        ----------
        measurements : array_like, shape (n_steps, n_y)
            ``y`` at each step, columns in :attr:`measurements` order (SI units).
        x0 : array_like, optional
            Initial state (default :attr:`x0`).
        compiled : bool, optional
            Evaluate generated C (:func:`mbsym.compile_function`, disk-cached) instead
            of CasADi's virtual machine.

        Returns
        -------
        commands : ndarray, shape (n_steps, n_u)
            ``u`` at each step (held over the following ``dt``).
        states : ndarray, shape (n_steps + 1, n_states)
            The state before each step and after the last.
        """
        y = np.asarray(measurements, dtype=float)
        if y.ndim != 2 or y.shape[1] != len(self.measurements):
            raise DimensionError(f"measurements must have shape (n_steps, {len(self.measurements)}) with columns "
                                 f"{list(self.measurements)}; got {y.shape}.")
        if not np.all(np.isfinite(y)):
            raise ParameterError("measurements must be finite.")
        x = np.array(self.x0 if x0 is None else x0, dtype=float).reshape(-1)
        if x.size != self.x0.size:
            raise DimensionError(f"x0 has {x.size} entries; expected {self.x0.size}.")
        loop = self.chunk_function(compiled=compiled)
        n, chunk = y.shape[0], loop.size2_in(1)
        padded = np.vstack([y, np.repeat(y[-1:], (-n) % chunk, axis=0)]) if n else y
        us, xs = [], []
        for k in range(0, padded.shape[0], chunk):
            x_chunk, u_chunk = loop(x, padded[k:k + chunk].T)
            xs.append(np.asarray(x_chunk).T)
            us.append(np.asarray(u_chunk).T)
            x = xs[-1][-1]
        states = np.vstack([self.x0 if x0 is None else np.asarray(x0, dtype=float).reshape(1, -1)] + xs)[:n + 1]
        commands = np.vstack(us)[:n] if us else np.zeros((0, len(self.commands)))
        return commands, states

    def chunk_function(self, *, compiled: bool = False, steps: int = 256):
        """``(xc, Y) -> (Xc, U)``: ``steps`` controller steps in one call (CasADi ``mapaccum``).

        ``Y`` is ``len(measurements)`` × steps; ``Xc`` holds the states after each step.  Cached per
        controller; ``compiled=True`` returns the compiled version.
        """
        key = (compiled, steps)
        cache = self.__dict__.setdefault("_chunks", {})
        if key not in cache:
            f = self.function.mapaccum(f"baseline_controller_{steps}", steps)
            if compiled:
                from ...codegen import compile_function
                f = compile_function(f).function
            cache[key] = f
        return cache[key]

    def __repr__(self) -> str:
        s = self.settings
        return (f"BaselineController(dt={self.dt:g} s, torque_mode={s.torque_mode}, wind_estimator="
                f"{s.wind_estimator}, ipc_mode={s.ipc_mode}, {len(self.state_names)} states)")


def _split2(v):
    return v[0], v[1]


def _split4(v):
    return v[0], v[1], v[2], v[3]
