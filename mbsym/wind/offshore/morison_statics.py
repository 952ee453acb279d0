"""HydroDyn's time-invariant Morison loads and its acceleration-proportional terms, at HydroDyn's nodes.

For a structure at rest in its undisplaced position, in still water and without wave stretching, HydroDyn v5.0.0
(read for the facts in ``Morison.f90``: ``SetMemberProperties_Cyl``, ``Morison_Init``, ``Morison_CalcOutput``,
``getElementHstLds_Mod1``, ``GetEndPlateHstLds_Cyl``, ``getMemBallastHiPt``, ``CylTaperCalc``, ``CylInertia``,
``MarineGrowthPartSegmentCyl``, ``FloodedBallastPartSegmentCyl``) puts on the nodes of :mod:`.morison_members`:

* **External hydrostatics** (``MHstLMod`` 1), element by element from the seabed cut up, with the buoyancy radii
  ``r = RMG √C_b``. A submerged element: ``F = ρg [V e_z − π (r₂² z₂ − r₁² z₁) k]`` and, about its lower node,
  ``M = ρg (V h_c + π (r₂⁴ − r₁⁴)/4) (k × e_z)`` (``V``, ``V h_c`` of the frustum), shared between its nodes with
  ``α = α₀ z₂³ / (α₀ z₂³ + (1 − α₀) z₁³)`` at node 2 (``α₀`` the frustum's centroid fraction), the moment of that
  share about node 1 removed before the split. The element crossing the still-water level: the submerged part's
  force and moment (its elliptic waterplane, straight or tapered), all at node 1 for a member's first element,
  else shared with the node below with ``α = (1 − α₀) z₁³ / ((1 − α₀) z₁³ − α₀ z₂³)``. End plates under water:
  ``F = −ρg π r² z₀ k`` at the lower end (minus at the upper) and ``M = −ρg π r⁴ sin φ / 4 ŷ`` (``ŷ`` horizontal,
  ⊥ ``k``); none at an end below the seabed. For a vertical cylinder of constant radius the sides give nothing:
  only the end plates carry buoyancy, so a pile cut by the seabed has none.
* **Filled members** (``NFillGroups``: fluid of density ``ρ_f`` up to ``FillFSLoc``): the fluid's weight (each
  element split at its middle, or at the fill level, into two part-segments lumped at their nodes with their
  centroid offsets) and its pressure, zero at the group's highest fluid point ``z_FG`` (the top of its fluid; 0 for a
  group open to the sea through a member cut by the seabed): per element ``ρ_f g π (r_mid² (z_mid − z_FG) −
  r₁² (z₁ − z_FG)) k`` at node 1 and the like at node 2, and on the end plates (at the lower end only when the
  member is not cut by the seabed, at the upper one only when it is full). Open at the seabed, a pile's fluid
  weighs nothing net: its pressure on the elements cancels its weight — except over the cut element's part below
  the seabed, whose pressure HydroDyn counts but not its weight: ``ρ_f g π r_in² (−WtrDpth − z₁)`` upward on the
  buried node and the first above it (77 kN for the IEA 15 MW monopile, whose pile reaches 0.1 m into the seabed).
* **Marine growth**: the shell between ``R`` and ``RMG`` of each half element (from the seabed), its weight at its
  node with the moment of its centroid offset; on each joint's end plates ``ρ_MG t |A_n|`` (:mod:`.strip_theory`).
  (A joint's plates take their radius and growth as :class:`~.morison_members.MorisonJoint` says: HydroDyn's, the
  other end's for a member written from its upper joint.)
* **Acceleration-proportional terms** (nodal 6 × 6 matrices ``A`` with ``F = −A (a, α)`` at the node): side added
  mass ``Δl ρ π RMG² [C_a (I − k kᵀ) + 2 C_{a,ax} |dR/dl| k kᵀ]`` on the ``AMMod = 0`` strips of the nodes
  below the still-water level, its moment ``(h k) × F`` with the strip centroid's offset ``h`` but the node's
  acceleration (so this block is not symmetric); the joints' end-plate added mass ``ρ C_{a,ax} V_n V_nᵀ / |V_n|``
  (joints under water); the fluid's and the growth's part-segments as rigid bodies (mass, centroid offset, inertia
  about the node ``I_r (I − k kᵀ) + I_l k kᵀ``), their centripetal and gyroscopic terms left out (second order in
  the rates).
"""

from __future__ import annotations

import math

import numpy as np

from ...exceptions import ParameterError
from .morison_members import MorisonFrame, MorisonMember, _equal, fill_groups
from .strip_theory import _growth_plate

__all__ = ["hydrostatic_loads", "fill_loads", "growth_loads", "nodal_mass", "joint_terms", "section_axes"]

_EZ = np.array([0.0, 0.0, 1.0])


def _cross(v) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def section_axes(k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """HydroDyn's section axes of a cylinder with axis ``k``: ``ŷ`` horizontal ⊥ ``k`` (``e_y`` for a vertical
    one) and ``ẑ = k × ŷ``, both flipped so that ``ẑ`` points up."""
    if abs(k[2]) > 0.999999:
        y = np.array([0.0, 1.0, 0.0])
    else:
        y = np.array([-k[1], k[0], 0.0]) / math.hypot(k[0], k[1])
    z = np.cross(k, y)
    return (-y, -z) if z[2] < 0.0 else (y, z)


def _taper(r1: float, r2: float, h: float) -> tuple[float, float]:
    """Volume [m³] (positive) and centroid offset from the ``r1`` end along ``h`` [m] (signed) of a frustum."""
    if _equal(r1, r2):
        return abs(math.pi * r1 * r1 * h), 0.5 * h
    if _equal(r1, 0.0):
        return abs(math.pi * r2 * r2 * h / 3.0), 0.75 * h
    slope = (r2 - r1) / h
    return (abs(math.pi / 3.0 / slope * (r2 ** 3 - r1 ** 3)),
            h * (r1 * r1 + 2 * r1 * r2 + 3 * r2 * r2) / 4.0 / (r1 * r1 + r1 * r2 + r2 * r2))


def _inertia(r1: float, r2: float, h: float, rho: float) -> tuple[float, float]:
    """Axial and radial (about the ``r1`` end) moments of inertia [kg m²] of a solid frustum, HydroDyn's formulas."""
    if _equal(r1, r2):
        return abs(0.5 * rho * math.pi * r1 ** 4 * h), abs(rho * math.pi * r1 * r1 * h * (3 * r1 * r1 + 4 * h * h) / 12)
    slope = (r2 - r1) / h
    if _equal(r1, 0.0):
        radial = rho * math.pi * (1 / (20 * slope) + 1 / (5 * slope ** 3)) * r2 ** 5
        return abs(rho * math.pi / (10 * slope) * r2 ** 5), abs(radial)
    hc = h * (r1 * r1 + 2 * r1 * r2 + 3 * r2 * r2) / 4.0 / (r1 * r1 + r1 * r2 + r2 * r2)
    tip = abs(math.pi / 20 * rho / slope * (1 + 4 / slope ** 2) * (r2 ** 5 - r1 ** 5))
    radial = abs(tip - rho / 3 / slope * math.pi * (r2 ** 3 - r1 ** 3) * (r1 / slope + 2 * hc) * r1 / slope)
    return abs(rho * math.pi / (10 * slope) * (r2 ** 5 - r1 ** 5)), radial


def _segment(r1: float, r2: float, h: float, rho: float) -> tuple[float, float, float, float]:
    """A fluid part-segment: mass [kg], centroid offset [m], axial and radial inertia [kg m²]."""
    volume, hc = _taper(r1, r2, h)
    axial, radial = _inertia(r1, r2, h, rho)
    return rho * volume, hc, axial, radial


def _shell(r1: float, r2: float, g1: float, g2: float, h: float, rho: float) -> tuple[float, float, float, float]:
    """A marine-growth part-segment between the bare radii ``r`` and the grown ``g``: as :func:`_segment`."""
    vi, ci = _taper(r1, r2, h)
    vo, co = _taper(g1, g2, h)
    mass = (vo - vi) * rho
    hc = 0.0 if _equal(mass, 0.0) else (co * vo - vi * ci) / (vo - vi)
    ao, ro = _inertia(g1, g2, h, rho)
    ai, ri = _inertia(r1, r2, h, rho)
    return mass, hc, ao - ai, ro - ri


def _body(part, k: np.ndarray) -> np.ndarray:
    """6 × 6 mass matrix at its node of a part-segment ``(m, h, I_l, I_r)`` on axis ``k`` (``F = −A (a, α)``)."""
    mass, hc, axial, radial = part
    kk = np.outer(k, k)
    arm = _cross(hc * k)
    return np.block([[mass * np.eye(3), -mass * arm], [mass * arm, radial * (np.eye(3) - kk) + axial * kk]])


def _elements(m: MorisonMember) -> range:
    """The (0-based) elements HydroDyn loads on the sides: from the one crossing the seabed up."""
    return range(max(m.floor, 1) - 1, m.n_elements)


# ---------------------------------------------------------------------------------------------- external hydrostatics
def hydrostatic_loads(frame: MorisonFrame, rho: float, gravity: float) -> np.ndarray:
    """``(n, 6)`` buoyancy of the ``MHstLMod = 1`` members at HydroDyn's nodes [N, N m] (module docstring)."""
    out = np.zeros((frame.n_nodes, 6))
    rg = rho * gravity
    for m in frame.members:
        if m.hydrostatics != 1:
            continue
        r, z, k, dl = m.buoyant, m.z, m.axis, m.dl
        for e in _elements(m):
            a, b = m.nodes[e], m.nodes[e + 1]
            r1, r2 = r[e], r[e + 1]
            alpha0 = 0.5 if _equal(r1, r2) else _taper(r1, r2, 1.0)[1]          # the frustum's centroid fraction
            if z[e] < 0.0 and z[e + 1] < 0.0:
                volume = math.pi * dl * (r1 * r1 + r1 * r2 + r2 * r2) / 3
                first = math.pi * dl * dl * (r1 * r1 + 2 * r1 * r2 + 3 * r2 * r2) / 12
                force = rg * (volume * _EZ - math.pi * (r2 * r2 * z[e + 1] - r1 * r1 * z[e]) * k)
                moment = rg * (first + 0.25 * math.pi * (r2 ** 4 - r1 ** 4)) * np.cross(k, _EZ)
                alpha = alpha0 * z[e + 1] ** 3 / (alpha0 * z[e + 1] ** 3 + (1 - alpha0) * z[e] ** 3)
                rest = moment - np.cross(k * dl, alpha * force)
                out[a] += np.r_[(1 - alpha) * force, (1 - alpha) * rest]
                out[b] += np.r_[alpha * force, alpha * rest]
            elif z[e] < 0.0 <= z[e + 1]:
                force, moment = _cut_element(m.points[e], k, z[e], z[e + 1], r[e], r[e + 1], dl, m)
                force, moment = rg * force, rg * moment
                if e == 0:
                    out[a] += np.r_[force, moment]
                    continue
                alpha = (1 - alpha0) * z[e] ** 3 / (-alpha0 * z[e + 1] ** 3 + (1 - alpha0) * z[e] ** 3)
                rest = moment + np.cross(k * dl, (1 - alpha) * force)
                out[m.nodes[e - 1]] += np.r_[(1 - alpha) * force, (1 - alpha) * rest]
                out[a] += np.r_[alpha * force, alpha * rest]
        ends = [(0, 1.0)] if m.floor == 0 else []
        if m.floor == 0 or m.end_buoyancy:
            ends.append((m.n_elements, -1.0))
        for j, sign in ends:
            out[m.nodes[j]] += sign * _end_plate(k, r[j], z[j], rg)
    return out


def _cut_element(p1, k, z1: float, z2: float, r1: float, r2: float, dl: float, m: MorisonMember):
    """Force and moment about node 1 (over ρg) of the submerged part of an element from ``z1 < 0`` to ``z2 ≥ 0``."""
    h0 = dl * z1 / (z1 - z2)
    slope = (r2 - r1) / dl
    t = np.cross(k, _EZ)
    sin_g, cos_g = float(np.linalg.norm(t)), float(k[2])
    if sin_g < 1e-4:
        t = np.array([1.0, 0.0, 0.0]) if k[2] >= 0.999999 else np.array([-k[1], k[0], 0.0]) / math.hypot(k[0], k[1])
    else:
        t = t / sin_g
    tan_g = sin_g / cos_g if cos_g > 1e-4 else math.inf
    s, rr = np.cross(t, _EZ), np.cross(t, k)
    if abs(slope) < 1e-4:
        if cos_g < 1e-4:
            raise ParameterError(f"HydroDyn member {m.ident} (line {m.line}) lies in the still-water plane.")
        a0, b0, s0 = r1 / cos_g, r1, 0.0
        vs, vrc, vhc = math.pi * r1 * r1 * h0, -0.25 * math.pi * r1 ** 4 * tan_g, \
            0.125 * math.pi * r1 * r1 * (4 * h0 * h0 + r1 * r1 * tan_g * tan_g)
    else:
        rh = r1 + h0 * slope
        c1 = 1.0 - slope * slope * tan_g * tan_g
        if c1 < 1e-4:
            raise ParameterError(f"HydroDyn member {m.ident} (line {m.line}): its wall is tangent to the still-water "
                                 "plane.")
        a0, b0 = rh / (c1 * cos_g), rh / math.sqrt(c1)
        c2 = a0 * b0 * rh * cos_g - r1 ** 3
        s0 = -rh * slope * tan_g / c1 / cos_g
        vs, vrc = math.pi * c2 / (3 * slope), -0.25 * math.pi * a0 * b0 * rh * rh * sin_g / c1
        vhc = 0.25 * math.pi * (a0 * b0 * rh * rh * cos_g / c1 - r1 ** 4 - 4.0 / 3.0 * r1 * c2) / slope ** 2
    z0 = z1 + h0 * k[2] + s0 * s[2]
    force = vs * _EZ - math.pi * a0 * b0 * z0 * _EZ + math.pi * r1 * r1 * z1 * k
    moment = (np.cross(vrc * rr + vhc * k, _EZ)
              + 0.25 * math.pi * a0 * b0 * ((s[2] * a0 * a0 + 4 * (s0 - h0 * sin_g) * z0) * t - t[2] * b0 * b0 * s)
              - 0.25 * math.pi * r1 ** 4 * (rr[2] * t - t[2] * rr))
    return force, moment


def _end_plate(k: np.ndarray, r: float, z0: float, rg: float) -> np.ndarray:
    """The pressure load on a member's end plate whose axis is ``k`` (HydroDyn adds it at the lower end, subtracts
    it at the upper): submerged ``−ρg π r² z₀ k`` and ``−ρg π r⁴ sin φ/4 ŷ``; dry nothing."""
    if z0 >= 0.0:
        return np.zeros(6)
    y, _ = section_axes(k)
    return rg * np.r_[-math.pi * r * r * z0 * k, -0.25 * math.pi * r ** 4 * math.hypot(k[0], k[1]) * y]


# ---------------------------------------------------------------------------------------------- filled members
def _fill_state(m: MorisonMember, depth: float) -> dict:
    """HydroDyn's flooding of a filled member: member status (0 none, 1 full, 2 partial), per element status, the
    partly filled element, its filled length, and the part-segments ``(m, h, I_l, I_r)`` at each element's nodes."""
    level, rho = m.fill_level, m.fill_density
    n, dl, z, rin = m.n_elements, m.dl, m.z, m.inner
    zero = (0.0, 0.0, 0.0, 0.0)
    if level >= z[-1]:
        status, filled = 1, n * dl
    elif z[0] >= level or z[-1] <= -depth:
        status, filled = 0, 0.0
    else:
        status, filled = 2, (level - z[0]) / m.axis[2]
    lower, upper, flood = [zero] * n, [zero] * n, [0] * n
    top, top_length = None, 0.0
    for e in range(n):
        i = e + 1                                         # HydroDyn's element number
        za, zb = z[e], z[e + 1]
        if status > 0 and level > za:
            if i > m.floor and level >= zb:
                mid = 0.5 * (rin[e] + rin[e + 1])
                lower[e], upper[e] = _segment(rin[e], mid, 0.5 * dl, rho), _segment(rin[e + 1], mid, -0.5 * dl, rho)
            elif i > m.floor:
                part = level - za
                mid = rin[e] + part / (zb - za) * (rin[e + 1] - rin[e])
                lower[e] = _segment(rin[e], mid, part, rho)
            elif i == m.floor:
                mid = (-m.floor_length * rin[e] + (dl + m.floor_length) * rin[e + 1]) / dl
                upper[e] = _segment(rin[e + 1], mid, m.floor_length, rho)
        if zb < -depth:
            continue
        if status > 0 and level >= zb:
            flood[e] = 1
            if _equal(level, zb) or i == n:
                top, top_length = e, dl
        elif status > 0 and za < level < zb:
            flood[e], top, top_length = 2, e, filled - e * dl
    return {"status": status, "flood": flood, "top": top, "top_length": top_length, "lower": lower, "upper": upper}


def _fill_top(m: MorisonMember, state: dict) -> float:
    """HydroDyn's highest point of a flooded member's fluid (``getMemBallastHiPt``, undisplaced)."""
    _, up = section_axes(m.axis)
    high = m.z[0] + m.inner[0] * up[2]
    if state["status"] == 1:
        high = max(high, m.z[-1] + m.inner[-1] * up[2])
    elif state["status"] == 2 and state["top"] is not None:
        e, length = state["top"], state["top_length"]
        s = length / m.dl
        r = m.inner[e] * (1 - s) + m.inner[e + 1] * s
        high = max(high, m.points[e][2] + length * m.axis[2] + r * up[2])
    return high


def fill_loads(frame: MorisonFrame, hd, rho: float, gravity: float) -> tuple[np.ndarray, np.ndarray]:
    """``(n, 6)`` weight and pressure of the filled members' fluid [N, N m] and their ``(n, 6, 6)`` mass at HydroDyn's
    nodes (module docstring)."""
    loads, mass = np.zeros((frame.n_nodes, 6)), np.zeros((frame.n_nodes, 6, 6))
    states = {i: _fill_state(m, frame.water_depth) for i, m in enumerate(frame.members) if m.fill_group is not None}
    tops = {}
    for k, _ in enumerate(fill_groups(hd, rho)):
        group = [i for i in states if frame.members[i].fill_group == k]
        if any(frame.members[i].floor > 0 for i in group):
            tops[k] = 0.0                                 # open to the sea through the seabed cut
        else:
            flooded = [_fill_top(frame.members[i], states[i]) for i in group if states[i]["status"] > 0]
            tops[k] = max(flooded) if flooded else 0.0
    for i, state in states.items():
        m = frame.members[i]
        if state["status"] == 0:
            continue
        top, k, rin, z, dl = tops[m.fill_group], m.axis, m.inner, m.z, m.dl
        rg = m.fill_density * gravity
        tilt = np.cross(k, _EZ)
        for e in _elements(m):
            if state["flood"][e] == 0:
                continue
            a, b = m.nodes[e], m.nodes[e + 1]
            low, high = state["lower"][e], state["upper"][e]
            mass[a] += _body(low, k)
            mass[b] += _body(high, k)
            if state["flood"][e] == 1:
                zmid, rmid = 0.5 * (z[e] + z[e + 1]), 0.5 * (rin[e] + rin[e + 1])
            else:
                s = state["top_length"] / dl
                zmid, rmid = z[e] + state["top_length"] * k[2], rin[e] * (1 - s) + rin[e + 1] * s
            f1 = -gravity * low[0] * _EZ + rg * math.pi * (rmid ** 2 * (zmid - top) - rin[e] ** 2 * (z[e] - top)) * k
            m1 = -(gravity * low[0] * low[1] + rg * 0.25 * math.pi * (rmid ** 4 - rin[e] ** 4)) * tilt
            if state["flood"][e] == 1:
                f2 = -gravity * high[0] * _EZ + rg * math.pi * (rin[e + 1] ** 2 * (z[e + 1] - top)
                                                                 - rmid ** 2 * (zmid - top)) * k
                m2 = -(gravity * high[0] * high[1] + rg * 0.25 * math.pi * (rin[e + 1] ** 4 - rmid ** 4)) * tilt
                loads[b] += np.r_[f2, m2]
            elif e == state["top"]:
                f1 = f1 + rg * math.pi * rmid ** 2 * (top - zmid) * k
                m1 = m1 + rg * 0.25 * math.pi * rmid ** 4 * tilt
            loads[a] += np.r_[f1, m1]
        if m.floor == 0:
            loads[m.nodes[0]] -= rg * np.r_[math.pi * rin[0] ** 2 * (top - z[0]) * k,
                                            0.25 * math.pi * rin[0] ** 4 * tilt]
        if m.floor < m.n_elements + 1 and state["status"] == 1:
            loads[m.nodes[-1]] += rg * np.r_[math.pi * rin[-1] ** 2 * (top - z[-1]) * k,
                                             0.25 * math.pi * rin[-1] ** 4 * tilt]
    return loads, mass


# ---------------------------------------------------------------------------------------------- marine growth
def _growth_parts(m: MorisonMember) -> tuple[list, list]:
    """The growth's part-segments ``(m, h, I_l, I_r)`` lumped at each element's lower and upper node."""
    zero = (0.0, 0.0, 0.0, 0.0)
    lower, upper = [zero] * m.n_elements, [zero] * m.n_elements
    r, g, rho, dl = m.bare, m.radius, m.growth_density, m.dl
    for e in range(m.n_elements):
        if e + 1 > m.floor:
            mid, gmid = 0.5 * (r[e] + r[e + 1]), 0.5 * (g[e] + g[e + 1])
            lower[e] = _shell(r[e], mid, g[e], gmid, 0.5 * dl, rho[e])
            upper[e] = _shell(r[e + 1], mid, g[e + 1], gmid, -0.5 * dl, rho[e])
        elif e + 1 == m.floor:
            h = m.floor_length
            mid, gmid = (-h * r[e] + (dl + h) * r[e + 1]) / dl, (-h * g[e] + (dl + h) * g[e + 1]) / dl
            upper[e] = _shell(r[e + 1], mid, g[e + 1], gmid, h, rho[e])
    return lower, upper


def growth_loads(frame: MorisonFrame, gravity: float) -> tuple[np.ndarray, np.ndarray]:
    """``(n, 6)`` weight of the marine growth [N, N m] and its ``(n, 6, 6)`` mass at HydroDyn's nodes: the members'
    sides (from the seabed) and the joints' end plates (joints above the seabed)."""
    loads, mass = np.zeros((frame.n_nodes, 6)), np.zeros((frame.n_nodes, 6, 6))
    for m in frame.members:
        if not np.any(m.growth_density > 0.0):
            continue
        lower, upper = _growth_parts(m)
        tilt = np.cross(m.axis, _EZ)
        for e in _elements(m):
            for node, part in ((m.nodes[e], lower[e]), (m.nodes[e + 1], upper[e])):
                loads[node] += np.r_[-part[0] * gravity * _EZ, -part[0] * gravity * part[1] * tilt]
                mass[node] += _body(part, m.axis)
    for joint in frame.joints:
        if joint.position[2] < -frame.water_depth or not joint.ends:
            continue
        plates = [(sign * frame.members[i].axis, frame.members[i].radius[j], frame.members[i].growth[j],
                   frame.members[i].growth_density[j]) for i, j, sign in joint.ends]
        area = sum(math.pi * r ** 2 * n for n, r, _, _ in plates)
        block, weight, _ = _growth_plate(plates, area, np.zeros(3))
        loads[joint.node, 2] -= weight * gravity
        mass[joint.node] += block
    return loads, mass


# ---------------------------------------------------------------------------------------------- added mass
def joint_terms(frame: MorisonFrame, rho: float) -> list[tuple[int, np.ndarray, np.ndarray, np.ndarray, float, int]]:
    """Per joint above the seabed with members: ``(node, A_end (3, 3) [kg], pressure (3,) [m²], normal (3,), drag [m²],
    AxFDMod)``: the end plates' added mass ``ρ C_{a,ax} V_n V_nᵀ/|V_n|``, ``−C_{p,ax} A_n`` and the end drag's unit
    normal and ``C_{d,ax} |A_n|``."""
    out = []
    for joint in frame.joints:
        if joint.position[2] < -frame.water_depth or not joint.ends:
            continue
        cd, ca, cp, mode = joint.axial
        an = sum(sign * math.pi * frame.members[i].radius[j] ** 2 * frame.members[i].axis for i, j, sign in joint.ends)
        vn = sum(sign * 2 * math.pi / 3 * frame.members[i].radius[j] ** 3 * frame.members[i].axis
                 for i, j, sign in joint.ends)
        size, volume = float(np.linalg.norm(an)), float(np.linalg.norm(vn))
        added = rho * ca / volume * np.outer(vn, vn) if volume > 0.0 else np.zeros((3, 3))
        normal = an / size if not _equal(size * size, 0.0) else np.zeros(3)
        out.append((joint.node, added, -cp * an, normal, cd * size if size * size > 0 else 0.0, mode))
    return out


def nodal_mass(frame: MorisonFrame, rho: float) -> np.ndarray:
    """``(n, 6, 6)`` side and end-plate added mass at HydroDyn's nodes [kg, kg m] (``AMMod = 0``; module docstring)."""
    mass = np.zeros((frame.n_nodes, 6, 6))
    for m in frame.members:
        length, offset = m.strips(added_mass=True)
        slope, _ = m.slopes()
        kk = np.outer(m.axis, m.axis)
        c = m.coefficients
        for j in np.flatnonzero(length > 0.0):
            am = rho * math.pi * m.radius[j] ** 2 * (c["Ca"][j] * (np.eye(3) - kk) + 2 * c["AxCa"][j] * slope[j] * kk)
            mass[m.nodes[j], :3, :3] += length[j] * am
            mass[m.nodes[j], 3:, :3] += length[j] * _cross(offset[j] * m.axis) @ am
    for node, added, *_ in joint_terms(frame, rho):
        if frame.positions[node][2] <= 0.0:
            mass[node, :3, :3] += added
    return mass
