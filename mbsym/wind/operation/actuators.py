"""Collective pitch actuator, generator torque actuator and generator efficiency.

Both actuators turn a controller's demand into the value the structure sees:

* **pitch** (second order, natural frequency ``ω`` [rad/s], damping ratio ``ζ``, position
  limits ``[β_min, β_max]`` [rad], rate limits ``[β̇_min, β̇_max]`` [rad/s])::

      v* = clip( ω / (2ζ) · (clip(β_c, β_min, β_max) − β),  β̇_min, β̇_max )
      β̈  = 2ζω · (v* − β̇)

  Inside the limits this is exactly ``β̈ = ω² (β_c − β) − 2ζω β̇``. With the rate demand
  clipped, ``β̇`` approaches the rate limit as a first-order lag (time constant
  ``1/(2ζω)``) and never passes it (by more than the saturation's ``δ``, below): the rate
  interval is invariant. The position limit acts on the demand, so the pitch stays within
  its limits up to the overshoot of the second-order response (none for ``ζ >= 1``; 4.6 % of
  the last move for ``ζ = 0.7``).

* **generator torque** (first-order lag ``τ`` [s], torque limits ``[T_min, T_max]`` and rate
  limit ``|Ṫ| <= Ṫ_max`` [N m, N m/s], high-speed shaft)::

      Ṫ = clip( (clip(T_c, T_min, T_max) − T) / τ,  −Ṫ_max, Ṫ_max )

  The torque never leaves ``[T_min, T_max]`` or exceeds the rate limit (by more than ``δ``).

* **electrical power** ``GenPwr = η · T · ω_gen`` with the generator efficiency ``η``.

**Saturation.** ``clip`` is :func:`smooth_clip`: exactly the identity on the allowed interval
(a demand at a limit passes unchanged: fine pitch in region 2 is exact, and steady states at a limit
are exact equilibria), a quadratic blend over ``2δ`` beyond each limit (continuous first
derivative, second derivative ``1/(2δ)`` in the blend), and constant beyond the blend at the limit
``± δ``. ``δ`` is ``saturation_width`` (default 1e-4) times the width of the interval (for a rate
interval ``[−r, r]``: ``2r``): the limits hold to ``δ`` (1.6e-4 rad = 0.009° for the NREL 5 MW
pitch range, 3.5e-5 rad/s on its pitch rate, 8 N m/s on its torque rate). Fixed-step RK4 and the
adaptive integrators need no event handling at the switches. For optimization the same limits
are :meth:`ActuatorSettings.bounds` (position and rate constraints on the states and their
derivatives), which an NMPC imposes as constraints instead of relying on the saturation.

Numbers and their sources: :class:`ActuatorSettings` (``sources`` names the origin of
every value; :meth:`ActuatorSettings.from_deck` reads them from ServoDyn and ROSCO's
``DISCON.IN``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from types import MappingProxyType
from typing import Any, Mapping

import casadi as ca

from ...exceptions import ParameterError

__all__ = ["ActuatorSettings", "smooth_clip", "pitch_actuator_rhs", "torque_actuator_rhs", "ACTUATOR_PARAMETERS",
           "DEFAULT_PITCH_FREQUENCY", "DEFAULT_PITCH_DAMPING", "DEFAULT_TORQUE_TIME_CONSTANT"]

#: Default pitch-actuator natural frequency [rad/s] (invented, see :class:`ActuatorSettings`).
DEFAULT_PITCH_FREQUENCY = 50.0
#: Default pitch-actuator damping ratio [-] (invented, see :class:`ActuatorSettings`).
DEFAULT_PITCH_DAMPING = 0.7
#: Default generator-torque time constant [s] (invented, see :class:`ActuatorSettings`).
DEFAULT_TORQUE_TIME_CONSTANT = 0.01

#: Model parameter name -> (ActuatorSettings attribute, unit): the actuator parameters of an
#: operating turbine's Dynamics.
ACTUATOR_PARAMETERS = {
    "pitch_frequency": ("pitch_frequency", "rad/s"), "pitch_damping": ("pitch_damping", "-"),
    "pitch_min": ("pitch_min", "rad"), "pitch_max": ("pitch_max", "rad"),
    "pitch_rate_min": ("pitch_rate_min", "rad/s"), "pitch_rate_max": ("pitch_rate_max", "rad/s"),
    "torque_time_constant": ("torque_time_constant", "s"), "torque_min": ("torque_min", "N m"),
    "torque_max": ("torque_max", "N m"), "torque_rate_max": ("torque_rate_max", "N m/s"),
    "generator_efficiency": ("generator_efficiency", "-"),
}

_INVENTED = {
    "pitch_frequency": "invented: the reference (ElastoDyn without PitchDOF, ROSCO PA_Mode 0) pitches ideally; "
                       "20 rad/s is 33x the pitch loop's 0.6 rad/s (NREL/TP-500-38060 sec. 7.3) and 10x the first "
                       "tower mode, a lag 2*zeta/omega = 0.07 s",
    "pitch_damping": "invented: 0.7 (near-critical, the usual choice)",
    "torque_time_constant": "invented: ServoDyn applies the torque demand at once; 0.02 s (a converter's current "
                            "loop) keeps the lag below the 0.05 s output spacing",
}


def smooth_clip(x: Any, lo: Any, hi: Any, width: float = 1e-4) -> Any:
    """``x`` limited to ``[lo - δ, hi + δ]``, the identity on ``[lo, hi]``, with C¹ quadratic blends outside.

    Parameters
    ----------
    x, lo, hi : SX, MX or float
        Value and limits (``lo < hi``).
    width : float, optional
        ``δ`` as a fraction of ``hi - lo``.

    Returns
    -------
    Same type as ``x``: ``x`` on ``[lo, hi]``; ``x + (x - lo)² / (4δ)`` on ``[lo - 2δ, lo]`` and
    ``lo - δ`` below; symmetrically at ``hi``; ``δ = width (hi - lo)``.

    Examples
    --------
    >>> float(smooth_clip(0.5, 0.0, 1.0)), float(smooth_clip(0.0, 0.0, 1.0)), float(smooth_clip(-1.0, 0.0, 1.0))
    (0.5, 0.0, -0.0001)
    """
    d = width * (hi - lo)
    a = lo - x                             # depth below the lower limit
    b = x - hi                             # height above the upper limit
    low = ca.if_else(a <= 0, x, ca.if_else(a < 2 * d, x + a * a / (4 * d), lo - d))
    return ca.if_else(b <= 0, low, ca.if_else(b < 2 * d, x - b * b / (4 * d), hi + d))


def pitch_actuator_rhs(beta: Any, beta_d: Any, command: Any, p: Mapping[str, Any], width: float = 1e-4) -> Any:
    """``β̈`` of the pitch actuator (module docstring) for state ``(β, β̇)`` [rad, rad/s] and demand [rad]."""
    w, z = p["pitch_frequency"], p["pitch_damping"]
    target = smooth_clip(command, p["pitch_min"], p["pitch_max"], width)
    rate = smooth_clip(w / (2 * z) * (target - beta), p["pitch_rate_min"], p["pitch_rate_max"], width)
    return 2 * z * w * (rate - beta_d)


def torque_actuator_rhs(torque: Any, command: Any, p: Mapping[str, Any], width: float = 1e-4) -> Any:
    """``Ṫ`` of the generator-torque actuator (module docstring) for state ``T`` and demand [N m]."""
    target = smooth_clip(command, p["torque_min"], p["torque_max"], width)
    r = p["torque_rate_max"]
    return smooth_clip((target - torque) / p["torque_time_constant"], -r, r, width)


def _positive(name: str, value: float) -> str | None:
    return None if value > 0 else f"{name} must be > 0; got {value:g}"


@dataclass(frozen=True)
class ActuatorSettings:
    """Actuator and generator numbers (SI: rad, rad/s, N m on the high-speed shaft, s).

    Attributes
    ----------
    pitch_frequency, pitch_damping : float
        Natural frequency [rad/s] and damping ratio of the pitch actuator.
    pitch_min, pitch_max : float
        Pitch position limits [rad].
    pitch_rate_min, pitch_rate_max : float
        Pitch rate limits [rad/s] (``pitch_rate_min < 0 < pitch_rate_max``).
    torque_time_constant : float
        Generator-torque lag [s].
    torque_min, torque_max : float
        Generator torque limits [N m] (high-speed shaft).
    torque_rate_max : float
        Generator torque rate limit [N m/s].
    generator_efficiency : float
        Electrical over mechanical power, in (0, 1].
    sources : mapping
        Where each value comes from (attribute -> text).

    Defaults without a deck (:meth:`nrel5mw`): ServoDyn's GenEff and ROSCO's NREL 5 MW
    ``DISCON.IN`` limits; the dynamics (natural frequency, damping, torque lag) are
    invented, because OpenFAST's ElastoDyn without PitchDOF and ServoDyn apply the demands
    at once (``_INVENTED`` texts in ``sources`` say why each value was chosen).
    """

    pitch_frequency: float = DEFAULT_PITCH_FREQUENCY
    pitch_damping: float = DEFAULT_PITCH_DAMPING
    pitch_min: float = 0.0
    pitch_max: float = math.pi / 2
    pitch_rate_min: float = -0.1745
    pitch_rate_max: float = 0.1745
    torque_time_constant: float = DEFAULT_TORQUE_TIME_CONSTANT
    torque_min: float = 0.0
    torque_max: float = 47402.91
    torque_rate_max: float = 40000.0
    generator_efficiency: float = 0.944
    sources: Mapping[str, str] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        problems = []
        for f in fields(self):
            if f.name == "sources":
                continue
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                problems.append(f"{f.name} must be a finite number; got {v!r}")
            else:
                object.__setattr__(self, f.name, float(v))
        if not problems:
            for name in ("pitch_frequency", "pitch_damping", "torque_time_constant", "torque_rate_max"):
                problems.append(_positive(name, getattr(self, name)))
            if not self.pitch_min < self.pitch_max:
                problems.append(f"pitch_min ({self.pitch_min:g}) must be < pitch_max ({self.pitch_max:g}) [rad]")
            if not self.pitch_rate_min < 0 < self.pitch_rate_max:
                problems.append(f"pitch_rate_min < 0 < pitch_rate_max is required; got {self.pitch_rate_min:g}, "
                                f"{self.pitch_rate_max:g} [rad/s]")
            if not self.torque_min < self.torque_max:
                problems.append(f"torque_min ({self.torque_min:g}) must be < torque_max ({self.torque_max:g}) [N m]")
            if not 0 < self.generator_efficiency <= 1:
                problems.append(f"generator_efficiency must be in (0, 1]; got {self.generator_efficiency:g}")
        problems = [p for p in problems if p]
        if problems:
            raise ParameterError("ActuatorSettings: " + "; ".join(problems) + ".")
        src = {**{k: v for k, v in _INVENTED.items()}, **dict(self.sources)}
        object.__setattr__(self, "sources", MappingProxyType(src))

    def replace(self, **changes) -> "ActuatorSettings":
        """A copy with some values changed (validated again; ``sources`` say 'given' for them)."""
        sources = {**self.sources, **{k: "given" for k in changes if k != "sources"}}
        return replace(self, **{"sources": sources, **changes})

    def parameters(self) -> dict[str, float]:
        """Values by model parameter name (:data:`ACTUATOR_PARAMETERS`)."""
        return {name: getattr(self, attr) for name, (attr, _) in ACTUATOR_PARAMETERS.items()}

    def bounds(self) -> dict[str, tuple[float, float]]:
        """Limits for optimization: states ``BlPitch`` [rad], ``BlPitch_d`` [rad/s], ``GenTq`` [N m],
        the torque rate ``GenTq_d`` [N m/s] and the demands ``BlPitchCom``, ``GenTqCom``."""
        return {"BlPitch": (self.pitch_min, self.pitch_max), "BlPitch_d": (self.pitch_rate_min, self.pitch_rate_max),
                "GenTq": (self.torque_min, self.torque_max), "GenTq_d": (-self.torque_rate_max, self.torque_rate_max),
                "BlPitchCom": (self.pitch_min, self.pitch_max), "GenTqCom": (self.torque_min, self.torque_max)}

    @classmethod
    def nrel5mw(cls) -> "ActuatorSettings":
        """The built-in NREL 5 MW: ServoDyn GenEff 94.4 %, ROSCO 2.10.6 NREL 5 MW DISCON.IN limits."""
        rosco = "ROSCO 2.10.6 NREL-5MW DISCON.IN"
        return cls(sources={
            "pitch_min": f"{rosco} PC_MinPit", "pitch_max": f"{rosco} PC_MaxPit",
            "pitch_rate_min": f"{rosco} PC_MinRat", "pitch_rate_max": f"{rosco} PC_MaxRat",
            "torque_min": f"{rosco} VS_MinTq", "torque_max": f"{rosco} VS_MaxTq",
            "torque_rate_max": f"{rosco} VS_MaxRat",
            "generator_efficiency": "NREL 5 MW ServoDyn GenEff (94.4 %)"})

    @classmethod
    def from_deck(cls, servodyn=None, discon=None, **changes) -> "ActuatorSettings":
        """Settings from a ServoDyn file and/or a ROSCO ``DISCON.IN`` (paths or parsed records).

        ServoDyn gives the generator efficiency (``GenEff``). ServoDyn's Bladed-interface
        records ``Ptch_Min``/``Ptch_Max``/``PtchRate_*`` are values *sent* to a DLL, not
        limits of the plant, so the limits come from ``DISCON.IN`` (``PC_MinPit``,
        ``PC_MaxPit``, ``PC_MinRat``, ``PC_MaxRat``, ``VS_MinTq``, ``VS_MaxTq``,
        ``VS_MaxRat``; ``VS_GenEff`` if there is no ServoDyn). ROSCO's own pitch actuator
        (``PA_Mode``, ``PA_CornerFreq``) is part of the controller's command, not of the
        plant: it is not used here. Values missing from both keep the NREL 5 MW defaults
        (named in ``sources``); ``changes`` override any value.
        """
        from ..deck.discon_in import DisconInput, read_discon_in
        from ..deck.servodyn import ServoDynSettings, read_servodyn

        base = cls.nrel5mw()
        values: dict[str, float] = {}
        sources: dict[str, str] = dict(base.sources)
        if discon is not None:
            d = discon if isinstance(discon, DisconInput) else read_discon_in(discon)
            for attr, key in (("pitch_min", "PC_MinPit"), ("pitch_max", "PC_MaxPit"), ("pitch_rate_min", "PC_MinRat"),
                              ("pitch_rate_max", "PC_MaxRat"), ("torque_min", "VS_MinTq"),
                              ("torque_max", "VS_MaxTq"), ("torque_rate_max", "VS_MaxRat")):
                if key in d:
                    values[attr] = float(d[key])
                    sources[attr] = f"{d.where(key)} ({key})"
            if "VS_GenEff" in d:
                values["generator_efficiency"] = float(d["VS_GenEff"]) / 100.0
                sources["generator_efficiency"] = f"{d.where('VS_GenEff')} (VS_GenEff)"
        if servodyn is not None:
            s = servodyn if isinstance(servodyn, ServoDynSettings) else read_servodyn(servodyn)
            values["generator_efficiency"] = float(s.generator_efficiency)
            sources["generator_efficiency"] = f"{s.path}:{s.lines.get('GenEff', '?')} (GenEff)"
        for k in changes:
            sources[k] = "given"
        return cls(**{**values, **changes}, sources=sources)
