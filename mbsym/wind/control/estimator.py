"""The baseline controller's wind-speed estimator (ROSCO's ``WE_Mode`` 2 EKF and its fallback; private).

Moved out of :mod:`.baseline` unchanged; ROSCO's ControllerBlocks.f90 (``WindSpeedEstimator``) was read for the
facts, the code is ours. See the module docstring of :mod:`.baseline` for the scheme and the one difference
(:data:`RANGE_TOLERANCE`).
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ._blocks import D2R, EPS, R2D, interp1, interp2, lpf1, sat

#: Pitch below the estimator's range [rad] still counted in range (ROSCO: exactly 0; see wind_estimate).
RANGE_TOLERANCE = 1e-12
# ROSCO's fixed EKF constants (ControllerBlocks.f90): turbulence intensity, length scale / R, noise.
_EKF_TI, _EKF_LENGTH, _EKF_R = 0.18, 6.0, 0.02


def wind_estimate(s, dt: float, x: dict, nxt: dict, r, rot_f, pitch, torque_f, hub_wind, last_estimate):
    """ROSCO's WindSpeedEstimator: input saturation, EKF, fallback to the filtered hub wind.

    Parameters
    ----------
    s : BaselineSettings
    dt : float
        Sample time [s].
    x, nxt : dict
        The controller's states by name (read) and next states (written: ``estimator_on``, ``hub_wind_filter``,
        ``ekf_x``, ``ekf_P``, ``ekf_K``, ``wind_estimate``).
    r : casadi.SX
        1 at the first call.
    rot_f, pitch, torque_f, hub_wind, last_estimate : casadi.SX
        Filtered rotor speed [rad/s], the controller's pitch [rad], filtered torque [N m], hub-height wind [m/s],
        previous estimate [m/s].

    Returns
    -------
    estimate : casadi.SX
        The wind-speed estimate [m/s].
    op : casadi.SX
        1 if the estimator's inputs are in the Cp table's range.
    cp_op : casadi.SX
        The power coefficient at the operating point [-] (0 without the EKF).
    """
    min_speed = 0.25 * s.min_generator_speed / s.gearbox_ratio
    speed_in = ca.if_else(rot_f < min_speed, min_speed + EPS, rot_f)
    max_pitch = (s.cp_pitch[-1] * 180.0 / math.pi) * D2R if s.cp_pitch else 0.0
    pitch_in = sat(pitch, s.pitch_min, max_pitch)
    torque_min = 1e-4 * s.rated_torque
    torque_in = ca.if_else(torque_f < torque_min, torque_min, torque_f)
    op_last = ca.if_else(r, 1.0, x["estimator_on"])
    # ROSCO tests "input was saturated" with exact comparisons; a rounding residual (a rate-limited pitch
    # arriving at the minimum as -3e-20 rad) then switches its estimator off for one step and restarts
    # the EKF. We accept residuals below RANGE_TOLERANCE [rad] on the pitch (see the module docstring).
    op = ca.if_else((ca.fabs(pitch_in - pitch) > RANGE_TOLERANCE) + (torque_in != torque_f) +
                    (speed_in != rot_f), 0.0, 1.0)
    restart = r + (op != op_last) if s.wind_estimator > 0 else r
    restart = restart > 0
    nxt["estimator_on"] = op
    hub_f, a, b = lpf1(hub_wind, *_split2(x["hub_wind_filter"]), s.estimate_filter_corner / 10.0, dt,
                       restart, initial=last_estimate)
    nxt["hub_wind_filter"] = ca.vertcat(a, b)
    if s.wind_estimator != 2:
        nxt.update(ekf_x=x["ekf_x"], ekf_P=x["ekf_P"], ekf_K=x["ekf_K"], wind_estimate=hub_f)
        return hub_f, op, ca.SX(0.0)
    xh, P, K = x["ekf_x"], ca.reshape(x["ekf_P"], 3, 3), x["ekf_K"]
    # restart values
    vm0 = ca.fmax(hub_f, 3.0)
    xh_restart = ca.vertcat(speed_in, 0.0, vm0)
    P_restart = ca.diag(ca.vertcat(0.01, 0.01, 1.0))
    # prediction and update
    om_r, vt, vm = ca.fmax(xh[0], EPS), xh[1], xh[2]
    vh = vt + vm
    R, J, rho, L = s.rotor_radius, s.drivetrain_inertia, s.air_density, _EKF_LENGTH * s.rotor_radius
    area = math.pi * R**2
    pole = interp1(s.estimator_wind_speeds, s.estimator_poles, "we_poles")(vh)
    cp_lookup = interp2(np.asarray(s.cp_pitch) * 180.0 / math.pi, s.cp_tsr, s.cp, "we_cp")
    cp_raw = cp_lookup(pitch_in * R2D, ca.fmax(speed_in, EPS) * R / vh)
    cp_op = ca.fmax(0.0, cp_raw)
    F = ca.SX.zeros(3, 3)
    F[0, 0] = pole
    F[0, 1] = 1.0 / (2.0 * J) * rho * math.pi * R**2.0 * 1.0 / om_r * 3.0 * cp_op * vh**2.0
    F[0, 2] = F[0, 1]
    F[1, 1] = -math.pi * vm / (2.0 * L)
    F[1, 2] = -math.pi * vt / (2.0 * L)
    Q = ca.diag(ca.vertcat(1e-5, math.pi * vm**3.0 * _EKF_TI**2.0 / L, 2.0**2.0 / 600.0))
    wind = ca.fmax(last_estimate, EPS)
    tau = ca.fmax(0.5 * (rho * area) * (last_estimate**3 / speed_in) *
                  cp_lookup(pitch_in * R2D, speed_in * R / wind), 0.0)
    dx = ca.vertcat(1.0 / J * (tau - s.gearbox_ratio * torque_in), -math.pi * vm / (2.0 * L) * vt, 0.0)
    xp = xh + dt * dx
    Pp = P + dt * (F @ P + P @ F.T + Q - (K * _EKF_R) @ K.T)
    K_new = Pp[:, 0] / (Pp[0, 0] + _EKF_R)
    xu = xp + K_new * (speed_in - om_r)
    H = ca.horzcat(1.0, 0.0, 0.0)
    Pu = (ca.SX.eye(3) - K_new @ H) @ Pp
    # select
    run = op > 0
    xh_next = ca.if_else(run, ca.if_else(restart, xh_restart, xu), xh)
    P_next = ca.if_else(run, ca.if_else(restart, P_restart, Pu), P)
    K_next = ca.if_else(run, ca.if_else(restart, ca.SX.zeros(3), K_new), K)
    estimate = ca.if_else(run, xh_next[1] + xh_next[2], hub_f)
    nxt.update(ekf_x=xh_next, ekf_P=ca.vec(P_next), ekf_K=K_next, wind_estimate=estimate)
    return estimate, op, cp_op


def _split2(v):
    return v[0], v[1]
