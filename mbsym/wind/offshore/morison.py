"""Viscous drag on a floating platform's Morison members, as HydroDyn v5 computes it (``NMembers > 0``).

HydroDyn's Morison members are cylinders between joints. Every member gets its **viscous drag** from strip theory;
a member modelled by potential flow (``PropPot = TRUE``) only that (its buoyancy, added mass and wave inertia are in
the WAMIT data), one that is not (``PropPot = FALSE``) also those, from :mod:`.strip_theory`. This module models
the drag in still water and in first-order waves, with HydroDyn v5.0.0's conventions (read for the
facts in ``Morison.f90``: ``Morison_GenerateSimulationNodes``, ``SetMemberProperties_Cyl``, ``Morison_CalcOutput``,
``LumpDistrHydroLoads``):

* **Strips.** A member of length ``L`` from joint 1 to joint 2 is cut into ``N = ⌈L / MDivSize⌉`` equal elements
  ``dl``; its ``N + 1`` nodes carry the radius ``R`` linear from ``PropD1/2`` to ``PropD2/2`` plus the marine
  growth's thickness at their height (``SetNodeMG``: linear in the ``MGDpth`` table, zero outside it) and the
  coefficients of the member's table (``MCoefMod`` 1: ``SimplCd``, ``SimplAxCd``; 2: the depth-based table at their
  height, as ``SetDepthBasedCoefs_Cyl`` reads it; 3: ``MemberCd1 → MemberCd2``, ``MemberAxCd1 → 2``, linear along the
  member), the ``…MG`` coefficients where they have growth. (HydroDyn gives a potential-flow member's marine growth
  no mass or weight.) A node is in the water when its **undisplaced** height is ``z ≤ 0`` (still-water level;
  HydroDyn's ``WaveStMod = 0``). Each node takes half of each neighbouring element where both ends are wet, the
  wet part ``dl · z_i / (z_i − z_j)`` of an element that crosses the surface, nothing of a dry one: its strip
  ``Δl = Δl_left + Δl_right`` with its centroid ``h = (Δl_right − Δl_left)/2`` along the member's axis ``k``.
* **Drag per unit length** of the relative flow ``v = u_water − ṙ`` (``ṙ`` the node's velocity on the moving
  platform, at its displaced position; ``u_water = 0`` in still water), across the member
  ``v_n = (I − k kᵀ) v`` and along it ``v_a = k·v``:

      f = ½ ρ C_d D |v_n| v_n + ½ ρ C_{d,ax} π R |dR/dl| |v_a| v_a k,

  the second term the axial drag of a tapered member (zero for a straight one; ``dR/dl`` averaged over the node's
  two elements). ``k`` is the member's **undisplaced** axis (HydroDyn keeps it). The strip carries
  ``F = f Δl`` at the node and ``(h k) × F``.
* **End plates.** At a joint (above the seabed, ``z ≤ 0``) the members meeting there expose ``A n = Σ ± π R² k``
  (``−`` where a member starts, ``+`` where it ends: the outward normals; members in line cancel). With the joint's
  axial coefficients (``JointAxID`` → ``AxCd``, ``AxFDMod``) and ``v_n = v·n``:
  ``F = ¼ ρ C_{d,ax} A |v_n| v_n n`` (``AxFDMod`` 0) or ``½ ρ C_{d,ax} A |v_n| max(v_n, 0) n`` (1, drag only
  while the flow leaves the plate).

The loads are summed about the displaced platform reference point in inertial axes, as the other platform loads
(:class:`~.platform.PlatformHydrodynamics`), and enter HydroDyn's totals ``HydroFxi … HydroMzi``. The node
velocity is ``v + ω × (R p)`` with ``(v, ω)`` the reference point's velocity and angular velocity in inertial
axes (HydroDyn's mesh velocities: the operating turbine passes the Euler rates' ``ω``, :func:`~._casadi.body_motion`).

**In waves** the water's velocity ``u_water`` at every strip node and end plate is SeaState's first-order
kinematics at its undisplaced position (``WaveDisp = 0``; zero above the still-water level), read off SeaState's
grid as HydroDyn reads it (:mod:`.wave_kinematics`); the model takes it as inputs (:meth:`MorisonDrag.load`'s
``flow``), fed from tables like the excitation. **A current** (SeaState's ``CurrMod = 1``, :mod:`.current`) is
steady: read off the same grid at the same points, it is a constant part of ``u_water``
(:attr:`MorisonDrag.current`), in still water and in waves.

**Refused** (:func:`morison_problems`): rectangular members (``MSecGeom = 2``), filled members (``NFillGroups``:
their ballast), the end drag's high-pass filter (``AxVnCOff > 0``), SeaState's user current (``CurrMod = 2``),
waves or a current at the members' displaced positions (``WaveDisp = 1``), waves with second-order kinematics
(``WvDiffQTF``, ``WvSumQTF``), wave stretching (``WaveStMod > 0``), members below the seabed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ...exceptions import ParameterError
from ._casadi import _in, _out, euler_zyx
from .current import current_problems

__all__ = ["MorisonDrag", "morison_drag", "morison_problems"]

_EPS = 1e-6          # m/s: |v| as sqrt(v·v + ε²), so the drag stays differentiable at rest (bias ≤ 1e-6 m/s)


@dataclass(frozen=True, eq=False)
class MorisonDrag:
    """The wet strips and end plates of a platform's members (module docstring), SI units.

    Attributes
    ----------
    points : ndarray (n, 3)
        Strip nodes, platform axes relative to the reference point (= inertial axes undisplaced) [m].
    axis : ndarray (n, 3)
        Unit member axis ``k`` of each node (undisplaced, inertial).
    length, offset : ndarray (n,)
        Wetted strip length ``Δl`` and its centroid's offset ``h`` along ``k`` [m].
    drag : ndarray (n,)
        ``C_d D`` [m].
    taper : ndarray (n,)
        ``C_{d,ax} π R |dR/dl|`` [m].
    end_points, end_normals : ndarray (m, 3)
        Joints with an exposed end plate and its outward unit normal.
    end_drag : ndarray (m,)
        ``C_{d,ax} A`` [m²].
    end_one_sided : ndarray of bool (m,)
        ``AxFDMod = 1``.
    water_density : float
        [kg/m³].
    reference : ndarray (3,)
        The platform reference point's undisplaced position [m] (:attr:`flow_points` are absolute).
    current : ndarray (n_flow, 3) or None
        SeaState's steady current at :meth:`flow_points` [m/s] (:mod:`.current`), added to the water's velocity;
        None: no current.
    """

    points: np.ndarray
    axis: np.ndarray
    length: np.ndarray
    offset: np.ndarray
    drag: np.ndarray
    taper: np.ndarray
    end_points: np.ndarray
    end_normals: np.ndarray
    end_drag: np.ndarray
    end_one_sided: np.ndarray
    water_density: float
    reference: np.ndarray = field(default_factory=lambda: np.zeros(3))
    current: np.ndarray | None = None

    @property
    def n_nodes(self) -> int:
        """Wet strip nodes."""
        return int(self.length.size)

    @property
    def n_flow(self) -> int:
        """Points where the water's velocity enters: the strip nodes, then the end plates."""
        return self.n_nodes + int(self.end_drag.size)

    def flow_points(self) -> np.ndarray:
        """``(n_flow, 3)`` undisplaced positions [m] of the strip nodes, then the end plates (inertial, z from the
        still-water level): where HydroDyn reads the waves' kinematics (``WaveDisp = 0``)."""
        return np.vstack([self.points, self.end_points]) + np.asarray(self.reference, dtype=float)

    def load(self, q, qd, flow=None):
        """The drag at the reference point, inertial axes [N, N m] (numbers → numpy, SX/MX → expression).

        Parameters
        ----------
        q, qd : array_like or casadi (6)
            Platform DOFs (surge … yaw) [m, rad] and their rates [m/s, rad/s].
        flow : array_like or casadi (3 n_flow), optional
            The waves' velocity [m/s] at :meth:`flow_points` (x, y, z of each in turn); default still water.
            :attr:`current` is added to it.
        """
        x, v = _in(q, 6, "q"), _in(qd, 6, "qd")
        water = None if flow is None else _in(flow, 3 * self.n_flow, "flow")
        if self.current is not None:
            steady = ca.DM(np.asarray(self.current, dtype=float).reshape(-1))
            water = steady if water is None else water + steady
        rot = euler_zyx(x[3:6])
        force = moment = 0.0 * x[0:3]
        rho = self.water_density
        for k in range(self.n_nodes):
            arm = ca.mtimes(rot, ca.DM(self.points[k]))
            rel = -(v[0:3] + ca.cross(v[3:6], arm))
            if water is not None:
                rel = rel + water[3 * k:3 * k + 3]
            axis = ca.DM(self.axis[k])
            along = ca.dot(axis, rel)
            across = rel - along * axis
            f = 0.5 * rho * self.drag[k] * ca.sqrt(ca.sumsqr(across) + _EPS**2) * across
            if self.taper[k]:
                f += 0.5 * rho * self.taper[k] * ca.fabs(along) * along * axis
            f *= self.length[k]
            force += f
            moment += ca.cross(arm + self.offset[k] * axis, f)
        for k in range(self.end_drag.size):
            arm = ca.mtimes(rot, ca.DM(self.end_points[k]))
            rel = -(v[0:3] + ca.cross(v[3:6], arm))
            if water is not None:
                j = 3 * (self.n_nodes + k)
                rel = rel + water[j:j + 3]
            normal = ca.DM(self.end_normals[k])
            vn = ca.dot(normal, rel)
            if self.end_one_sided[k]:
                f = 0.5 * rho * self.end_drag[k] * ca.fabs(vn) * ca.fmax(vn, 0.0) * normal
            else:
                f = 0.25 * rho * self.end_drag[k] * ca.fabs(vn) * vn * normal
            force += f
            moment += ca.cross(arm, f)
        return _out(ca.vertcat(force, moment), q, qd, flow)


def _rows(hd, name: str) -> list[tuple]:
    return list(hd.tables.get(name, ()).rows) if name in hd.tables else []


def morison_problems(hd, sea=None, *, water_depth: float | None = None) -> list[str]:
    """What of a HydroDyn deck's members this module does not model (empty: all of it), one phrase each."""
    members = _rows(hd, "members")
    if not members:
        return []
    out = []
    lines = dict(zip([int(r[0]) for r in members], hd.tables["members"].lines))
    for row in members:
        where = f"member {int(row[0])} (line {lines[int(row[0])]})"
        if int(row[5]) != 1:
            out.append(f"{where}: MSecGeom = {int(row[5])} (rectangular members are not modelled)")
        if int(row[8]) not in (1, 2, 3):
            out.append(f"{where}: MCoefMod = {int(row[8])} (1 simple, 2 depth-based, 3 member-based coefficients)")
        if not row[7] > 0:
            out.append(f"{where}: MDivSize = {row[7]} must be > 0")
    out += _depth_range_problems(hd, members, lines)
    for name, what in (("fill_groups", "filled members (NFillGroups > 0: their ballast)"),
                       ("rectangle_properties", "rectangular property sets (NPropSetsRec > 0)")):
        if _rows(hd, name):
            out.append(what)
    for row in _rows(hd, "axial_coefficients"):
        if len(row) > 5 and row[5] > 0:
            out.append(f"AxVnCOff = {row[5]} on axial coefficients {int(row[0])} (the end drag's high-pass filter)")
        if len(row) > 4 and int(row[4]) not in (0, 1):
            out.append(f"AxFDMod = {int(row[4])} on axial coefficients {int(row[0])} (0 or 1)")
    if sea is not None:
        if (sea.wave_model != 0 or sea.current_model) and getattr(hd, "wave_displaced", 0):
            out.append(f"WaveDisp = {hd.wave_displaced} with waves or a current and members (the water's velocity at "
                       "the members' displaced positions; use 0, the undisplaced ones)")
        if sea.wave_model != 0 and (getattr(sea, "difference_qtf", False) or getattr(sea, "sum_qtf", False)):
            out.append("WvDiffQTF/WvSumQTF with waves and members (SeaState adds second-order kinematics to the "
                       "waves' velocity at the members, which is first order here; set both False)")
        out += current_problems(sea)
        if sea.stretching_model != 0:
            out.append(f"WaveStMod = {sea.stretching_model} with members (the members' wetted length at the "
                       "instantaneous free surface; use 0)")
    if water_depth is not None and math.isfinite(water_depth):
        deep = [int(r[0]) for r in _rows(hd, "joints") if r[3] < -water_depth]
        if deep:
            out.append(f"joints {deep} below the seabed (z < -{water_depth:g} m)")
    return out


def _depth_range_problems(hd, members: list, lines: dict) -> list[str]:
    """Members with depth-based coefficients whose joints lie outside the table's heights (HydroDyn refuses them:
    it does not extrapolate the table)."""
    joints = {int(r[0]): float(r[3]) for r in _rows(hd, "joints")}
    depths = [float(r[0]) for r in _rows(hd, "depth_cylinder_coefficients")]
    out = []
    for row in members:
        if int(row[8]) != 2 or int(row[5]) != 1:
            continue
        where = f"member {int(row[0])} (line {lines[int(row[0])]})"
        if not depths:
            out.append(f"{where}: MCoefMod = 2 needs the depth-based coefficient table (NCoefDpthCyl > 0)")
            continue
        z = [joints.get(int(row[j]), float("nan")) for j in (1, 2)]
        if not (min(depths) <= min(z) and max(z) <= max(depths)):
            out.append(f"{where}: MCoefMod = 2, its joints at z = {z[0]:g} and {z[1]:g} m lie outside the depth-based "
                       f"table's {min(depths):g} … {max(depths):g} m (HydroDyn does not extrapolate it either)")
    return out


def morison_drag(hd, *, water_density: float, reference=(0.0, 0.0, 0.0),
                 water_depth: float | None = None) -> MorisonDrag | None:
    """The :class:`MorisonDrag` of a HydroDyn input (None without members).

    Parameters
    ----------
    hd : HydroDynInput
        Checked first by :func:`morison_problems`.
    water_density : float
        [kg/m³].
    reference : sequence of 3 floats, optional
        The platform reference point's undisplaced position (ElastoDyn's ``PtfmRefxt/yt/zt``) [m].
    water_depth : float, optional
        [m]: joints deeper than it carry no end drag (HydroDyn's seabed).

    Raises
    ------
    ParameterError
        A member naming a joint, property set or coefficient row that does not exist.
    """
    members = member_geometry(hd)
    if not members:
        return None
    joints = {int(r[0]): (np.array(r[1:4], dtype=float), int(r[4])) for r in _rows(hd, "joints")}
    axial = {int(r[0]): (float(r[1]), int(r[4]) if len(r) > 4 else 0) for r in _rows(hd, "axial_coefficients")}
    growth = _rows(hd, "marine_growth")
    ref = np.asarray(reference, dtype=float)
    nodes, ends = [], {}
    for row, p1, p2, r1, r2, every in members:
        if p1[2] > 0 and p2[2] > 0:                         # both ends dry: HydroDyn skips the member
            continue
        nodes.append(_strips(p1, p2, ref, r1, r2, float(row[7]), _drag_coefficients(every), growth))
        k = (p2 - p1) / np.linalg.norm(p2 - p1)
        ends.setdefault(int(row[1]), []).append(-math.pi * (r1 + marine_growth(growth, p1[2])) ** 2 * k)
        ends.setdefault(int(row[2]), []).append(math.pi * (r2 + marine_growth(growth, p2[2])) ** 2 * k)
    strips = {key: np.concatenate([n[key] for n in nodes]) for key in nodes[0]} if nodes else None
    end = _end_plates(ends, joints, axial, ref, water_depth)
    if strips is None:
        strips = {"points": np.zeros((0, 3)), "axis": np.zeros((0, 3))} | {k: np.zeros(0) for k in
                                                                           ("length", "offset", "drag", "taper")}
    dragging = (strips["drag"] != 0) | (strips["taper"] != 0)       # nodes without drag need no flow input
    strips = {key: value[dragging] for key, value in strips.items()}
    return MorisonDrag(**strips, **end, water_density=float(water_density), reference=ref)


def _lookup(table: dict, key: int, what: str):
    if key not in table:
        raise ParameterError(f"HydroDyn {what} {key} is not in its table ({sorted(table)}).")
    return table[key]


#: Columns of each coefficient in HydroDyn's cylinder tables: (plain, marine growth); member-based: end 1, end 2 of
#: each (plain ones first, then the growth ones).
_SIMPLE = {"Cd": (0, 1), "Ca": (2, 3), "Cp": (4, 5), "AxCd": (6, 7), "AxCa": (8, 9), "AxCp": (10, 11), "Cb": (12, 13)}
_DEPTH = {name: (a + 1, b + 1) for name, (a, b) in _SIMPLE.items()}
_MEMBER = {name: 1 + 4 * k for k, name in enumerate(_SIMPLE)}


def member_coefficients(mode: int, tables: dict, ident: int):
    """``(s, z, growth) -> {name: values}`` per node of a member, ``name`` in Cd, Ca, Cp, AxCd, AxCa, AxCp, Cb
    (``MCoefMod`` 1 simple, 2 depth-based, 3 member-based; ``s`` the fraction along the member from joint 1, ``z``
    the height [m], ``growth`` where marine growth is): the marine-growth coefficients where the node has growth,
    as HydroDyn's ``SetExternalHydroCoefs_Cyl``."""
    if mode == 1:
        if not tables["simple"]:
            raise ParameterError(f"HydroDyn member {ident}: MCoefMod = 1 needs the simple coefficient table.")
        row = tables["simple"][0]
        return lambda s, z, mg: {n: np.where(mg, float(row[b]), float(row[a])) for n, (a, b) in _SIMPLE.items()}
    if mode == 2:
        rows = tables["depth"]
        if not rows:
            raise ParameterError(f"HydroDyn member {ident}: MCoefMod = 2 needs the depth-based coefficient table "
                                 "(NCoefDpthCyl > 0).")
        return lambda s, z, mg: {n: np.array([_depth_value(rows, zi, b if g else a) for zi, g in zip(z, mg)])
                                 for n, (a, b) in _DEPTH.items()}
    row = _lookup(tables["member"], ident, "member-based coefficients of member")

    def along(a, s):
        return float(row[a]) + s * (float(row[a + 1]) - float(row[a]))

    return lambda s, z, mg: {n: np.where(mg, along(a + 2, s), along(a, s)) for n, a in _MEMBER.items()}


def _drag_coefficients(every):
    """``(s, z, growth) -> (Cd, AxCd)`` of a member's :func:`member_coefficients`."""

    def drag(s, z, mg):
        c = every(s, z, mg)
        return c["Cd"], c["AxCd"]

    return drag


def member_geometry(hd) -> list[tuple]:
    """Each member of a HydroDyn input as ``(row, p1, p2, r1, r2, coefficients)``: its table row, its joints'
    undisplaced positions [m], the radii of its two property sets [m] and its :func:`member_coefficients`.

    Raises
    ------
    ParameterError
        A member naming a joint, property set or coefficient row that does not exist.
    """
    joints = {int(r[0]): np.array(r[1:4], dtype=float) for r in _rows(hd, "joints")}
    props = {int(r[0]): float(r[1]) for r in _rows(hd, "cylinder_properties")}
    tables = {"simple": _rows(hd, "simple_cylinder_coefficients"),
              "member": {int(r[0]): r for r in _rows(hd, "member_cylinder_coefficients")},
              "depth": _rows(hd, "depth_cylinder_coefficients")}
    out = []
    for row in _rows(hd, "members"):
        ident = int(row[0])
        p1, p2 = (_lookup(joints, int(row[j]), f"member {ident}: joint") for j in (1, 2))
        r1, r2 = (0.5 * _lookup(props, int(row[j]), f"member {ident}: property set") for j in (3, 4))
        out.append((row, p1, p2, r1, r2, member_coefficients(int(row[8]), tables, ident)))
    return out


def _depth_value(rows: list, z: float, column: int) -> float:
    """HydroDyn's depth-based coefficient at height ``z`` (``SetDepthBasedCoefs_Cyl``, its table read from the
    first row down): linear between the first row at or below ``z`` and the last at or above it (a member reaching
    outside the table is refused: :func:`_depth_range_problems`)."""
    below = next((k for k, r in enumerate(rows) if r[0] <= z), None)
    above = max((k for k, r in enumerate(rows) if r[0] >= z), default=0)
    below = 0 if below is None else below
    span = rows[below][0] - rows[above][0]
    s = 0.0 if abs(span) < 1e-9 else (rows[below][0] - z) / span
    return rows[below][column] * (1.0 - s) + rows[above][column] * s


def marine_growth(rows: list, z: float, column: int = 1) -> float:
    """HydroDyn's marine-growth thickness [m] (``column`` 1) or density [kg/m³] (2) at height ``z`` (``SetNodeMG``:
    linear between the first row of the table at or below ``z`` and the last at or above it; zero outside it)."""
    below = next((k for k, r in enumerate(rows) if r[0] <= z), None)
    above = max((k for k, r in enumerate(rows) if r[0] >= z), default=None)
    if below is None or above is None:
        return 0.0
    span = rows[below][0] - rows[above][0]
    s = 0.0 if abs(span) < 1e-9 else (rows[below][0] - z) / span
    return float(rows[below][column] * (1.0 - s) + rows[above][column] * s)


def _strips(p1: np.ndarray, p2: np.ndarray, ref: np.ndarray, r1: float, r2: float, div: float, coefficients,
            growth: list) -> dict:
    """The wet nodes of one member from joint ``p1`` to ``p2`` (inertial, undisplaced; points returned relative
    to the reference point ``ref``) (module docstring)."""
    span = p2 - p1
    length = float(np.linalg.norm(span))
    if length <= 0:
        raise ParameterError(f"HydroDyn member from {p1.tolist()} to {p2.tolist()} has zero length.")
    n = math.ceil(length / div)
    dl = length / n
    s = np.arange(n + 1) / n
    pts = p1 + s[:, None] * span
    z = pts[:, 2]
    thickness = np.array([marine_growth(growth, zi) for zi in z])
    radius = r1 + s * (r2 - r1) + thickness
    slope = np.abs(np.diff(radius)) / dl
    dr = np.concatenate([[slope[0]], 0.5 * (slope[:-1] + slope[1:]), [slope[-1]]]) if n > 1 else \
        np.array([slope[0], slope[0]])
    wet = z <= 0.0
    left, right = np.zeros(n + 1), np.zeros(n + 1)
    for j in range(n):
        a, b = j, j + 1
        for node, other, side in ((a, b, right), (b, a, left)):
            if wet[node]:
                side[node] = 0.5 * dl if wet[other] else dl * z[node] / (z[node] - z[other])
    keep = wet & (left + right > 0)
    k = span / length
    cd_n, ax_n = coefficients(s, z, thickness > 0)
    return {"points": (pts - ref)[keep], "axis": np.tile(k, (int(keep.sum()), 1)), "length": (left + right)[keep],
            "offset": 0.5 * (right - left)[keep], "drag": (2.0 * cd_n * radius)[keep],
            "taper": (ax_n * math.pi * radius * dr)[keep]}


def _end_plates(ends: dict, joints: dict, axial: dict, ref: np.ndarray, water_depth: float | None) -> dict:
    """The exposed end plates at the joints (module docstring)."""
    pts, normals, drag, one_sided = [], [], [], []
    for ident, vectors in ends.items():
        position, axial_id = joints[ident]
        if position[2] > 0 or (water_depth is not None and position[2] < -water_depth):
            continue
        total = np.sum(vectors, axis=0)
        area = float(np.linalg.norm(total))
        cd, mode = _lookup(axial, axial_id, f"joint {ident}: axial coefficients")
        if area <= 1e-12 * max(float(np.linalg.norm(v)) for v in vectors) or cd == 0.0:
            continue
        pts.append(position - ref)
        normals.append(total / area)
        drag.append(cd * area)
        one_sided.append(mode == 1)
    return {"end_points": np.array(pts).reshape(-1, 3), "end_normals": np.array(normals).reshape(-1, 3),
            "end_drag": np.array(drag, dtype=float), "end_one_sided": np.array(one_sided, dtype=bool)}
