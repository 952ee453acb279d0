"""The baseline controller's power reference (ROSCO 2.10.6's ``PRC_Mode`` 1 and 2, constant inputs).

ROSCO's ``PowerControlSetpoints`` and ``ComputeVariablesSetpoints`` (ControllerBlocks.f90) and its torque and
pitch saturation (Controllers.f90) were read for the facts; the code is ours.

``PRC_Mode 1`` (:attr:`~.settings.BaselineSettings.power_reference_mode` 1): the wind-speed estimate, low-pass
filtered (first order, ``PRC_LPF_Freq``, starting at the estimate at the first call), is looked up in the table
``PRC_WindSpeeds`` [m/s] → ``PRC_GenSpeeds`` [rad/s] (clamped linear interpolation). The value replaces the
pitch controller's reference speed ``PC_RefSpd`` and the torque controller's reference (after its filter and
limits, before the set-point smoother's shift and the minimum speed ``VS_MinOMSpd``).

``PRC_Mode 2`` with ``PRC_Comm 0`` (constant ratings from the DISCON.IN, ``PRC_R_Speed``, ``PRC_R_Torque``,
``PRC_R_Pitch``, all [-]):

* the pitch reference speed is ``PC_RefSpd · R_speed`` and the torque reference's upper limit
  ``VS_RefSpd · R_speed`` (ROSCO 2.10.6 limits the filtered reference there but does not scale the
  reference itself);
* the torque limit is ``R_torque`` times the constant-power torque (``VS_ConstPower 1``) or ``VS_RtTq``;
* the set-point smoother compares the power with ``VS_RtPwr · R_speed · R_torque · R_pitch``;
* with peak shaving (``PS_Mode 1``) the minimum pitch is at least ``PRC_Pitch_Table`` at ``R_pitch`` in
  ``PRC_R_Table``.

The open-loop (``PRC_Comm 1``) and ZeroMQ (``PRC_Comm 2``) ratings are refused by name.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ...exceptions import ControllerError
from ._blocks import interp1, lpf1

__all__ = ["power_reference_values", "power_reference_problems", "ratings", "rating_min_pitch", "scheduled_speed"]


def power_reference_values(d) -> dict:
    """The power-reference settings of a DISCON.IN with ``PRC_Mode`` 1 or 2 (refuses ``PRC_Comm`` ≠ 0 in mode 2).

    Parameters
    ----------
    d : DisconInput
        The controller input file read.

    Returns
    -------
    dict
        :class:`~.settings.BaselineSettings` attribute → value (ROSCO's SI units).

    Raises
    ------
    ControllerError
        ``PRC_Comm`` 1 or 2 (file, line, key), or ``PRC_R_Pitch`` ≠ 1 without ``PRC_R_Table``.
    """
    mode = int(d["PRC_Mode"])
    out = {"power_reference_mode": mode, "power_reference_filter_corner": d["PRC_LPF_Freq"],
           "power_reference_wind_speeds": d["PRC_WindSpeeds"], "power_reference_generator_speeds": d["PRC_GenSpeeds"]}
    if mode != 2:
        return out
    comm = int(d["PRC_Comm"]) if "PRC_Comm" in d.values else 0
    if comm != 0:
        raise ControllerError(f"{d.where('PRC_Comm')}: PRC_Comm = {comm} is not supported by the baseline controller "
                              "(supported: 0, constant ratings PRC_R_Speed, PRC_R_Torque, PRC_R_Pitch); the open-loop "
                              "(1) and ZeroMQ (2) inputs need DisconController with the DISCON library.")
    out.update(power_rating_speed=d["PRC_R_Speed"], power_rating_torque=d["PRC_R_Torque"],
               power_rating_pitch=d["PRC_R_Pitch"])
    if "PRC_R_Table" in d.values and "PRC_Pitch_Table" in d.values:
        out.update(power_rating_table=d["PRC_R_Table"], power_rating_min_pitch=d["PRC_Pitch_Table"])
    return out


def power_reference_problems(s) -> list[str]:
    """What is wrong with the power-reference settings of ``s`` (a BaselineSettings); [] if nothing."""
    mode = s.power_reference_mode
    if mode == 0:
        return []
    if mode not in (1, 2):
        return [f"power_reference_mode must be 0 (off), 1 (speed table) or 2 (ratings), as ROSCO's PRC_Mode; "
                f"got {mode}"]
    p = []
    n = len(s.power_reference_wind_speeds)
    if mode == 1:
        if n < 1 or len(s.power_reference_generator_speeds) != n:
            p.append("power_reference_wind_speeds and power_reference_generator_speeds must have the same length >= 1")
        if not s.power_reference_filter_corner > 0:
            p.append(f"power_reference_filter_corner must be > 0 [rad/s]; got {s.power_reference_filter_corner}")
        return p
    for name in ("power_rating_speed", "power_rating_torque", "power_rating_pitch"):
        if not getattr(s, name) >= 0:
            p.append(f"{name} must be >= 0 (as ROSCO requires); got {getattr(s, name)}")
    m = len(s.power_rating_table)
    if m != len(s.power_rating_min_pitch) or (m == 0 and s.peak_shaving):
        p.append("with peak shaving, power_reference_mode 2 needs power_rating_table and power_rating_min_pitch "
                 "(ROSCO's PRC_R_Table, PRC_Pitch_Table) of the same length >= 1")
    elif m > 1 and np.any(np.diff(s.power_rating_table) <= 0):
        p.append("power_rating_table must strictly increase")
    return p


def ratings(s) -> tuple[float, float, float]:
    """ROSCO's ``PRC_R_Speed``, ``PRC_R_Torque``, ``PRC_R_Pitch`` [-] (1, 1, 1 unless ``PRC_Mode 2``)."""
    if s.power_reference_mode != 2:
        return 1.0, 1.0, 1.0
    return s.power_rating_speed, s.power_rating_torque, s.power_rating_pitch


def rating_min_pitch(s) -> float | None:
    """The minimum pitch [rad] of the pitch rating (``PRC_Mode 2``, combined with peak shaving), else None."""
    if s.power_reference_mode != 2 or not s.power_rating_table:
        return None
    return float(np.interp(s.power_rating_pitch, s.power_rating_table, s.power_rating_min_pitch))


def scheduled_speed(s, dt: float, x: dict, nxt: dict, reset, estimate):
    """``PRC_Mode 1``: the generator-speed set-point [rad/s] from the filtered wind-speed estimate ``estimate``
    [m/s] (state ``power_reference_filter``); None (and no state) otherwise."""
    if s.power_reference_mode != 1:
        return None
    filtered, a, b = lpf1(estimate, x["power_reference_filter"][0], x["power_reference_filter"][1],
                          s.power_reference_filter_corner, dt, reset)
    nxt["power_reference_filter"] = ca.vertcat(a, b)
    return interp1(s.power_reference_wind_speeds, s.power_reference_generator_speeds, "prc_speed")(filtered)
