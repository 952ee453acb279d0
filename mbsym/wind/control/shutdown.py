"""The baseline controller's shut-down (ROSCO 2.10.6's ``SD_Mode 1``), a latch in the controller's states.

ROSCO's ``Shutdown`` (ControllerBlocks.f90) and the shut-down branches of its ``PitchControl`` and
``VariableSpeedControl`` (Controllers.f90) were read for the facts; the code is ours.

**Triggers** (checked at every call from the time ``SD_TimeActivate`` on, while none has tripped; the
time is ROSCO's, the host's clock in single precision, counted here from the first call at t = 0):

* ``SD_EnablePitch``: the mean pitch the controller last commanded (the measured one at the first call),
  low-pass filtered (first order, ``SD_PitchCornerFreq`` [rad/s]), above ``SD_MaxPit`` [rad];
* ``SD_EnableYawError``: the nacelle-vane yaw error (measurement ``YawErr`` [rad], swap record 24) as the
  angle of its low-pass filtered cosine and sine (``SD_YawErrorCornerFreq``), wrapped to ±180°, above
  ``SD_MaxYawError`` [deg] in magnitude;
* ``SD_EnableGenSpeed``: the measured generator speed, low-pass filtered (``SD_GenSpdCornerFreq``), above
  ``SD_MaxGenSpd`` [rad/s];
* ``SD_EnableTime``: the time after ``SD_Time`` [s].

Once tripped it stays tripped (state ``shutdown_trigger``: 1 pitch, 2 yaw error, 3 speed, 4 time, the last
that held at the tripping call). **Stages** (state ``shutdown_stage``): the call that trips enters stage 1
with both rates 0 (the commands freeze); ``SD_Method 1``: stage ``i`` lasts ``SD_StageTime(i)`` [s]
(``Time ≥ start + SD_StageTime(i)`` moves to ``i + 1``, the call still using stage ``i``'s rates);
``SD_Method 2``: the stage is one more than the last ``i`` with the pitch ≥ ``SD_StagePitch(i)`` [rad]
(unchanged below the first). In stage ``i ≤ SD_Stage_N`` the pitch rises at ``SD_MaxPitchRate(i)``
[rad/s] and the torque falls at ``SD_MaxTorqueRate(i)`` [N m/s]; after the last stage at ``PC_MaxRat``
and ``VS_MaxRat``.

**Commands**: the shut-down pitch (state ``shutdown_pitch``) follows each blade's rate-limited demand until
the trip, then rises from its last value by the stage's rate every call (unbounded: the blades' hardware
saturation and rate limit that follow cap it at ``PC_MaxPit``); the shut-down torque (state
``shutdown_torque``) follows the torque law's output until the trip, then falls by the stage's rate,
within [``VS_MinTq``, ``VS_MaxTq``]; the torque's saturation and rate limit follow as without shut-down.
The controller's other blocks keep running (their outputs are replaced).
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ._blocks import D2R, R2D, lpf1

__all__ = ["SHUTDOWN_MAP", "YAW_ERROR_MEASUREMENTS", "shutdown_values", "shutdown_problems", "shutdown_states",
           "shutdown_measurements", "shutdown_rates", "shutdown_pitch", "shutdown_torque"]

#: DISCON.IN keys of the shut-down → BaselineSettings attribute (read when SD_Mode = 1; ``SD_MaxYawError``
#: [deg] is held in rad, ``SD_Enable*`` as booleans).
SHUTDOWN_MAP = {
    "SD_Mode": "shutdown_mode", "SD_TimeActivate": "shutdown_activation_time",
    "SD_EnablePitch": "shutdown_on_pitch", "SD_EnableYawError": "shutdown_on_yaw_error",
    "SD_EnableGenSpeed": "shutdown_on_generator_speed", "SD_EnableTime": "shutdown_on_time",
    "SD_MaxPit": "shutdown_max_pitch", "SD_PitchCornerFreq": "shutdown_pitch_corner",
    "SD_MaxYawError": "shutdown_max_yaw_error", "SD_YawErrorCornerFreq": "shutdown_yaw_error_corner",
    "SD_MaxGenSpd": "shutdown_max_generator_speed", "SD_GenSpdCornerFreq": "shutdown_generator_speed_corner",
    "SD_Time": "shutdown_time", "SD_Method": "shutdown_method", "SD_StageTime": "shutdown_stage_times",
    "SD_StagePitch": "shutdown_stage_pitch", "SD_MaxTorqueRate": "shutdown_torque_rates",
    "SD_MaxPitchRate": "shutdown_pitch_rates",
}
_FLAGS = ("SD_EnablePitch", "SD_EnableYawError", "SD_EnableGenSpeed", "SD_EnableTime")
#: The measurement the yaw-error trigger adds after the others: the nacelle-vane yaw error (swap record 24).
YAW_ERROR_MEASUREMENTS = {"YawErr": "rad"}


def shutdown_values(d) -> dict:
    """The shut-down settings of a DISCON.IN with ``SD_Mode 1`` (:class:`~.settings.BaselineSettings`
    attribute → value; ROSCO's SI units, ``SD_MaxYawError`` converted from deg to rad)."""
    out = {}
    for key, attr in SHUTDOWN_MAP.items():
        if key in d.values:
            out[attr] = d[key]
    for key in _FLAGS:
        out[SHUTDOWN_MAP[key]] = bool(int(d[key]))
    out["shutdown_max_yaw_error"] = math.radians(float(d["SD_MaxYawError"]))
    n = int(d["SD_Stage_N"])
    for key in ("SD_StageTime", "SD_StagePitch", "SD_MaxTorqueRate", "SD_MaxPitchRate"):
        if key in d.values:
            out[SHUTDOWN_MAP[key]] = tuple(np.atleast_1d(d[key]).astype(float))[:n]
    return out


def shutdown_problems(s) -> list[str]:
    """What is wrong with the shut-down settings of ``s`` (a BaselineSettings; ROSCO's checks); [] if nothing."""
    if s.shutdown_mode == 0:
        return []
    if s.shutdown_mode != 1:
        return [f"shutdown_mode must be 0 (off) or 1, as ROSCO's SD_Mode; got {s.shutdown_mode}"]
    p = []
    n = len(s.shutdown_pitch_rates)
    if n < 1 or len(s.shutdown_torque_rates) != n:
        p.append("shutdown_pitch_rates and shutdown_torque_rates must have the same length >= 1 (SD_Stage_N)")
    if s.shutdown_method not in (1, 2):
        p.append(f"shutdown_method must be 1 (timed stages) or 2 (stages by pitch), as ROSCO's SD_Method; got "
                 f"{s.shutdown_method}")
    elif s.shutdown_method == 1 and (len(s.shutdown_stage_times) != n or any(t < 0 for t in s.shutdown_stage_times)):
        p.append("shutdown_method 1 needs shutdown_stage_times >= 0 [s], one per stage")
    elif s.shutdown_method == 2 and (len(s.shutdown_stage_pitch) != n or np.any(np.diff(s.shutdown_stage_pitch) < 0)):
        p.append("shutdown_method 2 needs non-decreasing shutdown_stage_pitch [rad], one per stage")
    if n and max(s.shutdown_pitch_rates) > s.pitch_rate_max:
        p.append("shutdown_pitch_rates must be <= pitch_rate_max (as ROSCO requires)")
    if n and max(s.shutdown_torque_rates) > s.torque_rate_max:
        p.append("shutdown_torque_rates must be <= torque_rate_max (as ROSCO requires)")
    for flag, corner in (("pitch", "pitch"), ("yaw_error", "yaw_error"), ("generator_speed", "generator_speed")):
        if getattr(s, f"shutdown_on_{flag}") and not getattr(s, f"shutdown_{corner}_corner") >= 0:
            p.append(f"shutdown_{corner}_corner must be >= 0 [rad/s]")
    return p


def shutdown_states(st, s) -> None:
    """Add the shut-down's states to the layout ``st`` (a ``_States``)."""
    st.add("shutdown_trigger")
    st.add("shutdown_stage")
    st.add("shutdown_stage_start")
    if s.shutdown_on_pitch:
        st.add("shutdown_pitch_filter", 2)
    if s.shutdown_on_yaw_error:
        st.add("shutdown_yaw_filter", 4)
    if s.shutdown_on_generator_speed:
        st.add("shutdown_speed_filter", 2)
    st.add("shutdown_pitch", 3 if s.ipc_mode else 1)
    st.add("shutdown_torque")


def shutdown_measurements(s) -> tuple[str, ...]:
    """The measurements the shut-down adds after the others (the yaw error with ``SD_EnableYawError``)."""
    return tuple(YAW_ERROR_MEASUREMENTS) if s.shutdown_mode and s.shutdown_on_yaw_error else ()


def shutdown_rates(s, dt: float, x: dict, nxt: dict, reset, time, pitch, gen_speed, yaw_error):
    """ROSCO's ``Shutdown`` at one call → (trigger, pitch rate [rad/s], torque rate [N m/s], stage).

    Parameters
    ----------
    s : BaselineSettings
    dt : float
        Sample time [s].
    x, nxt : dict
        The controller's states now and next (the shut-down's are updated in ``nxt``).
    reset : casadi.SX
        1 at the first call.
    time : casadi.SX
        ROSCO's time [s].
    pitch : casadi.SX
        The mean pitch ROSCO's ``BlPitchCMeas`` [rad] (previous commands; measured at the first call).
    gen_speed : casadi.SX
        The measured generator speed [rad/s].
    yaw_error : casadi.SX or None
        The nacelle-vane yaw error [rad] (with ``shutdown_on_yaw_error``).
    """
    trigger = ca.if_else(reset, 0.0, x["shutdown_trigger"])
    armed = (trigger == 0) * (time >= s.shutdown_activation_time)
    new = ca.SX(0.0)
    if s.shutdown_on_pitch:
        f = x["shutdown_pitch_filter"]
        pitch_f, a, b = lpf1(pitch, f[0], f[1], s.shutdown_pitch_corner, dt, reset)
        nxt["shutdown_pitch_filter"] = ca.vertcat(a, b)
        new = ca.if_else(pitch_f > s.shutdown_max_pitch, 1.0, new)
    if s.shutdown_on_yaw_error:
        new = ca.if_else(ca.fabs(_yaw_error_deg(s, dt, x, nxt, reset, yaw_error))
                         > math.degrees(s.shutdown_max_yaw_error), 2.0, new)
    if s.shutdown_on_generator_speed:
        f = x["shutdown_speed_filter"]
        speed_f, a, b = lpf1(gen_speed, f[0], f[1], s.shutdown_generator_speed_corner, dt, reset)
        nxt["shutdown_speed_filter"] = ca.vertcat(a, b)
        new = ca.if_else(speed_f > s.shutdown_max_generator_speed, 3.0, new)
    if s.shutdown_on_time:
        new = ca.if_else(time > s.shutdown_time, 4.0, new)
    trigger = ca.if_else(armed * (new > 0), new, trigger)
    nxt["shutdown_trigger"] = trigger

    stage = ca.if_else(reset, 0.0, x["shutdown_stage"])
    start = ca.if_else(reset, 0.0, x["shutdown_stage_start"])
    n = len(s.shutdown_pitch_rates)
    idle = stage == 0
    if s.shutdown_method == 1:
        pitch_rate, torque_rate = _by_stage(stage, s.shutdown_pitch_rates, s.pitch_rate_max), \
            _by_stage(stage, s.shutdown_torque_rates, s.torque_rate_max)
        stage_time = _by_stage(stage, s.shutdown_stage_times, 0.0)
        advance = (stage >= 1) * (stage <= n) * (time >= start + stage_time)
        start = ca.if_else(idle * (trigger > 0) + advance, time, start)
        stage_next = ca.if_else(idle, ca.if_else(trigger > 0, 1.0, 0.0), stage + advance)
    else:
        moved = stage
        for i, level in enumerate(s.shutdown_stage_pitch):
            moved = ca.if_else(pitch >= level, float(i + 2), moved)
        stage_next = ca.if_else(idle, ca.if_else(trigger > 0, 1.0, 0.0), moved)
        pitch_rate, torque_rate = _by_stage(stage_next, s.shutdown_pitch_rates, s.pitch_rate_max), \
            _by_stage(stage_next, s.shutdown_torque_rates, s.torque_rate_max)
    pitch_rate = ca.if_else(idle, 0.0, pitch_rate)
    torque_rate = ca.if_else(idle, 0.0, torque_rate)
    nxt["shutdown_stage"], nxt["shutdown_stage_start"] = stage_next, start
    return trigger, pitch_rate, torque_rate, stage_next


def _by_stage(stage, values: tuple[float, ...], after: float):
    """``values[stage − 1]`` for stages 1..n, ``after`` beyond (0 for stage 0)."""
    out = ca.if_else(stage > len(values), after, 0.0)
    for i, v in enumerate(values):
        out = ca.if_else(stage == i + 1, v, out)
    return out


def _yaw_error_deg(s, dt: float, x: dict, nxt: dict, reset, yaw_error):
    """The filtered yaw error [deg], ROSCO's ``SD_NacVaneF``: the angle of the low-pass filtered cosine and sine of
    the vane angle (in degrees from the record, as ROSCO converts it), wrapped to (−180°, 180°]."""
    f = x["shutdown_yaw_filter"]
    vane = yaw_error * R2D * D2R
    cos_f, a, b = lpf1(ca.cos(vane), f[0], f[1], s.shutdown_yaw_error_corner, dt, reset)
    sin_f, c, e = lpf1(ca.sin(vane), f[2], f[3], s.shutdown_yaw_error_corner, dt, reset)
    nxt["shutdown_yaw_filter"] = ca.vertcat(a, b, c, e)
    angle = ca.atan2(sin_f, cos_f) * R2D
    return ca.if_else(angle <= -180.0, angle + 360.0, ca.if_else(angle > 180.0, angle - 360.0, angle))


def shutdown_pitch(x: dict, nxt: dict, reset, trigger, rate, dt: float, demand):
    """Each blade's pitch demand [rad] after the shut-down (ROSCO's ``PitCom_SD``; state ``shutdown_pitch``)."""
    last = ca.if_else(reset, 0.0, x["shutdown_pitch"])
    out = ca.if_else(trigger == 0, demand, last + rate * dt)
    nxt["shutdown_pitch"] = out
    return out


def shutdown_torque(s, x: dict, nxt: dict, reset, trigger, rate, dt: float, torque):
    """The torque demand [N m] after the shut-down (ROSCO's ``GenTq_SD``; state ``shutdown_torque``)."""
    last = ca.if_else(reset, 0.0, x["shutdown_torque"])
    falling = ca.fmin(ca.fmax(last - rate * dt, s.torque_min), s.torque_max)
    out = ca.if_else(trigger == 0, torque, falling)
    nxt["shutdown_torque"] = out
    return out
