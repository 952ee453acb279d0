"""What a ROSCO-type controller settles to at a constant wind: its steady-state laws.

A trim (:mod:`.trim`) replaces the controller's dynamics by the conditions its loops satisfy
once every filter, integrator and estimator has settled. For ROSCO 2.10.6 (the scheme our
:class:`~mbsym.wind.control.BaselineController` reproduces; ROSCO's documentation and source
were read to learn it) these are, with ``ω`` the generator speed [rad/s], ``Ω = ω/N`` the
rotor speed, ``T`` the generator torque command [N m], ``β`` the pitch command [rad] and
``P = η T ω`` the electrical power:

* **Wind-speed estimate** ``Û`` (``WE_Mode`` 1 or 2: the I&I estimator or the EKF): the
  estimator's rotor-speed state stops moving only when the torque its Cp *table* predicts
  balances the generator torque,
  ``½ ρ_WE π R_WE² Û³ / Ω · max(Cp_table(β, Ω R_WE / Û), 0) = N_WE T``,
  so ``Û`` is the hub wind only if the table is the plant's. ROSCO's NREL 5 MW table is
  2–5 % below AeroDyn's Cp (shared OpenFAST README), so its ``Û`` is ~1 % high and region 2
  runs at TSR 7.60 instead of ``VS_TSRopt`` 7.5. ``WE_Mode 0``: ``Û`` is the hub wind.
  Out of the table's pitch range, or with the torque below ``1e-4 VS_RtTq``, ROSCO falls
  back to the filtered hub wind (also here).
* **Minimum pitch** ``β_min(Û)``: ``PC_FinePit``, or with peak shaving (``PS_Mode 1``)
  ``max(PS_BldPitchMin(Û), PC_FinePit)`` (clamped table lookup on the estimate).
* **Set-point smoother** (``SS_Mode 1``): the shift
  ``δ = ((β − β_min)/0.524 · SS_VSGain − (P_rated − P)/P_rated · SS_PCGain) · PC_RefSpd``
  raises the pitch controller's reference by ``−min(δ, 0)`` and lowers the torque
  controller's by ``max(δ, 0)``.
* **Torque reference** (``VS_ControlMode 2``): ``ω_ref = clamp(VS_TSRopt Û N / R,
  VS_MinOMSpd, VS_RefSpd) − max(δ, 0)``, at least ``VS_MinOMSpd``; ``VS_ControlMode 3``:
  ``(P / VS_GenEff / VS_Rgn2K)^(1/3)`` (``P`` the measured electrical power) in place of the TSR term.
* **Torque limits**: ``[VS_MinTq, min(VS_MaxTq, P_rated/(η ω))]`` (``VS_ConstPower 1``) or
  ``[VS_MinTq, min(VS_MaxTq, VS_RtTq)]`` (constant torque).
* **Pitch reference** ``PC_RefSpd − min(δ, 0)`` within ``[β_min, PC_MaxPit]``.
* ``VS_ControlMode 1``: ROSCO's state machine — ``T = VS_Rgn2K ω²`` (region 2), PI loops
  holding ``VS_MinOMSpd`` (1.5, torque up to ``k ω_min²``) or ``VS_RefSpd`` (2.5, torque in
  ``[k ω_rated², VS_ArSatTq]``), and region 3 (constant power or torque) once the pitch
  passes ``β_min + PC_Switch``.

A PI loop at steady state either holds its reference exactly (integral action) or sits on a
limit with the error pushing into it. Each combination is a **regime**
(:class:`Regime`): two equations (one per loop) and the sign conditions that make it the
controller's state. :meth:`SteadyControl.regimes` lists those of this controller.

Modes without a steady effect are accepted (IPC and the tower damper act on periodic or
oscillating signals, floating feedback on platform motion, start-up/shut-down on time,
filters pass constants). Modes that change the steady state and are not modelled
(``PRC_Mode``, ``OL_Mode``, ``VS_FBP``, ``VS_ControlMode`` 0 or 4, ``PF_Mode``) raise a
:class:`~mbsym.exceptions.ControllerError` naming the file, line and key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ControllerError, OpenFASTFormatError, ParameterError
from ..control.settings import DISCON_MAP

__all__ = ["SteadyControl", "Regime", "STEADY_IGNORED_MODES"]

#: DISCON.IN keys whose modes have no effect on a steady state (accepted, listed in ``notes``).
STEADY_IGNORED_MODES = ("IPC_ControlMode", "Y_ControlMode", "SU_Mode", "SD_Mode", "Fl_Mode", "TD_Mode", "TRA_Mode",
                        "Flp_Mode", "PA_Mode", "AWC_Mode", "Ext_Mode", "ZMQ_Mode", "CC_Mode", "StC_Mode")
#: Modes that change the steady state and are not modelled: key -> accepted values.
_REFUSED = {"PRC_Mode": (0,), "OL_Mode": (0,), "VS_FBP": (0,), "PF_Mode": (0,), "VS_ControlMode": (1, 2, 3),
            "PC_ControlMode": (0, 1), "WE_Mode": (0, 1, 2)}
#: DISCON.IN key -> SteadyControl attribute: the baseline controller's names (settings.DISCON_MAP) of the keys
#: a steady state depends on.
_STEADY_KEYS = ("VS_ControlMode", "PC_RefSpd", "PC_FinePit", "PC_MinPit", "PC_MaxPit", "PC_Switch", "VS_ArSatTq",
                "VS_MaxTq", "VS_MinTq", "VS_MinOMSpd", "VS_Rgn2K", "VS_RtPwr", "VS_RtTq", "VS_RefSpd", "VS_TSRopt",
                "SS_VSGain", "SS_PCGain", "WE_BladeRadius", "WE_GearboxRatio", "WE_RhoAir", "WE_Mode",
                "PS_WindSpeeds", "PS_BldPitchMin")
_KEYS = {key: DISCON_MAP[key] for key in _STEADY_KEYS}
#: The set-point smoother's pitch normalization [rad] (ROSCO: "normalize to 30 degrees").
_SMOOTHER_PITCH = 0.524
#: ROSCO's estimator torque floor, as a fraction of VS_RtTq.
_ESTIMATOR_TORQUE_FLOOR = 1e-4


@dataclass(frozen=True)
class Regime:
    """One steady state of the two loops.

    Attributes
    ----------
    name : str
        Short name (``"2"``, ``"3"``, ``"2.5-saturated"`` ...).
    torque : str
        The torque loop's equation: ``"track"`` (speed = torque reference), ``"upper"`` (torque
        at its upper limit), ``"lower"`` (at ``VS_MinTq``), ``"k2"`` (``T = k ω²``),
        ``"hold_min"``/``"hold_rated"`` (PI holding ``VS_MinOMSpd``/``VS_RefSpd``, mode 1),
        ``"arsat"`` (torque at ``VS_ArSatTq``, mode 1).
    pitch : str
        The pitch loop's: ``"min"`` (pitch at ``β_min(Û)``), ``"track"`` (speed = pitch
        reference), ``"max"`` (pitch at ``PC_MaxPit``).
    description : str
    """

    name: str
    torque: str
    pitch: str
    description: str


@dataclass(frozen=True)
class SteadyControl:
    """The settings of a ROSCO-type controller that fix its steady states (SI units).

    Build it with :meth:`from_discon` (a ``DISCON.IN``), :meth:`from_baseline` (a
    :class:`~mbsym.wind.control.BaselineSettings`) or :meth:`nrel5mw` (the built-in NREL 5 MW,
    ROSCO 2.10.6's settings). Speeds named ``*_generator_speed`` and
    ``pitch_reference_speed`` are on the generator (high-speed) shaft [rad/s]; torques on
    the generator shaft [N m]; pitch [rad]; ``rotor_radius``, ``gearbox_ratio``,
    ``air_density`` and the Cp table are the wind-speed estimator's (``WE_*``,
    ``PerfFileName``).
    """

    torque_mode: int = 2
    constant_power: bool = True
    pitch_control: bool = True
    rated_power: float = 5e6
    generator_efficiency: float = 1.0
    gearbox_ratio: float = 1.0
    rated_generator_speed: float = 0.0
    pitch_reference_speed: float = 0.0
    min_generator_speed: float = 0.0
    optimal_tsr: float = 0.0
    region2_gain: float = 0.0
    region25_torque_max: float = 0.0
    rated_torque: float = 0.0
    torque_max: float = 0.0
    torque_min: float = 0.0
    fine_pitch: float = 0.0
    pitch_min: float = 0.0
    pitch_max: float = math.pi / 2
    region3_pitch_margin: float = 0.01745
    setpoint_smoothing: bool = False
    smoother_torque_gain: float = 1.0
    smoother_power_gain: float = 0.0
    peak_shaving: bool = False
    min_pitch_wind_speeds: tuple[float, ...] = ()
    min_pitch_schedule: tuple[float, ...] = ()
    wind_estimator: int = 0
    rotor_radius: float = 0.0
    air_density: float = 1.225
    cp_tsr: tuple[float, ...] = ()
    cp_pitch: tuple[float, ...] = ()
    cp: tuple[tuple[float, ...], ...] = ()
    source: str = field(default="", compare=False)
    notes: tuple[str, ...] = field(default=(), compare=False)

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name == "cp":
                object.__setattr__(self, "cp", tuple(tuple(float(c) for c in row) for row in v))
            elif f.type.startswith("tuple[float"):
                object.__setattr__(self, f.name, tuple(float(c) for c in np.asarray(v, dtype=float).reshape(-1)))
            elif f.type == "float":
                if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or \
                        not math.isfinite(float(v)):
                    raise ParameterError(f"SteadyControl.{f.name} must be a finite number; got {v!r}.")
                object.__setattr__(self, f.name, float(v))
        self._validate()

    def _validate(self) -> None:
        p = []
        if self.torque_mode not in (1, 2, 3):
            p.append(f"torque_mode must be 1 (k·ω²), 2 (TSR tracking) or 3 (power-based TSR tracking); got "
                     f"{self.torque_mode!r}")
        if self.wind_estimator not in (0, 1, 2):
            p.append(f"wind_estimator must be 0, 1 or 2 (ROSCO WE_Mode); got {self.wind_estimator!r}")
        for name in ("rated_power", "rated_generator_speed", "gearbox_ratio"):
            if not getattr(self, name) > 0:
                p.append(f"{name} must be > 0; got {getattr(self, name)}")
        if self.pitch_control and not self.pitch_reference_speed > 0:
            p.append(f"pitch_reference_speed must be > 0 with pitch control; got {self.pitch_reference_speed}")
        if not 0 < self.generator_efficiency <= 1:
            p.append(f"generator_efficiency must be in (0, 1]; got {self.generator_efficiency}")
        if not self.fine_pitch <= self.pitch_max:
            p.append(f"fine_pitch ({self.fine_pitch}) must be <= pitch_max ({self.pitch_max}) [rad]")
        if self.torque_mode == 2 and not (self.optimal_tsr > 0 and self.rotor_radius > 0):
            p.append("TSR tracking needs optimal_tsr > 0 and rotor_radius > 0")
        if self.torque_mode in (1, 3) and not self.region2_gain > 0:
            p.append(f"torque_mode {self.torque_mode} needs region2_gain (VS_Rgn2K) > 0")
        if self.peak_shaving and (len(self.min_pitch_wind_speeds) < 1 or
                                  len(self.min_pitch_wind_speeds) != len(self.min_pitch_schedule)):
            p.append("peak shaving needs min_pitch_wind_speeds and min_pitch_schedule of equal length >= 1")
        if self.peak_shaving and np.any(np.diff(self.min_pitch_wind_speeds) <= 0):
            p.append("min_pitch_wind_speeds must strictly increase")
        if self.wind_estimator in (1, 2):
            shape = np.shape(self.cp)
            if shape != (len(self.cp_tsr), len(self.cp_pitch)) or min(shape + (2,)) < 2:
                p.append(f"the wind-speed estimator needs a cp table of shape (len(cp_tsr), len(cp_pitch)) >= (2, 2); "
                         f"got {shape}")
            if not (self.rotor_radius > 0 and self.air_density > 0):
                p.append("the wind-speed estimator needs rotor_radius > 0 and air_density > 0")
        if p:
            raise ParameterError("SteadyControl: " + "; ".join(p) + ".")

    def replace(self, **changes) -> "SteadyControl":
        """A copy with some settings changed (validated again)."""
        return replace(self, **changes)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_baseline(cls, settings) -> "SteadyControl":
        """The steady laws of a :class:`~mbsym.wind.control.BaselineSettings` (our ROSCO-scheme controller)."""
        from ..control.settings import BaselineSettings

        if not isinstance(settings, BaselineSettings):
            raise TypeError(f"settings must be a BaselineSettings; got {type(settings).__name__}.")
        names = {f.name for f in fields(cls)} - {"source", "notes", "pitch_control"}
        values = {n: getattr(settings, n) for n in names if hasattr(settings, n)}
        return cls(**values, pitch_control=True, source=settings.source or "BaselineSettings")

    @classmethod
    def nrel5mw(cls) -> "SteadyControl":
        """The built-in NREL 5 MW: ROSCO 2.10.6's NREL-5MW ``DISCON.IN`` and its Cp table (package data)."""
        from .nrel5mw import nrel5mw_baseline_settings

        return cls.from_baseline(nrel5mw_baseline_settings())

    @classmethod
    def from_discon(cls, discon, *, performance=None) -> "SteadyControl":
        """Read the steady laws from a ROSCO ``DISCON.IN`` (path or parsed :class:`DisconInput`).

        Parameters
        ----------
        discon : str, Path or DisconInput
        performance : PerformanceTable, str or Path, optional
            The estimator's Cp table; default ``PerfFileName`` (relative to the ``DISCON.IN``).

        Raises
        ------
        OpenFASTFormatError
            A malformed file or a missing performance table (file, line, key).
        ControllerError
            A mode that changes the steady state and is not modelled (file, line, key, the
            accepted values).
        """
        from ..deck.discon_in import DisconInput, read_discon_in
        from ..deck.performance import PerformanceTable, read_performance_table

        d = discon if isinstance(discon, DisconInput) else read_discon_in(discon)
        bad = [f"{d.where(k)} = {d[k]} (accepted: {', '.join(map(str, ok))})"
               for k, ok in _REFUSED.items() if int(d[k]) not in ok]
        if bad:
            raise ControllerError("operating points cannot model these controller modes, which change the steady "
                                  "state: " + "; ".join(bad) + ". Set them to an accepted value, or simulate to "
                                  "steady state with the DISCON library instead.")
        values: dict[str, Any] = {attr: d[key] for key, attr in _KEYS.items()}
        values["generator_efficiency"] = float(d["VS_GenEff"]) / 100.0
        values["constant_power"] = bool(d["VS_ConstPower"])
        values["pitch_control"] = int(d["PC_ControlMode"]) == 1
        values["setpoint_smoothing"] = bool(d["SS_Mode"])
        values["peak_shaving"] = bool(d["PS_Mode"])
        notes = tuple(f"{k} = {d[k]} has no steady-state effect (ignored)" for k in STEADY_IGNORED_MODES
                      if int(d[k]) != 0)
        if int(d["WE_Mode"]) in (1, 2):
            if isinstance(performance, PerformanceTable):
                table = performance
            else:
                path = performance if performance is not None else d.performance_file
                if path is None or not Path(path).is_file():
                    raise OpenFASTFormatError(f"{d.where('PerfFileName')}: performance table not found: tried "
                                              f"'{path}'. Fix PerfFileName (relative to the DISCON.IN).")
                table = read_performance_table(path)
            values.update(cp_tsr=table.tsr, cp_pitch=table.pitch, cp=table.cp)
        try:
            return cls(**values, source=str(d.path), notes=notes)
        except ParameterError as exc:
            raise ControllerError(f"{d.path}: {exc}") from None

    # ------------------------------------------------------------------ laws (numbers or CasADi expressions)
    def min_pitch(self, wind_estimate: Any) -> Any:
        """``β_min(Û)`` [rad]: fine pitch, or the peak-shaving schedule at the estimate (at least fine pitch).

        Without pitch control (``PC_ControlMode 0``: "fix to fine pitch") always the fine pitch.
        """
        if not self.peak_shaving or not self.pitch_control:
            return self.fine_pitch + 0.0 * wind_estimate
        return ca.fmax(self._lookup("ps", self.min_pitch_wind_speeds, self.min_pitch_schedule)(wind_estimate),
                       self.fine_pitch)

    def shift(self, pitch: Any, min_pitch: Any, power: Any) -> Any:
        """Set-point smoother shift ``δ`` [rad/s] (0 without smoothing)."""
        if not self.setpoint_smoothing:
            return 0.0 * pitch
        return ((pitch - min_pitch) / _SMOOTHER_PITCH * self.smoother_torque_gain
                - (self.rated_power - power) / self.rated_power * self.smoother_power_gain) * self.pitch_reference_speed

    def pitch_reference(self, shift: Any) -> Any:
        """Generator speed the pitch loop holds [rad/s]."""
        return self.pitch_reference_speed - ca.fmin(shift, 0.0)

    def torque_reference(self, wind_estimate: Any, power: Any, shift: Any) -> Any:
        """Generator speed the torque loop holds [rad/s] (modes 2, 3; mode 1: ``VS_RefSpd`` less the shift)."""
        if self.torque_mode == 2:
            raw = self.optimal_tsr * wind_estimate / self.rotor_radius * self.gearbox_ratio
        elif self.torque_mode == 3:      # ROSCO: (max(VS_GenPwr, 0) / VS_GenEff / VS_Rgn2K)^(1/3), the measured power
            raw = (ca.fmax(power, 0.0) / self.generator_efficiency / self.region2_gain) ** (1.0 / 3.0)
        else:
            raw = self.rated_generator_speed + 0.0 * wind_estimate
        ref = ca.fmin(ca.fmax(raw, self.min_generator_speed), self.rated_generator_speed)
        return ca.fmax(ref - ca.fmax(shift, 0.0), self.min_generator_speed)

    def torque_upper(self, generator_speed: Any) -> Any:
        """Upper torque limit [N m] in region 3: constant power ``P/(η ω)`` or rated torque, within VS_MaxTq."""
        if self.constant_power:
            return ca.fmin(self.rated_power / self.generator_efficiency / generator_speed, self.torque_max)
        return ca.fmin(self.rated_torque, self.torque_max) + 0.0 * generator_speed

    def estimator_torque(self, wind_estimate: Any, rotor_speed: Any, pitch: Any) -> Any:
        """Rotor torque [N m] the estimator's Cp table predicts (ROSCO's ``AeroDynTorque``)."""
        R = self.rotor_radius
        u = ca.fmax(wind_estimate, 1e-3)
        cp = self._cp_lookup()(rotor_speed * R / u, pitch)
        return 0.5 * self.air_density * math.pi * R**2 * u**3 / rotor_speed * ca.fmax(cp, 0.0)

    def estimator_in_range(self, pitch: float, torque: float) -> bool:
        """Whether the estimator runs (pitch within its table, torque above its floor) or falls back."""
        if self.wind_estimator == 0:
            return False
        lo, hi = self.cp_pitch[0], self.cp_pitch[-1]
        return bool(lo - 1e-12 <= pitch <= hi + 1e-12 and torque >= _ESTIMATOR_TORQUE_FLOOR * self.rated_torque)

    # ------------------------------------------------------------------ regimes
    def regimes(self) -> tuple[Regime, ...]:
        """The candidate steady regimes of this controller, in the order they are tried by default."""
        if self.torque_mode in (2, 3):
            out = [Regime("2", "track", "min", "torque loop holds the speed reference; pitch at its minimum"),
                   Regime("3", "upper", "track", "torque at its region-3 limit; pitch loop holds the speed"),
                   Regime("2.5-saturated", "upper", "min", "torque at its limit, pitch at its minimum; the speed "
                                                           "floats between the two references"),
                   Regime("1", "lower", "min", "torque at VS_MinTq, pitch at its minimum"),
                   Regime("3-max-pitch", "upper", "max", "torque at its limit, pitch at PC_MaxPit")]
        else:
            out = [Regime("2", "k2", "min", "T = k·ω² (VS_Rgn2K); pitch at its minimum"),
                   Regime("1.5", "hold_min", "min", "torque PI holds VS_MinOMSpd; pitch at its minimum"),
                   Regime("2.5", "hold_rated", "min", "torque PI holds VS_RefSpd; pitch at its minimum"),
                   Regime("2.5-saturated", "arsat", "min", "torque at VS_ArSatTq, pitch at its minimum"),
                   Regime("3-transition", "arsat", "track", "torque at VS_ArSatTq below β_min + PC_Switch; pitch "
                                                            "loop holds the speed"),
                   Regime("3", "upper", "track", "region 3 torque; pitch loop holds the speed"),
                   Regime("3-max-pitch", "upper", "max", "region 3 torque, pitch at PC_MaxPit")]
        if not self.pitch_control:
            out = [r for r in out if r.pitch == "min"]
        return tuple(out)

    def torque_equation(self, regime: Regime, *, speed: Any, torque: Any, reference: Any) -> Any:
        """Residual of the torque loop's steady condition, scaled to [rad/s] (speeds) or [N m / rated torque · ω]."""
        t_scale = self.rated_generator_speed / max(self.torque_max, self.rated_torque, 1.0)
        kind = regime.torque
        if kind == "track":
            return speed - reference
        if kind == "upper":
            return (torque - self.torque_upper(speed)) * t_scale
        if kind == "lower":
            return (torque - self.torque_min) * t_scale
        if kind == "k2":
            return (torque - self.region2_gain * speed**2) * t_scale
        if kind == "hold_min":
            return speed - self.min_generator_speed
        if kind == "hold_rated":
            return speed - reference
        if kind == "arsat":
            return (torque - self.region25_torque_max) * t_scale
        raise ParameterError(f"unknown torque regime {kind!r}.")

    def pitch_equation(self, regime: Regime, *, speed: Any, pitch: Any, min_pitch: Any, reference: Any) -> Any:
        """Residual of the pitch loop's steady condition: [rad] (pitch) or [rad/s] (speed) × its scale."""
        kind = regime.pitch
        if kind == "min":
            return (pitch - min_pitch) * self.rated_generator_speed
        if kind == "track":
            return speed - reference
        if kind == "max":
            return (pitch - self.pitch_max) * self.rated_generator_speed
        raise ParameterError(f"unknown pitch regime {kind!r}.")

    def violations(self, regime: Regime, s: dict[str, float], *, tol: float = 1e-6) -> list[str]:
        """Why a solved regime is not this controller's steady state (empty: it is).

        ``s`` holds ``speed`` (generator, rad/s), ``torque`` [N m], ``pitch`` [rad],
        ``min_pitch`` [rad], ``torque_reference``, ``pitch_reference`` [rad/s]. ``tol`` is
        relative (to the rated speed, the torque limit, 1 rad).
        """
        w_tol = tol * self.rated_generator_speed
        t_tol = tol * max(self.torque_max, self.rated_torque, 1.0)
        b_tol = tol
        w, t, b = s["speed"], s["torque"], s["pitch"]
        out = []
        k = regime.torque
        if k == "track":
            upper = float(self.torque_upper(w))
            if t > upper + t_tol:
                out.append(f"torque {t:.6g} N m above its limit {upper:.6g}")
            if t < self.torque_min - t_tol:
                out.append(f"torque {t:.6g} N m below VS_MinTq {self.torque_min:.6g}")
        elif k == "upper":
            if self.torque_mode in (2, 3) and w < s["torque_reference"] - w_tol:
                out.append(f"speed {w:.6g} rad/s below the torque reference {s['torque_reference']:.6g}: the torque "
                           "loop would leave its limit")
            if self.torque_mode == 1 and b < s["min_pitch"] + self.region3_pitch_margin - b_tol:
                out.append("pitch below β_min + PC_Switch: not region 3")
        elif k == "lower":
            if w > s["torque_reference"] + w_tol:
                out.append(f"speed {w:.6g} rad/s above the torque reference: the torque would rise")
        elif k == "k2":
            if w < self.min_generator_speed - w_tol or w > self.rated_generator_speed + w_tol:
                out.append(f"speed {w:.6g} rad/s outside [VS_MinOMSpd, VS_RefSpd]")
        elif k == "hold_min":
            if not self.torque_min - t_tol <= t <= self.region2_gain * self.min_generator_speed**2 + t_tol:
                out.append(f"torque {t:.6g} N m outside [VS_MinTq, k ω_min²]")
        elif k == "hold_rated":
            lo = self.region2_gain * self.rated_generator_speed**2
            if not lo - t_tol <= t <= self.region25_torque_max + t_tol:
                out.append(f"torque {t:.6g} N m outside [k ω_rated², VS_ArSatTq]")
        elif k == "arsat":
            if w < s["torque_reference"] - w_tol:
                out.append("speed below VS_RefSpd: the region-2.5 PI would leave VS_ArSatTq")
        if self.torque_mode == 1 and k in ("k2", "hold_min", "hold_rated", "arsat") and \
                b >= s["min_pitch"] + self.region3_pitch_margin + b_tol:
            out.append("pitch above β_min + PC_Switch: region 3")
        p = regime.pitch if self.pitch_control else "fixed"        # PC_ControlMode 0: pitch fixed at fine pitch
        if p == "min" and w > s["pitch_reference"] + w_tol:
            out.append(f"speed {w:.6g} rad/s above the pitch reference {s['pitch_reference']:.6g}: the pitch would rise")
        if p == "track" and not s["min_pitch"] - b_tol <= b <= self.pitch_max + b_tol:
            out.append(f"pitch {b:.6g} rad outside [β_min {s['min_pitch']:.6g}, PC_MaxPit {self.pitch_max:.6g}]")
        if p == "max" and w < s["pitch_reference"] - w_tol:
            out.append("speed below the pitch reference: the pitch would leave PC_MaxPit")
        return out

    def region(self, regime: Regime, s: dict[str, float], *, tol: float = 1e-6) -> str:
        """The usual region name of a solved regime: ``"1"``, ``"1.5"``, ``"2"``, ``"2.5"``, ``"3"``.

        Region 2 with the speed held at ``VS_RefSpd`` (the reference capped) is ``"2.5"``, at
        ``VS_MinOMSpd`` ``"1.5"``; a regime with the torque at its limit below the pitch loop's
        reference (speed floating) is ``"2.5"``.
        """
        w = s["speed"]
        if regime.pitch in ("track", "max"):
            return "3"
        if not self.pitch_control and regime.torque == "upper" and w >= self.rated_generator_speed * (1 - tol):
            return "3"                      # fixed pitch: torque at its limit, the rotor above rated speed
        if regime.torque in ("track", "k2"):
            if w >= self.rated_generator_speed * (1 - tol):
                return "2.5"
            if w <= self.min_generator_speed * (1 + tol):
                return "1.5"
            return "2"
        return {"hold_min": "1.5", "hold_rated": "2.5", "arsat": "2.5", "upper": "2.5", "lower": "1"}[regime.torque]

    # ------------------------------------------------------------------ lookups
    def _lookup(self, name: str, grid, values):
        cache = self.__dict__.setdefault("_lookups", {})
        if name not in cache:
            grid, values = np.asarray(grid, dtype=float), np.asarray(values, dtype=float)
            if grid.size == 1:
                cache[name] = lambda q: float(values[0]) + 0.0 * q
            else:
                table = ca.interpolant(f"steady_{name}", "linear", [grid], values)
                cache[name] = lambda q: table(ca.fmin(ca.fmax(q, grid[0]), grid[-1]))
        return cache[name]

    def _cp_lookup(self):
        """Clamped bilinear ``(λ, β) -> Cp`` of the estimator's table (ROSCO's ``interp2d``)."""
        cache = self.__dict__.setdefault("_lookups", {})
        if "cp" not in cache:
            tsr, pitch = np.asarray(self.cp_tsr), np.asarray(self.cp_pitch)
            table = ca.interpolant("steady_cp", "linear", [tsr, pitch], np.asarray(self.cp).ravel(order="F"))
            cache["cp"] = lambda lam, beta: table(ca.vertcat(ca.fmin(ca.fmax(lam, tsr[0]), tsr[-1]),
                                                             ca.fmin(ca.fmax(beta, pitch[0]), pitch[-1])))
        return cache["cp"]

    def __repr__(self) -> str:
        mode = {1: "k·ω²", 2: "TSR tracking", 3: "power-based TSR tracking"}[self.torque_mode]
        return (f"SteadyControl({mode}, rated {self.rated_power / 1e6:g} MW at {self.rated_generator_speed:.5g} rad/s "
                f"(generator), {'constant power' if self.constant_power else 'constant torque'}, "
                f"peak shaving {'on' if self.peak_shaving else 'off'}, estimator WE_Mode {self.wind_estimator})")
