"""Settings of the baseline controller (descriptive SI names) and their mapping from ROSCO's ``DISCON.IN``.

:class:`BaselineSettings` holds every number :class:`~mbsym.wind.control.baseline.BaselineController`
uses; :data:`DISCON_MAP` is the one documented mapping from ``DISCON.IN`` keys
(``VS_GenEff`` % becomes a fraction, every other value keeps ROSCO's SI unit).
:meth:`BaselineSettings.from_discon` reads a ``DISCON.IN`` (and the performance
table it names, for the wind-speed estimator) and refuses, naming file and line,
the ROSCO features the baseline does not implement (yaw control, power reference
from open-loop or ZeroMQ inputs, fixed-pitch torque control, the I&I estimator, ...); use
:class:`~mbsym.wind.control.discon.DisconController` with the
library for those. Modelled besides the land scheme: the floating feedback, translational
``Fl_Mode 1`` and rotational ``Fl_Mode 2``, with its filters (:data:`FLOATING_MAP`), the pitch actuator
model ``PA_Mode`` 1 and 2 (:data:`ACTUATOR_MAP`), the generator-speed notch filters (``F_GenSpdNotch_N``),
the tower fore-aft damper ``TD_Mode 1`` (:data:`TOWER_DAMPER_MAP`), the power reference ``PRC_Mode`` 1
and 2 with constant ratings (``PRC_Comm 0``, :data:`POWER_REFERENCE_MAP`), the shut-down ``SD_Mode 1``
(:data:`~.shutdown.SHUTDOWN_MAP`) and the start-up ``SU_Mode 1`` (:data:`~.startup.STARTUP_MAP`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from ...exceptions import ControllerError, OpenFASTFormatError, ParameterError

__all__ = ["BaselineSettings", "DISCON_MAP", "IPC_MAP", "FLOATING_MAP", "ACTUATOR_MAP", "TOWER_DAMPER_MAP",
           "POWER_REFERENCE_MAP", "UNSUPPORTED_MODES"]

#: DISCON.IN key → BaselineSettings attribute.
DISCON_MAP = {
    "F_LPFType": "speed_filter_order", "F_LPFCornerFreq": "speed_filter_corner",
    "F_LPFDamping": "speed_filter_damping", "VS_ControlMode": "torque_mode", "VS_ConstPower": "constant_power",
    "SS_Mode": "setpoint_smoothing", "WE_Mode": "wind_estimator", "PS_Mode": "peak_shaving",
    "F_SSCornerFreq": "smoother_corner", "F_WECornerFreq": "estimate_filter_corner",
    "F_VSRefSpdCornerFreq": "reference_filter_corner",
    "PC_GS_angles": "schedule_pitch", "PC_GS_KP": "schedule_kp", "PC_GS_KI": "schedule_ki",
    "PC_MaxPit": "pitch_max", "PC_MinPit": "pitch_min", "PC_MaxRat": "pitch_rate_max",
    "PC_MinRat": "pitch_rate_min", "PC_RefSpd": "pitch_reference_speed", "PC_FinePit": "fine_pitch",
    "PC_Switch": "region3_pitch_margin", "VS_GenEff": "generator_efficiency", "VS_ArSatTq": "region25_torque_max",
    "VS_MaxRat": "torque_rate_max", "VS_MaxTq": "torque_max", "VS_MinTq": "torque_min",
    "VS_MinOMSpd": "min_generator_speed", "VS_Rgn2K": "region2_gain", "VS_RtPwr": "rated_power",
    "VS_RtTq": "rated_torque", "VS_RefSpd": "rated_generator_speed", "VS_KP": "torque_kp",
    "VS_KI": "torque_ki", "VS_TSRopt": "optimal_tsr", "SS_VSGain": "smoother_torque_gain",
    "SS_PCGain": "smoother_power_gain", "WE_BladeRadius": "rotor_radius", "WE_GearboxRatio": "gearbox_ratio",
    "WE_Jtot": "drivetrain_inertia", "WE_RhoAir": "air_density", "WE_FOPoles_v": "estimator_wind_speeds",
    "WE_FOPoles": "estimator_poles", "PS_WindSpeeds": "min_pitch_wind_speeds", "PS_BldPitchMin": "min_pitch_schedule",
}
#: DISCON.IN keys of individual pitch control → BaselineSettings attribute (read when IPC_ControlMode > 0).
IPC_MAP = {
    "IPC_ControlMode": "ipc_mode", "IPC_SatMode": "ipc_saturation_mode", "IPC_Vramp": "ipc_wind_ramp",
    "IPC_IntSat": "ipc_integrator_limit", "IPC_KP": "ipc_kp", "IPC_KI": "ipc_ki",
    "IPC_aziOffset": "ipc_azimuth_offset", "IPC_CornerFreqAct": "ipc_actuator_corner",
}
#: DISCON.IN keys of the floating feedback → BaselineSettings attribute (read when Fl_Mode > 0); the
#: tower-top notch filters (F_TwrTopNotch_Ind into F_NotchFreqs/BetaNum/BetaDen) are read with them.
FLOATING_MAP = {
    "Fl_Mode": "floating_mode", "Fl_Kp": "floating_kp", "Fl_U": "floating_wind_speeds",
    "F_FlHighPassFreq": "floating_highpass_corner",
}
#: DISCON.IN keys of the pitch actuator model → BaselineSettings attribute (read when PA_Mode > 0).
ACTUATOR_MAP = {"PA_Mode": "actuator_mode", "PA_CornerFreq": "actuator_corner", "PA_Damping": "actuator_damping"}
#: DISCON.IN keys of the tower fore-aft damper → BaselineSettings attribute (read when TD_Mode > 0).
TOWER_DAMPER_MAP = {"TD_Mode": "tower_damper_mode", "FA_KI": "tower_damper_ki",
                    "FA_HPFCornerFreq": "tower_damper_highpass_corner", "FA_IntSat": "tower_damper_limit"}
#: DISCON.IN keys of the power reference → BaselineSettings attribute (read when PRC_Mode > 0; the ratings and
#: their pitch table with PRC_Mode 2 only).
POWER_REFERENCE_MAP = {
    "PRC_Mode": "power_reference_mode", "PRC_LPF_Freq": "power_reference_filter_corner",
    "PRC_WindSpeeds": "power_reference_wind_speeds", "PRC_GenSpeeds": "power_reference_generator_speeds",
    "PRC_R_Speed": "power_rating_speed", "PRC_R_Torque": "power_rating_torque", "PRC_R_Pitch": "power_rating_pitch",
    "PRC_R_Table": "power_rating_table", "PRC_Pitch_Table": "power_rating_min_pitch",
}
#: Modes the baseline does not implement: key → the values it accepts.
UNSUPPORTED_MODES = {
    "IPC_ControlMode": (0, 1, 2), "Y_ControlMode": (0,), "PRC_Mode": (0, 1, 2), "SU_Mode": (0, 1), "SD_Mode": (0, 1),
    "Fl_Mode": (0, 1, 2), "TD_Mode": (0, 1), "TRA_Mode": (0,), "Flp_Mode": (0,), "OL_Mode": (0,), "PA_Mode": (0, 1, 2),
    "PF_Mode": (0,), "AWC_Mode": (0,), "Ext_Mode": (0,), "ZMQ_Mode": (0,), "CC_Mode": (0,), "StC_Mode": (0,),
    "VS_FBP": (0,), "VS_ControlMode": (1, 2, 3), "WE_Mode": (0, 2), "PC_ControlMode": (1,),
}


def _tuple(values) -> tuple[float, ...]:
    return tuple(float(v) for v in np.asarray(values, dtype=float).reshape(-1))


@dataclass(frozen=True)
class BaselineSettings:
    """Every setting of the baseline controller (SI units: rad, rad/s, N m, W, m, kg m², s).

    Speeds named ``*_generator_speed``/``pitch_reference_speed`` are on the generator
    (high-speed) shaft.  The pitch gain schedule ``schedule_kp`` [s], ``schedule_ki``
    [-] is indexed by the filtered pitch ``schedule_pitch`` [rad]; ``torque_kp``
    [N m s/rad], ``torque_ki`` [N m/rad] are the torque PI gains.  The wind-speed
    estimator (``wind_estimator = 2``, ROSCO's EKF) needs the rotor's power
    coefficient table ``cp`` (rows: ``cp_tsr``, columns: ``cp_pitch`` [rad]) and the
    first-order poles ``estimator_poles`` [1/s] over ``estimator_wind_speeds`` [m/s].

    Individual pitch control (:mod:`~mbsym.wind.control.ipc`, off with ``ipc_mode = 0``):
    ``ipc_mode`` 1 (1P) or 2 (1P + 2P); per harmonic the PI gains ``ipc_kp``
    [rad/(N m)], ``ipc_ki`` [rad/(N m s)] and the azimuth offsets ``ipc_azimuth_offset``
    [rad]; the gains ramp in between the wind speeds ``ipc_wind_ramp`` [m/s]; the
    integrator limit ``ipc_integrator_limit`` [rad]; ``ipc_saturation_mode`` 0-3
    (ROSCO's ``IPC_SatMode``); the corner frequency of the low-pass filter on the IPC
    commands ``ipc_actuator_corner`` [rad/s] (0: none).

    Generator-speed notch filters (ROSCO's ``F_GenSpdNotch_Ind``, after the speed low-pass): natural frequencies
    ``speed_notch_freqs`` [rad/s] and numerator/denominator damping ``speed_notch_beta_num``,
    ``speed_notch_beta_den`` [-] (empty: none). Tower fore-aft damper (``tower_damper_mode = 1``, ROSCO's
    ``TD_Mode``): the nacelle's fore-aft acceleration, high-pass filtered at ``tower_damper_highpass_corner``
    [rad/s], integrated with the gain ``tower_damper_ki`` [rad s/m] and limited to ±``tower_damper_limit``
    [rad], is added to the collective pitch. Power reference (``power_reference_mode``, ROSCO's ``PRC_Mode``;
    :mod:`~mbsym.wind.control.power_reference`): 1, the generator-speed set-points from the wind-speed estimate
    low-pass filtered at ``power_reference_filter_corner`` [rad/s] through the table
    ``power_reference_wind_speeds`` [m/s] → ``power_reference_generator_speeds`` [rad/s]; 2, the constant
    ratings ``power_rating_speed``, ``power_rating_torque``, ``power_rating_pitch`` [-] scale the speed
    set-points, the torque limit and the smoother's rated power, and the minimum pitch (with peak shaving) is
    at least ``power_rating_min_pitch`` [rad] at ``power_rating_pitch`` in ``power_rating_table`` [-].

    Shut-down (``shutdown_mode = 1``, ROSCO's ``SD_Mode``; :mod:`~mbsym.wind.control.shutdown`): from
    ``shutdown_activation_time`` [s] on, the triggers ``shutdown_on_pitch`` (filtered pitch above
    ``shutdown_max_pitch`` [rad], corner ``shutdown_pitch_corner`` [rad/s]), ``shutdown_on_yaw_error`` (filtered
    yaw error above ``shutdown_max_yaw_error`` [rad], ``shutdown_yaw_error_corner`` [rad/s]),
    ``shutdown_on_generator_speed`` (filtered speed above ``shutdown_max_generator_speed`` [rad/s],
    ``shutdown_generator_speed_corner`` [rad/s]) and ``shutdown_on_time`` (after ``shutdown_time`` [s]) latch it;
    then the pitch rises at ``shutdown_pitch_rates`` [rad/s] and the torque falls at ``shutdown_torque_rates``
    [N m/s], one per stage, the stages timed (``shutdown_method`` 1, ``shutdown_stage_times`` [s]) or by pitch
    (2, ``shutdown_stage_pitch`` [rad]). Start-up (``startup_mode = 1``, ROSCO's ``SU_Mode``;
    :mod:`~mbsym.wind.control.startup`): pitch held until ``startup_time`` [s], free-wheeling without torque at
    the rotor speed ``startup_rotor_speed`` [rad/s] (filter corner ``startup_rotor_speed_corner`` [rad/s]) for at
    least ``startup_freewheel_duration`` [s], then the torque rating ramps to ``startup_loads`` [-] in
    ``startup_ramp_durations`` [s] and holds for ``startup_hold_durations`` [s], stage by stage.
    """

    dt: float
    speed_filter_corner: float
    speed_filter_order: int = 1
    speed_filter_damping: float = 0.0
    torque_mode: int = 2
    constant_power: bool = True
    setpoint_smoothing: bool = True
    wind_estimator: int = 2
    peak_shaving: bool = True
    smoother_corner: float = 0.6283
    estimate_filter_corner: float = 0.20944
    reference_filter_corner: float = 0.20944
    schedule_pitch: tuple[float, ...] = ()
    schedule_kp: tuple[float, ...] = ()
    schedule_ki: tuple[float, ...] = ()
    pitch_max: float = math.pi / 2
    pitch_min: float = 0.0
    pitch_rate_max: float = 0.1745
    pitch_rate_min: float = -0.1745
    pitch_reference_speed: float = 0.0
    fine_pitch: float = 0.0
    region3_pitch_margin: float = 0.01745
    generator_efficiency: float = 1.0
    region25_torque_max: float = 0.0
    torque_rate_max: float = 0.0
    torque_max: float = 0.0
    torque_min: float = 0.0
    min_generator_speed: float = 0.0
    region2_gain: float = 0.0
    rated_power: float = 0.0
    rated_torque: float = 0.0
    rated_generator_speed: float = 0.0
    torque_kp: float = 0.0
    torque_ki: float = 0.0
    optimal_tsr: float = 0.0
    smoother_torque_gain: float = 1.0
    smoother_power_gain: float = 0.0
    rotor_radius: float = 0.0
    gearbox_ratio: float = 1.0
    drivetrain_inertia: float = 0.0
    air_density: float = 1.225
    estimator_wind_speeds: tuple[float, ...] = ()
    estimator_poles: tuple[float, ...] = ()
    min_pitch_wind_speeds: tuple[float, ...] = ()
    min_pitch_schedule: tuple[float, ...] = ()
    cp_tsr: tuple[float, ...] = ()
    cp_pitch: tuple[float, ...] = ()
    cp: tuple[tuple[float, ...], ...] = ()
    ipc_mode: int = 0
    ipc_saturation_mode: int = 0
    ipc_wind_ramp: tuple[float, ...] = ()
    ipc_integrator_limit: float = 0.0
    ipc_kp: tuple[float, ...] = ()
    ipc_ki: tuple[float, ...] = ()
    ipc_azimuth_offset: tuple[float, ...] = ()
    ipc_actuator_corner: float = 0.0
    floating_mode: int = 0
    floating_kp: tuple[float, ...] = ()
    floating_wind_speeds: tuple[float, ...] = ()
    floating_filter_corner: float = 0.0
    floating_filter_damping: float = 0.0
    floating_highpass_corner: float = 0.0
    tower_notch_freqs: tuple[float, ...] = ()
    tower_notch_beta_num: tuple[float, ...] = ()
    tower_notch_beta_den: tuple[float, ...] = ()
    actuator_mode: int = 0
    actuator_corner: float = 0.0
    actuator_damping: float = 0.0
    speed_notch_freqs: tuple[float, ...] = ()
    speed_notch_beta_num: tuple[float, ...] = ()
    speed_notch_beta_den: tuple[float, ...] = ()
    tower_damper_mode: int = 0
    tower_damper_ki: float = 0.0
    tower_damper_highpass_corner: float = 0.0
    tower_damper_limit: float = 0.0
    power_reference_mode: int = 0
    power_reference_filter_corner: float = 0.0
    power_reference_wind_speeds: tuple[float, ...] = ()
    power_reference_generator_speeds: tuple[float, ...] = ()
    power_rating_speed: float = 1.0
    power_rating_torque: float = 1.0
    power_rating_pitch: float = 1.0
    power_rating_table: tuple[float, ...] = ()
    power_rating_min_pitch: tuple[float, ...] = ()
    shutdown_mode: int = 0
    shutdown_activation_time: float = 0.0
    shutdown_on_pitch: bool = False
    shutdown_on_yaw_error: bool = False
    shutdown_on_generator_speed: bool = False
    shutdown_on_time: bool = False
    shutdown_max_pitch: float = 0.0
    shutdown_pitch_corner: float = 0.0
    shutdown_max_yaw_error: float = 0.0
    shutdown_yaw_error_corner: float = 0.0
    shutdown_max_generator_speed: float = 0.0
    shutdown_generator_speed_corner: float = 0.0
    shutdown_time: float = 0.0
    shutdown_method: int = 1
    shutdown_stage_times: tuple[float, ...] = ()
    shutdown_stage_pitch: tuple[float, ...] = ()
    shutdown_torque_rates: tuple[float, ...] = ()
    shutdown_pitch_rates: tuple[float, ...] = ()
    startup_mode: int = 0
    startup_time: float = 0.0
    startup_freewheel_duration: float = 0.0
    startup_rotor_speed: float = 0.0
    startup_rotor_speed_corner: float = 0.0
    startup_loads: tuple[float, ...] = ()
    startup_ramp_durations: tuple[float, ...] = ()
    startup_hold_durations: tuple[float, ...] = ()
    source: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        problems = []
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "cp":
                value = tuple(_tuple(row) for row in value)
                object.__setattr__(self, "cp", value)
            elif f.type.startswith("tuple"):
                object.__setattr__(self, f.name, _tuple(value))
            elif f.type == "float":
                if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(float(value)):
                    problems.append(f"{f.name} must be a finite number; got {value!r}")
                else:
                    object.__setattr__(self, f.name, float(value))
        if problems:
            raise ParameterError("BaselineSettings: " + "; ".join(problems) + ".")
        self._validate()

    def _validate(self) -> None:
        p = []
        if not self.dt > 0:
            p.append(f"dt must be > 0 [s]; got {self.dt}")
        if self.speed_filter_order not in (1, 2):
            p.append(f"speed_filter_order must be 1 or 2; got {self.speed_filter_order}")
        if self.torque_mode not in (1, 2, 3):
            p.append(f"torque_mode must be 1 (k·ω² with PI transitions), 2 (TSR tracking) or 3 (power-based TSR "
                     f"tracking); got {self.torque_mode}")
        if self.torque_mode == 3 and not self.region2_gain > 0:
            p.append(f"torque_mode 3 needs region2_gain (VS_Rgn2K) > 0; got {self.region2_gain}")
        if self.wind_estimator not in (0, 2):
            p.append(f"wind_estimator must be 0 (filtered hub wind) or 2 (EKF); got {self.wind_estimator}")
        n = len(self.schedule_pitch)
        if n < 1 or len(self.schedule_kp) != n or len(self.schedule_ki) != n:
            p.append("schedule_pitch, schedule_kp and schedule_ki must have the same length >= 1")
        if n > 1 and np.any(np.diff(self.schedule_pitch) <= 0):
            p.append("schedule_pitch must strictly increase")
        if self.peak_shaving and (len(self.min_pitch_wind_speeds) < 1 or
                                  len(self.min_pitch_wind_speeds) != len(self.min_pitch_schedule)):
            p.append("peak shaving needs min_pitch_wind_speeds and min_pitch_schedule of equal length >= 1")
        if self.wind_estimator == 2:
            if len(self.estimator_wind_speeds) < 1 or len(self.estimator_wind_speeds) != len(self.estimator_poles):
                p.append("the EKF needs estimator_wind_speeds and estimator_poles of equal length >= 1")
            shape = np.shape(self.cp)
            if shape != (len(self.cp_tsr), len(self.cp_pitch)) or min(shape + (2,)) < 2:
                p.append(f"the EKF needs a cp table of shape (len(cp_tsr), len(cp_pitch)) >= (2, 2); got {shape}")
            for name in ("rotor_radius", "drivetrain_inertia", "air_density"):
                if not getattr(self, name) > 0:
                    p.append(f"{name} must be > 0 for the EKF")
        if not 0 < self.generator_efficiency <= 1:
            p.append(f"generator_efficiency must be in (0, 1]; got {self.generator_efficiency}")
        if not (self.pitch_rate_min < 0 < self.pitch_rate_max and self.torque_rate_max > 0):
            p.append("pitch_rate_min < 0 < pitch_rate_max and torque_rate_max > 0 are required")
        for name in ("speed_filter_corner", "estimate_filter_corner", "pitch_reference_speed", "rated_power",
                     "rated_generator_speed", "gearbox_ratio"):
            if not getattr(self, name) > 0:
                p.append(f"{name} must be > 0; got {getattr(self, name)}")
        p += self._ipc_problems()
        p += self._floating_problems()
        p += self._mode_problems()
        if p:
            raise ParameterError("BaselineSettings: " + "; ".join(p) + ".")

    def _ipc_problems(self) -> list[str]:
        if self.ipc_mode == 0:
            return []
        if self.ipc_mode not in (1, 2):
            return [f"ipc_mode must be 0 (off), 1 (1P) or 2 (1P + 2P); got {self.ipc_mode}"]
        p = []
        if self.ipc_saturation_mode not in (0, 1, 2, 3):
            p.append(f"ipc_saturation_mode must be 0, 1, 2 or 3 (ROSCO's IPC_SatMode); got {self.ipc_saturation_mode}")
        for name in ("ipc_wind_ramp", "ipc_kp", "ipc_ki", "ipc_azimuth_offset"):
            if len(getattr(self, name)) != 2:
                p.append(f"{name} must have 2 entries; got {getattr(self, name)}")
        if len(self.ipc_wind_ramp) == 2 and not self.ipc_wind_ramp[0] < self.ipc_wind_ramp[1]:
            p.append(f"ipc_wind_ramp must be (start, end) with start < end [m/s] (the gain ramp is undefined "
                     f"otherwise); got {self.ipc_wind_ramp}")
        if any(k < 0 for k in self.ipc_ki):
            p.append(f"ipc_ki must be >= 0; got {self.ipc_ki}")
        if not self.ipc_integrator_limit >= 0:
            p.append(f"ipc_integrator_limit must be >= 0 [rad]; got {self.ipc_integrator_limit}")
        if not self.ipc_actuator_corner >= 0:
            p.append(f"ipc_actuator_corner must be >= 0 [rad/s] (0: no filter); got {self.ipc_actuator_corner}")
        return p

    def _floating_problems(self) -> list[str]:
        p = []
        if self.floating_mode not in (0, 1, 2):
            p.append(f"floating_mode must be 0 (off), 1 (translational feedback) or 2 (rotational feedback), as "
                     f"ROSCO's Fl_Mode; got {self.floating_mode}")
        if self.floating_mode:
            n = len(self.floating_kp)
            if n < 1 or len(self.floating_wind_speeds) != n:
                p.append("floating_kp and floating_wind_speeds must have the same length >= 1")
            if not (self.floating_filter_corner > 0 and self.floating_filter_damping > 0
                    and self.floating_highpass_corner > 0):
                p.append("the floating feedback needs floating_filter_corner, floating_filter_damping and "
                         "floating_highpass_corner > 0")
            if not len(self.tower_notch_freqs) == len(self.tower_notch_beta_num) == len(self.tower_notch_beta_den):
                p.append("tower_notch_freqs, tower_notch_beta_num and tower_notch_beta_den must have the same length")
        if self.actuator_mode not in (0, 1, 2):
            p.append(f"actuator_mode must be 0 (none), 1 or 2 (first- or second-order filter, ROSCO's PA_Mode); "
                     f"got {self.actuator_mode}")
        elif self.actuator_mode and not (self.actuator_corner > 0 and (self.actuator_mode == 1 or
                                                                       self.actuator_damping > 0)):
            p.append("the pitch actuator model needs actuator_corner > 0 (and actuator_damping > 0 with mode 2)")
        return p

    def _mode_problems(self) -> list[str]:
        """The notch filters, the tower damper and the power reference (ROSCO's checks and ours)."""
        from .power_reference import power_reference_problems

        p = []
        notches = (self.speed_notch_freqs, self.speed_notch_beta_num, self.speed_notch_beta_den)
        if len({len(v) for v in notches}) != 1:
            p.append("speed_notch_freqs, speed_notch_beta_num and speed_notch_beta_den must have the same length")
        if any(w <= 0 for w in self.speed_notch_freqs) or any(b <= 0 for b in self.speed_notch_beta_den):
            p.append("speed_notch_freqs and speed_notch_beta_den must be > 0 (as ROSCO requires)")
        if self.tower_damper_mode not in (0, 1):
            p.append(f"tower_damper_mode must be 0 (off) or 1 (ROSCO's TD_Mode); got {self.tower_damper_mode}")
        elif self.tower_damper_mode and not (self.tower_damper_highpass_corner > 0 and self.tower_damper_limit >= 0):
            p.append("the tower damper needs tower_damper_highpass_corner > 0 [rad/s] and tower_damper_limit >= 0 "
                     "[rad]")
        from .shutdown import shutdown_problems
        from .startup import startup_problems

        return p + power_reference_problems(self) + shutdown_problems(self) + startup_problems(self)

    def replace(self, **changes) -> BaselineSettings:
        """A copy with some settings changed (validated again)."""
        return replace(self, **changes)

    @classmethod
    def from_discon(cls, discon, *, dt: float, performance=None) -> BaselineSettings:
        """Settings from a ROSCO ``DISCON.IN`` (path or :class:`~mbsym.wind.deck.discon_in.DisconInput`).

        Parameters
        ----------
        discon : str, Path or DisconInput
            The controller input file.
        dt : float
            Controller time step [s] (ServoDyn's ``DLL_DT``).
        performance : PerformanceTable, str or Path, optional
            The rotor performance table for the EKF; default: ``PerfFileName`` of the file.

        Raises
        ------
        OpenFASTFormatError
            A malformed ``DISCON.IN`` or performance table (file, line, key).
        ControllerError
            A mode the baseline does not implement (file, line, key and the supported values).
        """
        from ..deck.discon_in import DisconInput, read_discon_in
        from ..deck.performance import PerformanceTable, read_performance_table

        d = discon if isinstance(discon, DisconInput) else read_discon_in(discon)
        bad = [f"{d.where(k)}: {k} = {d[k]} is not supported by the baseline controller (supported: "
               f"{', '.join(map(str, ok))})" for k, ok in UNSUPPORTED_MODES.items() if int(d[k]) not in ok]
        if bad:
            raise ControllerError("; ".join(bad) + ". Use DisconController with the DISCON library for these "
                                  "features, or set the modes to a supported value.")
        values = {attr: d[key] for key, attr in DISCON_MAP.items()}
        values["generator_efficiency"] = d["VS_GenEff"] / 100.0
        values["torque_kp"], values["torque_ki"] = float(d["VS_KP"][0]), float(d["VS_KI"][0])
        values["constant_power"] = bool(d["VS_ConstPower"])
        values["setpoint_smoothing"] = bool(d["SS_Mode"])
        values["peak_shaving"] = bool(d["PS_Mode"])
        if d["IPC_ControlMode"] > 0:
            _check_ipc(d)
            values.update({attr: d[key] for key, attr in IPC_MAP.items()})
        if d["Fl_Mode"] > 0:
            values.update(_floating(d))
        if d["PA_Mode"] > 0:
            values.update({attr: d[key] for key, attr in ACTUATOR_MAP.items()})
        if int(d["F_GenSpdNotch_N"]) > 0:
            values.update(zip(("speed_notch_freqs", "speed_notch_beta_num", "speed_notch_beta_den"),
                              _notches(d, "F_GenSpdNotch")))
        if d["TD_Mode"] > 0:
            values.update({attr: d[key] for key, attr in TOWER_DAMPER_MAP.items()})
        if d["PRC_Mode"] > 0:
            from .power_reference import power_reference_values

            values.update(power_reference_values(d))
        if d["SD_Mode"] > 0:
            from .shutdown import shutdown_values

            values.update(shutdown_values(d))
        if d["SU_Mode"] > 0:
            from .startup import startup_values

            values.update(startup_values(d))
        if d["WE_Mode"] == 2:
            table = performance if isinstance(performance, PerformanceTable) else \
                read_performance_table(performance if performance is not None else _performance_path(d))
            values.update(cp_tsr=table.tsr, cp_pitch=table.pitch, cp=table.cp)
        try:
            return cls(dt=dt, **values, source=str(d.path))
        except ParameterError as exc:
            raise ControllerError(f"{d.path}: {exc}") from None


def _floating(d) -> dict:
    """The floating-feedback settings of a DISCON.IN (Fl_Mode > 0), with the tower-top notch filters."""
    out = {attr: d[key] for key, attr in FLOATING_MAP.items()}
    n = int(d["Fl_n"]) if "Fl_n" in d.values else 1
    out["floating_kp"] = tuple(np.atleast_1d(d["Fl_Kp"]).astype(float))[:n]
    out["floating_wind_speeds"] = tuple(np.atleast_1d(d["Fl_U"]).astype(float))[:n]
    corner = np.atleast_1d(d["F_FlCornerFreq"]).astype(float)
    if corner.size != 2:
        raise ControllerError(f"{d.where('F_FlCornerFreq')}: expected two values (natural frequency [rad/s] and "
                              f"damping [-]); got {corner.tolist()}.")
    out["floating_filter_corner"], out["floating_filter_damping"] = float(corner[0]), float(corner[1])
    out["tower_notch_freqs"], out["tower_notch_beta_num"], out["tower_notch_beta_den"] = _notches(d, "F_TwrTopNotch")
    return out


def _notches(d, prefix: str) -> tuple[tuple[float, ...], ...]:
    """(frequencies [rad/s], numerator and denominator damping [-]) of the notch filters ``<prefix>_Ind`` names
    among ``F_NotchFreqs``, ``F_NotchBetaNum``, ``F_NotchBetaDen`` (1-based, in ROSCO's order of application)."""
    count = int(d[f"{prefix}_N"]) if f"{prefix}_N" in d.values else 0
    index = [int(i) for i in np.atleast_1d(d[f"{prefix}_Ind"])[:count]] if count else []
    freqs, num, den = (np.atleast_1d(d[k]).astype(float) for k in ("F_NotchFreqs", "F_NotchBetaNum",
                                                                    "F_NotchBetaDen"))
    bad = [i for i in index if not 1 <= i <= min(freqs.size, num.size, den.size)]
    if bad:
        raise ControllerError(f"{d.where(f'{prefix}_Ind')}: notch indices {bad} outside 1..{freqs.size} "
                              "(F_NotchFreqs). Fix the indices or F_NumNotchFilts.")
    return tuple(tuple(v[i - 1] for i in index) for v in (freqs, num, den))


def _check_ipc(d) -> None:
    """Refuse, with file, line and key, IPC values the baseline does not model."""
    bad = []
    ramp = d["IPC_Vramp"]
    if not ramp[0] < ramp[1]:
        bad.append(f"{d.where('IPC_Vramp')}: the gain ramp needs start < end [m/s]; got {ramp[0]:g} {ramp[1]:g}. "
                   "Give two increasing wind speeds")
    if not d["IPC_IntSat"] >= 0:
        bad.append(f"{d.where('IPC_IntSat')}: must be >= 0 [rad] (a pitch amplitude); got {d['IPC_IntSat']:g}")
    if bad:
        raise ControllerError("; ".join(bad) + ".")


def _performance_path(d) -> Path:
    path = d.performance_file
    if path is None or not path.is_file():
        raise OpenFASTFormatError(f"{d.where('PerfFileName')}: performance table not found: tried "
                                  f"'{path}'. Fix PerfFileName (relative to the DISCON.IN).")
    return path
