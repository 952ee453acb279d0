"""The baseline controller's feedback of the tower top's motion to pitch (private to :mod:`.baseline`).

* ROSCO's floating feedback (``Fl_Mode 1``, ``2``): the acceleration low-pass, high-pass and notch filtered
  (:func:`floating_filter`), integrated and fed back with the gain scheduled on the wind-speed estimate;
* ROSCO's tower fore-aft damper (``TD_Mode 1``, :func:`tower_damper`): the nacelle's fore-aft acceleration
  ``FA_Acc_Nac`` high-pass filtered at ``FA_HPFCornerFreq`` (ROSCO's ``PreFilterMeasuredSignals``), integrated by
  a PI controller with no proportional gain, the integral gain ``FA_KI`` [rad s/m] and the limits ±``FA_IntSat``
  [rad] starting at 0 (ROSCO's ``ForeAftDamping``); the result is added to every blade's pitch after the
  collective pitch's saturation and rate limit, before the blades' saturation (ROSCO's ``PitchControl``).

Both read the nacelle's fore-aft acceleration as ROSCO does: zero at the first call, then
``YawBrTAxp cos(NacYaw) + YawBrTAyp sin(NacYaw)`` [m/s²] (``Fl_Mode 2``: the nacelle's pitching acceleration
``NcIMURAys`` [rad/s²]). ROSCO's Filters.f90 and Controllers.f90 (2.10) were read for the facts; the code is ours.
"""

from __future__ import annotations

import casadi as ca

from ._blocks import hpf1, lpf2, notch, pi

#: Measurements the translational signal needs: the tower top's fore-aft and side-side accelerations in the
#: tower-top axes (ServoDyn's records 53, 54) and the nacelle yaw (record 37).
TRANSLATIONAL_MEASUREMENTS = {"YawBrTAxp": "m/s^2", "YawBrTAyp": "m/s^2", "NacYaw": "rad"}
#: The rotational signal (``Fl_Mode 2``): the nacelle's pitching acceleration (record 83).
ROTATIONAL_MEASUREMENTS = {"NcIMURAys": "rad/s^2"}


def extra_measurements(s) -> tuple[str, ...]:
    """The measurements the floating feedback and the tower damper of settings ``s`` add after the others."""
    out = tuple(ROTATIONAL_MEASUREMENTS) if s.floating_mode == 2 else ()
    if s.floating_mode == 1 or s.tower_damper_mode:
        out += tuple(TRANSLATIONAL_MEASUREMENTS)
    return out


def fore_aft_acceleration(measurements: tuple[str, ...], y, reset):
    """ROSCO's ``FA_Acc_Nac`` [m/s²] from the named measurements ``y``: zero at the first call (``reset``)."""
    ax, ay, yaw = (y[measurements.index(n)] for n in TRANSLATIONAL_MEASUREMENTS)
    return ca.if_else(reset, 0.0, ax * ca.cos(yaw) + ay * ca.sin(yaw))


def floating_signal(s, measurements: tuple[str, ...], y, reset):
    """What the floating feedback filters: the nacelle's pitching acceleration [rad/s²] (``Fl_Mode 2``) or
    fore-aft acceleration [m/s²] (``Fl_Mode 1``), zero at the first call as in ROSCO."""
    if s.floating_mode == 1:
        return fore_aft_acceleration(measurements, y, reset)
    return ca.if_else(reset, 0.0, y[measurements.index("NcIMURAys")])


def floating_filter(s, dt: float, x: dict, nxt: dict, reset, acceleration):
    """ROSCO's filtering of the floating feedback's acceleration: second-order low-pass, first-order high-pass
    and the tower-top notch filters (states ``floating_lowpass``, ``floating_highpass``, ``floating_notch<k>``)."""
    u, st = lpf2(acceleration, _split4(x["floating_lowpass"]), s.floating_filter_corner, s.floating_filter_damping,
                 dt, reset)
    nxt["floating_lowpass"] = ca.vertcat(*st)
    u, a, b = hpf1(u, x["floating_highpass"][0], x["floating_highpass"][1], s.floating_highpass_corner, dt, reset)
    nxt["floating_highpass"] = ca.vertcat(a, b)
    for k, (w, bn, bd) in enumerate(zip(s.tower_notch_freqs, s.tower_notch_beta_num, s.tower_notch_beta_den)):
        u, st = notch(u, _split4(x[f"floating_notch{k + 1}"]), w, bn, bd, dt, reset)
        nxt[f"floating_notch{k + 1}"] = ca.vertcat(*st)
    return u


def floating_pitch(s, dt: float, x: dict, nxt: dict, reset, filtered, gain):
    """ROSCO's ``FloatingFeedback``: ``−gain ×`` the integrated filtered acceleration → (pitch [rad], velocity)."""
    velocity, nxt["floating_integral"] = pi(filtered, 0.0, 1.0, -100.0, 100.0, dt, x["floating_integral"], 0.0,
                                            reset)
    return -velocity * gain, velocity


def tower_damper(s, dt: float, x: dict, nxt: dict, reset, acceleration):
    """ROSCO's ``ForeAftDamping`` on the fore-aft acceleration [m/s²] → (pitch increment [rad], filtered
    acceleration [m/s²]) (states ``tower_damper_highpass``, ``tower_damper_integral``)."""
    hp = x["tower_damper_highpass"]
    filtered, a, b = hpf1(acceleration, hp[0], hp[1], s.tower_damper_highpass_corner, dt, reset)
    nxt["tower_damper_highpass"] = ca.vertcat(a, b)
    limit = s.tower_damper_limit
    pitch, nxt["tower_damper_integral"] = pi(filtered, 0.0, s.tower_damper_ki, -limit, limit, dt,
                                             x["tower_damper_integral"], 0.0, reset)
    return pitch, filtered


def _split4(v):
    return v[0], v[1], v[2], v[3]
