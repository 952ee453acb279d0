"""Individual pitch control (IPC) of the baseline controller: ROSCO 2.10.6's scheme as CasADi SX expressions.

Used by :class:`~mbsym.wind.control.baseline.BaselineController` when
``settings.ipc_mode > 0`` (``IPC_ControlMode`` 1: 1P, 2: 1P + 2P).  One step, in ROSCO's
order (its Fortran source was read to learn the scheme; the code is ours):

1. the blade-root out-of-plane moments ``RootMyc1..3`` [N m] pass a band-pass
   centred on the filtered rotor speed (ROSCO's moving "inverted notch",
   damping 0.7; see :func:`~._blocks.bandpass`), which isolates the 1P content;
2. the Coleman (multi-blade) transform at the measured azimuth ψ, harmonic n = 1
   (and 2): tilt ``(2/3) Σ_k cos(n(ψ + φ_k)) M_k``, yaw ``(2/3) Σ_k sin(n(ψ + φ_k)) M_k``,
   ``φ_k = (k − 1)·2π/3``;
3. per axis a PI controller (``IPC_KP``, ``IPC_KI`` of the harmonic) on that axis,
   its output and integrator limited to ±L; both gains are ramped in over the
   current wind-speed estimate with ROSCO's cubic ``sigma`` between ``IPC_Vramp[0]``
   (off) and ``IPC_Vramp[1]`` (fully on); the limit L is ``IPC_IntSat``
   (``IPC_SatMode`` 0 and 1), ``min(IPC_IntSat, β̄ − PC_MinPit)`` (mode 2) or
   ``min(IPC_IntSat, β̄ − β_min)`` (mode 3, β_min: the previous step's minimum pitch,
   peak shaving included), with β̄ the mean of the three previous pitch commands;
4. the inverse transform at ``ψ + IPC_aziOffset[n−1]``:
   ``θ_k = cos(n(ψ + offset + φ_k))·tilt + sin(n(ψ + offset + φ_k))·yaw``, summed over
   the harmonics, then optionally low-pass filtered (first order,
   ``IPC_CornerFreqAct`` > 0).

The pitch block adds ``θ_k`` to the saturated collective demand of each blade
(``IPC_SatMode 1`` saturates the sum again to [β_min, ``PC_MaxPit``]), then
rate-limits, saturates to [``PC_MinPit``, ``PC_MaxPit``] and rate-limits again per blade.

At the first call (ROSCO's initialization) every filter starts at its input and
every PI controller outputs 0, so the first commands carry no IPC.

ROSCO 2.10.6 feeds the 2P yaw-axis PI controller a signal it never sets (its
``axisYawF_2P``, which stays 0): with ``IPC_ControlMode 2`` only the 2P *tilt* axis
acts.  We reproduce that (the 2P yaw command is identically 0) to track the library.
"""

from __future__ import annotations

import casadi as ca

from ._blocks import bandpass, lpf1, pi

__all__ = ["IPC_DIAGNOSTICS", "ROSCO_PI", "coleman", "coleman_inverse", "gain_ramp", "ipc_states", "ipc_step"]

#: ROSCO's value of π (Constants.f90), used in its blade phase angles; kept to stay bit-close.
ROSCO_PI = 3.14159265359
_PHASES = (0.0, 2.0 / 3.0 * ROSCO_PI, 4.0 / 3.0 * ROSCO_PI)
#: Damping of the band-pass on the root moments (ROSCO's fixed value).
ROOT_MOMENT_DAMPING = 0.7
#: Internal signals appended to the controller's diagnostics when IPC is on.
IPC_DIAGNOSTICS = ("IPC_axisTilt_1P", "IPC_axisYaw_1P", "IPC_axisTilt_2P", "IPC_axisYaw_2P", "IPC_Ramp",
                   "IPC_IntSat", "IPC_PitComF1", "IPC_PitComF2", "IPC_PitComF3")


def coleman(moments, azimuth, harmonic: int):
    """Coleman transform of three blade signals → (tilt, yaw) at ``harmonic`` (1 or 2)."""
    cos_sum = sum(ca.cos(harmonic * (azimuth + p)) * m for p, m in zip(_PHASES, moments))
    sin_sum = sum(ca.sin(harmonic * (azimuth + p)) * m for p, m in zip(_PHASES, moments))
    return 2.0 / 3.0 * cos_sum, 2.0 / 3.0 * sin_sum


def coleman_inverse(tilt, yaw, azimuth, harmonic: int, offset: float):
    """Inverse Coleman transform → the three blade signals (blade k at ``azimuth + offset + φ_k``)."""
    angles = [harmonic * (azimuth + offset + p) for p in _PHASES]
    return [ca.cos(a) * tilt + ca.sin(a) * yaw for a in angles]


def gain_ramp(wind, start: float, end: float):
    """ROSCO's ``sigma`` ramp from 0 (wind < start) to 1 (wind > end), a cubic with zero slopes at both ends."""
    d3 = (start - end) ** 3
    a3, a2, a1, a0 = 2.0 / d3, -3.0 * (start + end) / d3, 6.0 * end * start / d3, (start - 3.0 * end) * start**2 / d3
    cubic = a3 * wind**3 + a2 * wind**2 + a1 * wind + a0
    return ca.if_else(wind < start, 0.0, ca.if_else(wind > end, 1.0, cubic))


def ipc_states(states, settings) -> None:
    """Add the IPC states to the controller's state layout (``states.add(name, n)``)."""
    states.add("root_filter", 12)                                 # 3 blades × (in1, in2, out1, out2)
    states.add("ipc_integral", 2 * settings.ipc_mode)             # (tilt, yaw) per harmonic
    if settings.ipc_actuator_corner > 0:
        states.add("ipc_filter", 6)                               # 3 blades × (last in, last out)


def ipc_step(settings, dt: float, x: dict, nxt: dict, reset, moments, azimuth, rotor_speed_f, wind_estimate,
             mean_pitch):
    """One IPC step → (the three blade pitch increments [rad], diagnostics :data:`IPC_DIAGNOSTICS`).

    ``x``/``nxt``: the controller's bound states and next states (IPC entries are
    written to ``nxt``); ``moments``: RootMyc1..3 [N m]; ``azimuth`` [rad];
    ``rotor_speed_f``: filtered rotor speed [rad/s] (band-pass centre);
    ``wind_estimate`` [m/s] (gain ramp); ``mean_pitch``: β̄ [rad] (soft saturation).
    """
    s = settings
    filtered, filter_next = [], []
    for k in range(3):
        y, st = bandpass(moments[k], [x["root_filter"][4 * k + i] for i in range(4)], rotor_speed_f,
                         ROOT_MOMENT_DAMPING, dt, reset)
        filtered.append(y)
        filter_next += list(st)
    nxt["root_filter"] = ca.vertcat(*filter_next)

    ramp = gain_ramp(wind_estimate, *s.ipc_wind_ramp)
    if s.ipc_saturation_mode == 2:
        limit = ca.fmin(s.ipc_integrator_limit, mean_pitch - s.pitch_min)
    elif s.ipc_saturation_mode == 3:
        limit = ca.fmin(s.ipc_integrator_limit, mean_pitch - x["min_pitch"])
    else:
        limit = ca.SX(s.ipc_integrator_limit)

    axes, integral_next, pitch = [], [], [ca.SX(0.0)] * 3
    for h in range(1, s.ipc_mode + 1):
        tilt, yaw = coleman(filtered, azimuth, h)
        if h == 2:
            yaw = ca.SX(0.0)          # ROSCO 2.10.6: the 2P yaw PI input is never set (module docstring)
        kp, ki = ramp * s.ipc_kp[h - 1], ramp * s.ipc_ki[h - 1]
        out = []
        for j, error in enumerate((tilt, yaw)):
            u, i_next = pi(error, kp, ki, -limit, limit, dt, x["ipc_integral"][2 * (h - 1) + j], 0.0, reset)
            out.append(u)
            integral_next.append(i_next)
        axes += out
        blade = coleman_inverse(out[0], out[1], azimuth, h, s.ipc_azimuth_offset[h - 1])
        pitch = [p + b for p, b in zip(pitch, blade)]
    nxt["ipc_integral"] = ca.vertcat(*integral_next)
    axes += [ca.SX(0.0)] * (4 - len(axes))

    if s.ipc_actuator_corner > 0:
        out, st = [], []
        for k in range(3):
            y, a, b = lpf1(pitch[k], x["ipc_filter"][2 * k], x["ipc_filter"][2 * k + 1], s.ipc_actuator_corner, dt,
                           reset)
            out.append(y)
            st += [a, b]
        pitch = out
        nxt["ipc_filter"] = ca.vertcat(*st)
    return pitch, axes + [ramp, limit] + pitch
