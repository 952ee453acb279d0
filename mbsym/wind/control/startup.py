"""The baseline controller's start-up (ROSCO 2.10.6's ``SU_Mode 1``): free-wheeling, then staged torque.

ROSCO's ``Startup`` (ControllerBlocks.f90, called after its power-reference set-points) and the pre-start
branch of its ``PitchControl`` (Controllers.f90) were read for the facts; the code is ours.

Stages (state ``startup_stage``; the time is ROSCO's, the host's clock in single precision, counted here
from the first call at t = 0; ``start``: state ``startup_stage_start`` [s]):

* −1, from the first call until the time passes ``SU_StartTime`` [s]: the pitch controller's limits are
  the mean pitch last commanded (the pitch is held, up to the saturation and rate limits that follow) and
  the torque rating is 0;
* 1, free-wheeling: torque rating 0, speed rating ``SU_RotorSpeedThresh · WE_GearboxRatio / PC_RefSpd``
  (the pitch controller holds the rotor near the threshold speed [rad/s]); ``start`` is the last time the
  rotor speed, low-pass filtered (first order, ``SU_RotorSpeedCornerFreq`` [rad/s]), was below 0.95 × the
  threshold; ``SU_FW_MinDuration`` [s] after ``start`` the load stages begin;
* 2 … N + 1 (load stage ``i = stage − 1`` of ``N = SU_LoadStages_N``): the torque rating rises from the
  previous stage's load (0 before the first) to ``SU_LoadStages(i)`` [-] along ROSCO's cubic ``sigma``
  in ``SU_LoadRampDuration(i)`` [s] and holds for ``SU_LoadHoldDuration(i)`` [s]; in the first the speed
  rating rises from the threshold's to 1 over the same ramp;
* 0 after the last hold: normal operation (the ratings of the power reference, 1 without ``PRC_Mode 2``).

The ratings act as ROSCO's ``PRC_R_Speed``/``PRC_R_Torque`` (:mod:`.power_reference`): the pitch controller's
reference speed and the torque reference's upper limit scale with the speed rating, the torque limit (and
the set-point smoother's rated power) with the torque rating.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ._blocks import lpf1, sigma

__all__ = ["STARTUP_MAP", "startup_values", "startup_problems", "startup_states", "startup_ratings"]

#: DISCON.IN keys of the start-up → BaselineSettings attribute (read when SU_Mode = 1).
STARTUP_MAP = {
    "SU_Mode": "startup_mode", "SU_StartTime": "startup_time", "SU_FW_MinDuration": "startup_freewheel_duration",
    "SU_RotorSpeedThresh": "startup_rotor_speed", "SU_RotorSpeedCornerFreq": "startup_rotor_speed_corner",
    "SU_LoadStages": "startup_loads", "SU_LoadRampDuration": "startup_ramp_durations",
    "SU_LoadHoldDuration": "startup_hold_durations",
}


def startup_values(d) -> dict:
    """The start-up settings of a DISCON.IN with ``SU_Mode 1`` (BaselineSettings attribute → value)."""
    n = int(d["SU_LoadStages_N"])
    out = {attr: d[key] for key, attr in STARTUP_MAP.items() if not key.startswith("SU_Load")}
    for key in ("SU_LoadStages", "SU_LoadRampDuration", "SU_LoadHoldDuration"):
        out[STARTUP_MAP[key]] = tuple(np.atleast_1d(d[key]).astype(float))[:n] if n else ()
    return out


def startup_problems(s) -> list[str]:
    """What is wrong with the start-up settings of ``s`` (ROSCO's checks and ours); [] if nothing."""
    if s.startup_mode == 0:
        return []
    if s.startup_mode != 1:
        return [f"startup_mode must be 0 (off) or 1, as ROSCO's SU_Mode; got {s.startup_mode}"]
    p = []
    n = len(s.startup_loads)
    if n < 1 or len(s.startup_ramp_durations) != n or len(s.startup_hold_durations) != n:
        p.append("startup_loads, startup_ramp_durations and startup_hold_durations must have the same length >= 1 "
                 "(SU_LoadStages_N; ROSCO indexes past the arrays with none)")
    if any(v < 0 for v in s.startup_loads + s.startup_hold_durations):
        p.append("startup_loads and startup_hold_durations must be >= 0 (as ROSCO requires)")
    if any(v <= 0 for v in s.startup_ramp_durations):
        p.append("startup_ramp_durations must be > 0 [s] (ROSCO's cubic ramp divides by them: NaN commands)")
    for name in ("startup_freewheel_duration", "startup_rotor_speed", "startup_rotor_speed_corner"):
        if not getattr(s, name) >= 0:
            p.append(f"{name} must be >= 0 (as ROSCO requires); got {getattr(s, name)}")
    return p


def startup_states(st, s) -> None:
    """Add the start-up's states to the layout ``st`` (a ``_States``)."""
    st.add("startup_stage")
    st.add("startup_stage_start")
    st.add("startup_rotor_filter", 2)


def _pick(index, values: tuple[float, ...], default: float):
    """``values[index − 1]`` for index 1..n (SX), ``default`` otherwise."""
    out = ca.SX(default)
    for i, v in enumerate(values):
        out = ca.if_else(index == i + 1, v, out)
    return out


def startup_ratings(s, dt: float, x: dict, nxt: dict, reset, time, rot_speed, r_speed, r_torque):
    """ROSCO's ``Startup`` at one call → (speed rating, torque rating [-], stage).

    Parameters
    ----------
    s : BaselineSettings
    dt : float
        Sample time [s].
    x, nxt : dict
        The controller's states now and next (the start-up's are updated in ``nxt``).
    reset : casadi.SX
        1 at the first call.
    time : casadi.SX
        ROSCO's time [s].
    rot_speed : casadi.SX
        The measured rotor speed [rad/s].
    r_speed, r_torque : float or casadi.SX
        The ratings of the power reference [-] (what normal operation uses).
    """
    f = x["startup_rotor_filter"]
    rot_f, a, b = lpf1(rot_speed, f[0], f[1], s.startup_rotor_speed_corner, dt, reset)
    nxt["startup_rotor_filter"] = ca.vertcat(a, b)
    n = len(s.startup_loads)
    stage = ca.if_else(reset, -1.0, x["startup_stage"])
    start = ca.if_else(reset, 0.0, x["startup_stage_start"])
    stage = ca.if_else((stage == -1) * (time > s.startup_time), 1.0, stage)
    start = ca.if_else((stage == 1) * (rot_f < 0.95 * s.startup_rotor_speed), time, start)
    leave = (stage == 1) * (time >= s.startup_freewheel_duration + start)
    start = ca.if_else(leave, time, start)
    stage = ca.if_else(leave, 2.0, stage)
    loading = (stage >= 2) * (stage <= n + 1)
    ramp = _pick(stage - 1, s.startup_ramp_durations, 1.0)
    hold = _pick(stage - 1, s.startup_hold_durations, 0.0)
    advance = loading * (time >= start + ramp + hold)
    stage = stage + advance
    start = ca.if_else(advance, time, start)

    threshold = s.startup_rotor_speed * s.gearbox_ratio / s.pitch_reference_speed
    ramp = _pick(stage - 1, s.startup_ramp_durations, 1.0)
    r_speed = ca.if_else(stage == 1, threshold,
                         ca.if_else(stage == 2, sigma(time, start, start + ramp, threshold, 1.0), r_speed))
    previous = ca.if_else(stage == 2, 0.0, _pick(stage - 2, s.startup_loads, 0.0))
    load = _pick(stage - 1, s.startup_loads, 0.0)
    loading = (stage >= 2) * (stage <= n + 1)
    staged = ca.if_else(time < start + ramp, sigma(time, start, start + ramp, previous, load), load)
    r_torque = ca.if_else((stage == 1) + (stage == -1), 0.0, ca.if_else(loading, staged, r_torque))
    stage = ca.if_else(stage == n + 2, 0.0, stage)
    nxt["startup_stage"], nxt["startup_stage_start"] = stage, start
    return r_speed, r_torque, stage
