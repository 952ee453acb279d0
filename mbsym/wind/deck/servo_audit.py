"""What ServoDyn does to the DOFs mbsym models: modelled, or refused with the file, line and key.

ServoDyn acts on the structure through the yaw bearing, the high-speed shaft, the blade pitch
and, optionally, structural controllers. Each setting that can change the motion of a DOF mbsym
models within the simulated time ``t_end`` is either modelled or refused here (never ignored):

=====================================  =========================================================
Setting                                What mbsym does
=====================================  =========================================================
YawSpr, YawDamp, YawNeut (YawDOF)      modelled: ``YawMom = -YawSpr (NacYaw - YawNeut) - YawDamp
                                       YawRate`` (ServoDyn's ``Yaw_CalcOutput`` with ``YCMode = 0``
                                       or before ``TYCOn``: the command is the neutral yaw at rest)
TYawManS < t_end (YCMode 0, or before  modelled: the override yaw maneuver moves the command (``YawPosCom``,
TYCOn), YawManRat, NacYawF             ``YawRateCom``) from YawNeut to NacYawF at YawManRat
                                       (mbsym.wind.deck.yaw_control.YawManeuver)
YCMode 5 with TYCOn < t_end            modelled with the DISCON library in the loop: its yaw-rate demand
                                       (record 48) integrated by ServoDyn (yaw_control.DllYaw)
YCMode 3, 4 with TYCOn < t_end;        refused (user routine, Simulink; the maneuver from a library's
TYawManS after TYCOn with YCMode 5     integrated command)
HSSBrMode 1 (THSSBrDp, HSSBrDT,        modelled by the operating turbine (GenDOF): the brake ramp as
HSSBrTqF)                              the input HSSBrTqC (mbsym.wind.operation.hss_brake); HSSBrMode 3,
                                       4, 5 refused
GenTiStr/TimGenOn > 0, SpdGenOn above  refused (generator switched on late or off early); SpdGenOn at
the initial speed, GenTiStp with       or below the initial generator speed: online from t = 0 (modelled)
TimGenOf < t_end (GenDOF)
TPitManS(k) < t_end                    refused (override pitch maneuver)
TPCOn > 0 with PCMode ≠ 0              refused (pitch control starting late)
NumNStC, NumTStC, NumSStC > 0          modelled: nacelle, tower and platform tuned mass dampers and
                                       prescribed loads (mbsym.wind.structure.structural_control,
                                       which refuses the StC modes and settings it does not model)
AfCmode ≠ 0, NumBStC > 0, CCmode ≠ 0   refused (airfoil control, blade structural controllers, cable
                                       control)
PitSpr, PitDamp, PitNeut               inert: they act on ElastoDyn's PitchDOF, which mbsym refuses
=====================================  =========================================================

Facts from OpenFAST v5 ``modules/servodyn/src/ServoDyn.f90`` (``Yaw_CalcOutput``,
``CalculateStandardYaw``: the sign convention and that without yaw control the commanded yaw
is ``YawNeut`` at zero rate).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

from ...exceptions import OpenFASTFormatError

__all__ = ["YawDrive", "servo_audit"]


@dataclass(frozen=True)
class YawDrive:
    """ServoDyn's yaw spring and damper about the neutral yaw.

    Attributes
    ----------
    spring : float
        YawSpr [N m/rad].
    damping : float
        YawDamp [N m s/rad].
    neutral : float
        YawNeut [rad].
    control : YawManeuver or DllYaw or None
        ServoDyn's commanded yaw when it moves within the run (:mod:`mbsym.wind.deck.yaw_control`).
    """

    spring: float
    damping: float
    neutral: float
    control: object = None


def servo_audit(servodyn, dofs: Mapping[str, bool], t_end: float, *,
                generator_speed: float | None = None) -> YawDrive | None:
    """The yaw drive ServoDyn applies, after refusing every setting mbsym does not model (module docstring).

    Parameters
    ----------
    servodyn : ServoDynSettings or None
        None (``CompServo = 0``): no ServoDyn loads, returns None.
    dofs : mapping of str to bool
        ElastoDyn DOF flags of the model (``YawDOF``, ``GenDOF`` ...).
    t_end : float
        The simulated end time [s] (the deck's TMax for steady analyses): settings triggered later
        than this do not act.
    generator_speed : float, optional, keyword-only
        The initial generator (HSS) speed [rad/s]: with ``GenTiStr = False`` ServoDyn puts the generator online
        once its speed reaches ``SpdGenOn`` and keeps it there, so a start at or above it is the generator
        online from t = 0 (modelled).

    Returns
    -------
    YawDrive or None
        With ``YawDOF``, the spring and damper to put on the yaw DOF.

    Raises
    ------
    OpenFASTFormatError
        Every setting that would act and is not modelled, each with file, line and key.
    """
    if servodyn is None:
        return None
    problems = [f"{servodyn.path}, line {servodyn.lines.get(key, '?')}, key '{key}': {text}"
                for key, text in _problems(servodyn, dofs, float(t_end), generator_speed)]
    if len(problems) == 1:
        raise OpenFASTFormatError(problems[0])
    if problems:
        raise OpenFASTFormatError(f"{len(problems)} ServoDyn settings mbsym does not model:\n  - "
                                  + "\n  - ".join(problems))
    if not dofs.get("YawDOF"):
        return None
    return YawDrive(float(servodyn.yaw_spring), float(servodyn.yaw_damping), float(servodyn.yaw_neutral),
                    _yaw_control(servodyn, float(t_end)))


def _yaw_control(s, t_end: float):
    """The commanded yaw that moves within the run (after the refusals of :func:`_problems`), or None."""
    from .yaw_control import DllYaw, YawManeuver

    if s.yaw_maneuver_start_time < t_end:
        return YawManeuver.from_servodyn(s)
    if s.yaw_control_mode == 5 and s.yaw_control_start_time < t_end:
        return DllYaw.from_servodyn(s)
    return None


def _when(t: float) -> str:
    return f"at t = {t:g} s" if math.isfinite(t) else "never"


def _problems(s, dofs: Mapping[str, bool], t_end: float, generator_speed: float | None = None
              ) -> list[tuple[str, str]]:
    out = []
    later = f"set it beyond the simulated time ({t_end:g} s)"
    if dofs.get("YawDOF"):
        control = s.yaw_control_mode != 0 and s.yaw_control_start_time < min(t_end, s.yaw_maneuver_start_time)
        if control and s.yaw_control_mode != 5:
            out.append(("YCMode", f"active yaw control (YCMode = {s.yaw_control_mode}, TYCOn = "
                                  f"{s.yaw_control_start_time:g} s) is not modelled; set YCMode = 0 (the yaw spring "
                                  f"and damper hold the nacelle at YawNeut), 5 (a DISCON library's yaw rate) or "
                                  f"TYCOn: {later}"))
        if s.yaw_maneuver_start_time < t_end and control:
            out.append(("TYawManS", f"the override yaw maneuver {_when(s.yaw_maneuver_start_time)} after active yaw "
                                    f"control started (TYCOn = {s.yaw_control_start_time:g} s) is not modelled; "
                                    f"{later}, or TYCOn after it"))
        elif s.yaw_maneuver_start_time < t_end and s.yaw_maneuver_rate == 0.0:
            out.append(("YawManRat", "the override yaw maneuver needs YawManRat ≠ 0 (as ServoDyn)"))
    if dofs.get("GenDOF"):
        brake = s.hss_brake_mode
        if brake in (3, 4, 5):
            out.append(("HSSBrMode", f"the high-speed shaft brake of HSSBrMode = {brake} (user routine, DLL or "
                                     "external) is not modelled; set HSSBrMode = 0, or 1 (ServoDyn's ramp: "
                                     "THSSBrDp, HSSBrDT, HSSBrTqF)"))
        if s.generator_start_timed and s.generator_start_time > 0:
            out.append(("TimGenOn", f"the generator switched on at t = {s.generator_start_time:g} s is not "
                                    "modelled (it runs from t = 0); set TimGenOn = 0"))
        if not s.generator_start_timed and s.generator_start_speed > 0 and not (
                generator_speed is not None and generator_speed >= s.generator_start_speed):
            rpm = 30.0 / math.pi
            now = "" if generator_speed is None else f" ({generator_speed * rpm:.6g} rpm)"
            out.append(("GenTiStr", f"starting the generator at a speed (GenTiStr = False, SpdGenOn = "
                                    f"{s.generator_start_speed * rpm:.6g} rpm) above the initial generator speed"
                                    f"{now} is not modelled; set GenTiStr = True and TimGenOn = 0, or start at "
                                    "SpdGenOn or above"))
        if s.generator_stop_timed and s.generator_stop_time < t_end:
            out.append(("TimGenOf", f"the generator switched off at t = {s.generator_stop_time:g} s is not "
                                    f"modelled; {later}"))
    for k, t in enumerate(s.pitch_maneuver_start_time, 1):
        if t < t_end:
            out.append((f"TPitManS({k})", f"the override pitch maneuver of blade {k} {_when(t)} is not modelled; "
                                          f"{later}"))
    if s.pitch_control_mode != 0 and s.pitch_control_start_time > 0:
        out.append(("TPCOn", f"pitch control starting at t = {s.pitch_control_start_time:g} s is not modelled "
                             "(the controller pitches from t = 0); set TPCOn = 0"))
    if s.airfoil_control_mode != 0:
        out.append(("AfCmode", f"airfoil control (AfCmode = {s.airfoil_control_mode}) is not modelled; set 0"))
    if s.n_blade_structural_controllers > 0:
        out.append(("NumBStC", f"{s.n_blade_structural_controllers} blade structural controller(s) (StC) are not "
                               "modelled; set NumBStC = 0"))
    if s.cable_control_mode != 0:
        out.append(("CCmode", f"cable control (CCmode = {s.cable_control_mode}) is not modelled; set 0"))
    return out
