"""OpenFAST output channels of a :class:`~mbsym.wind.structure.turbine.TurbineModel`.

Names, units and signs follow ElastoDyn (docs/elastodyn_notes.md §6): ``Q_*``,
``QD_*``, ``QD2_*`` for every enabled DOF (``Q_TSS*`` is the negative of our
side-side coordinate, ``Q_GeAz`` is wrapped to [0, 2π)), ``Azimuth`` [deg],
``RotSpeed`` and ``GenSpeed`` [rpm], ``NacYaw`` [deg], tower-top displacements
``TTDspFA``, ``TTDspSS`` (platform axes), ``TTDspAx`` (ElastoDyn's axial drop) and
``YawBrTDxp``, ``YawBrTDyp`` (deflected tower-top axes), the platform motions
``PtfmSurge`` … ``PtfmYaw``, and per blade ``k``: ``BldPitch<k>`` [deg], the tip
deflections relative to the undeflected tip in the coned frame ``i``, ``OoPDefl<k>``
(= ``TipDxc<k>``, out of plane), ``IPDefl<k>`` (= ``TipDyc<k>``, in plane), ``TipDzc<k>``
(axial), and in the pitched frame ``j``, ``TipDxb<k>``, ``TipDyb<k>`` [m]
(notes §6: twisted tip shapes, then the pitch rotation; zero for rigid blades).

:func:`output_function` returns a CasADi Function ``(x, u, p) -> y`` (accelerations
from the model's rhs) with the channel names and units alongside.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...bodies.flexible import FlexibleBody
from ...kinematics import elastodyn_rotation
from .dofs import blade1_azimuth, blade_dof

__all__ = ["Channels", "output_function", "channel_function", "channel_units"]

_TRANSLATIONS = {"Sg", "Sw", "Hv", "TFA1", "TSS1", "TFA2", "TSS2"}
_RPM = 30.0 / np.pi
_DEG = 180.0 / np.pi


@dataclass(frozen=True)
class Channels:
    """A CasADi output Function with OpenFAST channel names and units."""

    function: ca.Function          # (x, u, p) -> y (n_y,)
    names: tuple[str, ...]
    units: tuple[str, ...]

    @property
    def headers(self) -> tuple[str, ...]:
        """``<channel>_[<unit>]`` as in OpenFAST's CSV output."""
        return tuple(f"{n}_[{u}]" for n, u in zip(self.names, self.units))


def channel_units(name: str) -> str:
    """Unit of a DOF channel ``Q_<dof>``, ``QD_<dof>`` or ``QD2_<dof>``."""
    prefix, dof = name.split("_", 1)
    base = "m" if dof in _TRANSLATIONS or blade_dof(dof) else "rad"
    return {"Q": base, "QD": f"{base}/s", "QD2": f"{base}/s^2"}[prefix]


def output_function(model) -> Channels:
    """Output channels of a TurbineModel as a CasADi Function of (x, u, p)."""
    eom = model.eom
    f_y, names, units = channel_function(model)
    x = ca.MX.sym("x", eom.n_x)
    u = ca.MX.sym("u", eom.n_u)
    p = ca.MX.sym("p", eom.n_p)
    n = eom.n_q
    xd = eom.functions.rhs(x, u, p)
    f = ca.Function("outputs", [x, u, p], [f_y(x[:n], x[n:], xd[n:], u, p)], ["x", "u", "p"], ["y"])
    return Channels(f, names, units)


def channel_function(model) -> tuple[ca.Function, tuple[str, ...], tuple[str, ...]]:
    """The channels as an SX Function of ``(q, qd, qdd, u, p)`` (accelerations given: a model that adds to the
    structure's mass matrix, e.g. a floating platform's A∞, passes its own), with their names and units."""
    eom = model.eom
    d = eom.symbolic
    q, qd, qdd = d.q, d.qd, d.qdd
    val = {n: q[i] for i, n in enumerate(eom.coordinates)}
    vel = {n: qd[i] for i, n in enumerate(eom.coordinates)}
    acc = {n: qdd[i] for i, n in enumerate(eom.coordinates)}
    rows: list[tuple[str, str, ca.SX]] = []
    for n in eom.coordinates:
        sign = -1.0 if n.startswith("TSS") else 1.0       # ElastoDyn's internal SS DOF points along -y
        value = ca.fmod(val[n], 2 * np.pi) if n == "GeAz" else sign * val[n]
        for prefix, expr in (("Q", value), ("QD", sign * vel[n]), ("QD2", sign * acc[n])):
            rows.append((f"{prefix}_{n}", channel_units(f"{prefix}_{n}"), expr))
    rows += _rotor_rows(model, val, vel, d)
    rows += _tower_rows(model, val)
    rows += _platform_rows(model, val)
    rows += _blade_rows(model, val, d)
    names, units, exprs = zip(*rows)
    y = ca.vertcat(*exprs)
    return ca.Function("outputs_sx", [q, qd, qdd, d.u, d.p], [y]), tuple(names), tuple(units)


def _input(d, name: str):
    names = d.names["input"]
    return d.u[names.index(name)] if name in names else None


def _rotor_rows(model, val, vel, d) -> list:
    t = model.turbine
    geaz = val.get("GeAz", _input(d, "GeAz"))
    geaz_d = vel.get("GeAz", _input(d, "GeAz_d"))
    if geaz is None:                    # rotor held at its initial azimuth
        geaz, geaz_d = ca.SX(model.initial_generator_azimuth()), ca.SX(0.0)
    rotor = geaz + val.get("DrTr", 0.0)
    rotor_d = geaz_d + vel.get("DrTr", 0.0)
    azimuth = ca.fmod(blade1_azimuth(rotor, t.azimuth_blade1_up), 2 * np.pi)
    azimuth = ca.if_else(azimuth < 0, azimuth + 2 * np.pi, azimuth)
    yaw = val.get("Yaw", t.initial_conditions.nacelle_yaw)
    return [("Azimuth", "deg", _DEG * azimuth), ("RotSpeed", "rpm", _RPM * rotor_d),
            ("GenSpeed", "rpm", _RPM * abs(t.gearbox_ratio) * geaz_d), ("NacYaw", "deg", _DEG * ca.SX(yaw))]


def _tip(body, val):
    """Tip displacement (x, y, z) of a flexible body in its own axes, from its shape integrals.

    ``end_displacement`` per coordinate, and the axial shortening ``-1/2 qᵀ Ax_tip q`` with
    ``Ax_tip = kg_tip[z]`` (:func:`mbsym.beam.lumped.lumped_shape_integrals`); the body's
    coordinates are looked up by name in ``val``.
    """
    sid = body.sid
    qe = ca.vertcat(*[val[c.name()] for c in body.elastic_coordinates])
    xy = ca.DM(np.asarray(sid.end_displacement, dtype=float)) @ qe
    drop = -0.5 * qe.T @ ca.DM(np.asarray(sid.kg_tip[2], dtype=float)) @ qe
    return xy[0], xy[1], drop, qe


def _tower_rows(model, val) -> list:
    """Tower-top displacements in platform axes and in the deflected tower-top axes."""
    tower = model.bodies["tower"]
    if not isinstance(tower, FlexibleBody):     # rigid tower
        zero = ca.SX(0.0)
        return [("TTDspFA", "m", zero), ("TTDspSS", "m", zero), ("TTDspAx", "m", zero),
                ("YawBrTDxp", "m", zero), ("YawBrTDyp", "m", zero)]
    fa, ss, drop, qe = _tip(tower, val)
    R = elastodyn_rotation(ca.DM(np.asarray(tower.sid.end_rotation)) @ qe)
    r = ca.vertcat(fa, ss, drop)
    return [("TTDspFA", "m", fa), ("TTDspSS", "m", ss), ("TTDspAx", "m", drop),
            ("YawBrTDxp", "m", ca.dot(r, R[:, 0])), ("YawBrTDyp", "m", ca.dot(r, R[:, 1]))]


def _platform_rows(model, val) -> list:
    ic = model.turbine.initial_conditions
    init = {"Sg": ic.platform_surge, "Sw": ic.platform_sway, "Hv": ic.platform_heave,
            "R": ic.platform_roll, "P": ic.platform_pitch, "Y": ic.platform_yaw}
    rows = []
    for dof, name, scale, unit in (("Sg", "PtfmSurge", 1.0, "m"), ("Sw", "PtfmSway", 1.0, "m"),
                                   ("Hv", "PtfmHeave", 1.0, "m"), ("R", "PtfmRoll", _DEG, "deg"),
                                   ("P", "PtfmPitch", _DEG, "deg"), ("Y", "PtfmYaw", _DEG, "deg")):
        rows.append((name, unit, scale * ca.SX(val.get(dof, init[dof]))))
    return rows


def _blade_rows(model, val, d) -> list:
    """Pitch and tip deflections of every blade (notes §6), ElastoDyn's names and signs.

    The tip (j1, j2, j3) displacements are those of the blade bodies' shape integrals
    (ElastoDyn's twisted tip shapes and ``AxRedBld`` at the tip).
    """
    t = model.turbine
    pitch_input = _input(d, "BlPitch")
    rows = []
    for k in range(t.number_of_blades):
        own = _input(d, f"BlPitch{k + 1}")                 # individual pitch (pitch_input="individual")
        pitch = own if own is not None else pitch_input if pitch_input is not None else \
            ca.SX(float(t.initial_conditions.blade_pitch[k]))
        blade = model.bodies[f"blade{k + 1}"]
        if isinstance(blade, FlexibleBody):
            x, y, z, _ = _tip(blade, val)
        else:                                       # rigid blade
            x = y = z = ca.SX(0.0)
        c, s = ca.cos(pitch), ca.sin(pitch)
        oop, ip = x * c + y * s, -x * s + y * c
        n = k + 1
        rows += [(f"BldPitch{n}", "deg", _DEG * pitch), (f"OoPDefl{n}", "m", oop), (f"IPDefl{n}", "m", ip),
                 (f"TipDxc{n}", "m", oop), (f"TipDyc{n}", "m", ip), (f"TipDzc{n}", "m", z),
                 (f"TipDxb{n}", "m", x), (f"TipDyb{n}", "m", y)]
    return rows
