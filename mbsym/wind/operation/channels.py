"""OpenFAST output channels of an operating turbine: names and units as in OpenFAST's outputs.

The structural channels of :mod:`mbsym.wind.structure.channels` (``Q_*``, ``RotSpeed`` [rpm],
``GenSpeed`` [rpm], ``BldPitch<k>`` [deg], ``TTDspFA`` [m], ...), then:

=============  ======  ==================================================================
channel        unit    definition
=============  ======  ==================================================================
Wind1VelX      m/s     hub-height wind (input)
RtVAvgxh       m/s     relative wind along the shaft ``U_rel`` (AeroDyn's disk average)
RtTSR          -       ``Ω R / U_rel`` (``U_rel`` floored at ``RotorAero.u_min``)
RtAeroCp/Ct/Cq -       coefficients of the applied loads referred to ``U_rel``
RtAeroFxh      N       aerodynamic thrust applied to the hub (along the shaft)
RtAeroMxh      N-m     aerodynamic torque applied to the hub (about the shaft)
RtAeroPwr      W       ``Ω · RtAeroMxh``
GenTq          kN-m    generator torque (actuator state, high-speed shaft)
GenPwr         kW      ``η · GenTq · ω_gen`` (electrical power)
RotTorq        kN-m    low-speed-shaft torque: with DrTrDOF the drivetrain spring and damper
                       torque; with GenDOF alone ``N (GenTq + J_gen α_gen·c₁)`` (the torque
                       the generator needs, α_gen its absolute angular acceleration); with
                       the speed prescribed, RtAeroMxh
RotPwr         kW      ``RotTorq · Ω``
RotThrust      kN      low-speed-shaft axial force, as ElastoDyn: aerodynamic thrust plus the
                       rotor's weight along the (deflected) shaft minus its inertia force,
                       ``T + m_rotor (g − a_apex)·c₁``
TwrBsMxt       kN-m    tower-base roll moment: minus the reaction of the locked base rotation
                       about x (equations of the same graph)
TwrBsMyt       kN-m    tower-base pitch (fore-aft) moment: minus the reaction about y
YawBrTAxp/yp   m/s^2   tower-top acceleration along the yaw bearing's x and y axes
=============  ======  ==================================================================

With ``OperatingTurbine(..., load_channels=True)`` the structure also has the locked joints of the
low-speed shaft and the yaw bearing, and these channels follow (:mod:`mbsym.wind.structure.load_cuts`):

=============  ======  ==================================================================
LSShftFxa      kN      rotor's force on the shaft along it (ElastoDyn's ``RotThrust``, which
                       then equals it: exact, with the inertia of every blade node)
LSShftFys/Fzs  kN      rotor's shear force on the shaft, nonrotating shaft axes (y lateral,
                       z up in the shaft's vertical plane)
YawBrFxp …     kN      force of nacelle, generator and rotor on the tower top (tower-top axes
YawBrFzp               x, y, z: deflected, not yawed)
YawBrMxp …     kN-m    their moment about the tower-top point (roll, pitch, yaw)
YawBrMzp
=============  ======  ==================================================================

A floating turbine (``model.platform``) adds its platform's channels (``HydroFxi … HydroMzi`` [N, N-m],
``FAIRTEN1..n`` [N], ``Wave1Elev`` [m]: :meth:`~mbsym.wind.offshore.operating.FloatingPlatform.channel_rows`)
and ``NcIMURAys`` [deg/s^2], the nacelle's angular acceleration about the tower-top (shaft) lateral axis
(ElastoDyn's nacelle IMU channel; ServoDyn passes it to ROSCO's floating feedback as record 83).

With AeroDyn's nacelle drag (``OperatingTurbine(nacelle_drag=...)``, :mod:`mbsym.wind.aero.nacelle`): ``NcFdx …
NcFdz`` [N] and ``NcMdx … NcMdz`` [N-m], its force at the yaw bearing and moment about it in nacelle axes, and
``NcFxi … NcMzi``, the same in ground axes (AeroDyn's total nacelle load: no buoyancy here).

Signs follow OpenFAST: a downwind thrust gives positive ``TwrBsMyt``; the rotor's reaction
torque on the nacelle gives positive ``TwrBsMxt``.
"""

from __future__ import annotations

import math
from typing import Any

import casadi as ca

from ..structure.elastodyn_nodes import rotor_mass_properties
from ..structure.gearbox import generator_torque_at_shaft, has_losses
from ..aero.nacelle import NACELLE_CHANNELS
from ..structure.load_cuts import reaction_rows

__all__ = ["channel_rows", "OPERATION_CHANNELS"]

#: The channels this module adds to the structural ones, with their units.
OPERATION_CHANNELS = {
    "Wind1VelX": "m/s", "RtVAvgxh": "m/s", "RtTSR": "-", "RtAeroCp": "-", "RtAeroCt": "-", "RtAeroCq": "-",
    "RtAeroFxh": "N", "RtAeroMxh": "N-m", "RtAeroPwr": "W", "GenTq": "kN-m", "GenPwr": "kW", "RotTorq": "kN-m",
    "RotPwr": "kW", "RotThrust": "kN", "TwrBsMxt": "kN-m", "TwrBsMyt": "kN-m", "YawBrTAxp": "m/s^2",
    "YawBrTAyp": "m/s^2",
}


def channel_rows(g) -> list[tuple[str, str, Any]]:
    """``(name, unit, expression)`` of every channel of the composed graph ``g`` (:class:`.compose.Graph`)."""
    model = g.model
    structural = model.structure.output_function()
    y_s = structural.function(ca.vertcat(g.q, g.qd), g.u_s, g.p_s)
    rows = [(n, u, y_s[i]) for i, (n, u) in enumerate(zip(structural.names, structural.units))]
    ops = _operation(g)
    rows += [(n, OPERATION_CHANNELS[n], ops[n]) for n in OPERATION_CHANNELS]
    if model.aero == "blade":
        from .blade_channels import blade_channel_rows

        rows += blade_channel_rows(g)
    rows += [r for r in reaction_rows(g.eom.locked, reactions(g)) if r[0].startswith(("LSShft", "YawBr"))]
    if g.platform is not None:
        rows += _floating_rows(g)
    drag = getattr(g, "nacelle_drag", None)
    if drag is not None:                                            # AeroDyn's NcFd*, NcMd*, NcF*i, NcM*i
        values = ca.vertcat(drag["force"], drag["moment"], ca.mtimes(drag["R"], drag["force"]),
                            ca.mtimes(drag["R"], drag["moment"]))
        rows += [(n, "N" if n[2] == "F" else "N-m", values[i]) for i, n in enumerate(NACELLE_CHANNELS)]
    if getattr(model, "hss_brake", None) is not None:               # ElastoDyn's HSSBrTq: the brake's torque
        rows.append(("HSSBrTq", "kN-m", g.brake_torque / 1e3))
    return rows


def _floating_rows(g) -> list[tuple[str, str, Any]]:
    """The platform's channels and the nacelle's pitching acceleration ``NcIMURAys`` [deg/s^2]."""
    ap = ca.vertcat(*[g.qdd[i] if i is not None else 0.0 for i in g.platform_index])
    rows = list(g.platform.channel_rows(g.platform_terms, ap))
    yb = g.kinematics_with_accelerations("yaw_bearing")
    rows.append(("NcIMURAys", "deg/s^2", 180.0 / math.pi * ca.dot(yb["wd"], yb["R"][:, 1])))
    return rows


def reactions(g) -> Any:
    """The reactions of the structure's locked coordinates (``eom.locked``) in the graph ``g``, computed once."""
    lam = getattr(g, "_channel_reactions", None)
    if lam is None:
        lam = g.eom.functions.reactions(g.q, g.qd, g.qdd, g.u_s, g.p_s)
        g._channel_reactions = lam
    return lam


def _operation(g) -> dict[str, Any]:
    model, eom, X, P = g.model, g.eom, g.X, g.P
    R = model.rotor.tip_radius if model.aero == "blade" else model.rotor.radius
    u = g.aero["u"]                                       # floored relative wind [m/s]
    omega = g.rotor_speed
    dyn = 0.5 * P["air_density"] * math.pi * R**2 * u**2
    ct, cq = g.thrust / dyn, g.torque / (dyn * R)
    tsr = omega * R / u
    gen_tq = X["GenTq"]
    out = {"Wind1VelX": g.hub_wind_x, "RtVAvgxh": g.u_rel, "RtTSR": tsr, "RtAeroCp": tsr * cq, "RtAeroCt": ct,
           "RtAeroCq": cq, "RtAeroFxh": g.thrust, "RtAeroMxh": g.torque, "RtAeroPwr": omega * g.torque,
           "GenTq": gen_tq / 1e3, "GenPwr": P["generator_efficiency"] * gen_tq * g.generator_speed / 1e3}
    lss = _lss_torque(g)
    out.update(RotTorq=lss / 1e3, RotPwr=lss * omega / 1e3, RotThrust=_lss_thrust(g) / 1e3)
    tower = dict((n, v) for n, _, v in reaction_rows(eom.locked, reactions(g)) if n.startswith("TwrBs"))
    out.update(TwrBsMxt=tower["TwrBsMxt"], TwrBsMyt=tower["TwrBsMyt"])
    yb = g.kinematics_with_accelerations("yaw_bearing")
    out.update(YawBrTAxp=ca.dot(yb["a"], yb["R"][:, 0]), YawBrTAyp=ca.dot(yb["a"], yb["R"][:, 1]))
    return out


def _lss_torque(g) -> Any:
    """Low-speed-shaft torque [N m] (see the module docstring)."""
    model, eom, P = g.model, g.eom, g.P
    coords = eom.coordinates
    if "DrTr" in coords:
        i = coords.index("DrTr")
        return P["drivetrain_stiffness"] * g.q[i] + P["drivetrain_damping"] * g.qd[i]
    if model.spins_freely:                 # the generator's balance: N (T_gen + J_gen α_gen), α about the shaft
        gen = g.kinematics_with_accelerations("generator")
        inertia, torque = P["generator_inertia"], g.X["GenTq"] + getattr(g, "brake_torque", 0.0)   # + HSS brake
        if has_losses(model.structure):    # through the lossy gearbox (structure.gearbox, rigid drivetrain)
            eta = float(model.turbine.gearbox_efficiency)
            inertia, torque = inertia / eta, generator_torque_at_shaft(torque, eta)
        return model.gearbox_ratio * (torque + inertia * ca.dot(gen["wd"], g.shaft_axis))
    return g.torque


def _lss_thrust(g) -> Any:
    """Low-speed-shaft axial force [N]: thrust plus the rotor's weight and inertia force along the shaft.

    With the shaft's locked joints (``load_channels=True``) the exact reaction (ElastoDyn's ``LSShftFxa``);
    otherwise the rotor as one mass at the apex.
    """
    rows = dict((n, v) for n, _, v in reaction_rows(g.eom.locked, reactions(g)) if n == "LSShftFxa")
    if rows:
        return 1e3 * rows["LSShftFxa"]
    model, P = g.model, g.P
    mass = P["hub_mass"] + float(sum(rotor_mass_properties(model.turbine).blade_mass))
    apex = g.kinematics_with_accelerations("hub")
    gravity = ca.vertcat(0.0, 0.0, -P["gravity"])
    return g.thrust + mass * ca.dot(gravity - apex["a"], g.shaft_axis)
