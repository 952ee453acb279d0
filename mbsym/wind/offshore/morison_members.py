"""HydroDyn's Morison members on a bottom-fixed structure, discretized as HydroDyn v5.0.0 discretizes them.

The geometry :mod:`.substructure_water` puts HydroDyn's loads on (read for the facts in ``Morison.f90``:
``Morison_GenerateSimulationNodes``, ``FlipMemberNodeData``, ``SetMemberProperties_Cyl``, ``Morison_Init``,
``Morison_CalcOutput``), for still water level = mean sea level (``MSL2SWL = 0``) and no wave stretching:

* **Nodes.** HydroDyn's Morison mesh holds the joints (file order), then, member by member in file order, the
  ``N − 1`` interior nodes of a member cut into ``N = ⌈L / MDivSize⌉`` equal elements ``dl`` (positions from joint 1
  to joint 2 as written). A member whose joint 2 is lower than joint 1 (equal heights: larger x, then larger y) is
  **flipped**: its nodes run from its lowest end, its property sets swap, and member-based coefficients keep their
  joints (``s → 1 − s``). Radii are linear between the two property sets' ``PropD/2``, the inner radius
  ``PropD/2 − PropThck`` likewise; marine growth (``MGDpth`` table at each node's height) thickens the outer radius
  ``RMG = R + t_MG`` (and selects the ``…MG`` coefficients); the buoyancy radius is ``RMG √C_b``.
* **Seabed cut.** A member whose lowest node is below the seabed (``z < −WtrDpth``) is cut at it: with ``j`` the
  first node above the seabed, HydroDyn's ``i_floor = j`` (:attr:`MorisonMember.floor`, the crossing element is the
  ``j``-th, 1-based) and ``h_floor = (−WtrDpth − z_j)/cos φ ≤ 0`` (:attr:`MorisonMember.floor_length`). Side loads
  start at node ``j``, whose strip reaches down to the seabed (``−h_floor`` below it); the lower end plate is gone
  (no buoyancy, end drag or end inertia on it); marine growth and fill start at the seabed. A joint below the
  seabed carries no joint term.
* **Strips.** A node (at or above the seabed) with ``z ≤ 0`` takes half of each neighbouring element, the wet part
  ``−z_i dl/(z_j − z_i)`` of one crossing the still-water level, nothing at a member's ends beyond its last node:
  the drag and wave-inertia strip ``Δl`` with its centroid ``h`` along ``k`` (:meth:`MorisonMember.strips`); the
  added mass uses the same rule with ``−z_i / cos φ`` for the crossing element (``AMMod`` 0).
* **Joints** (above the seabed) carry the end plates of the members meeting there: ``A_n = Σ ± π RMG² k``,
  ``V_n = Σ ± (2π/3) RMG³ k`` (``−`` where a member starts). For a **flipped** member HydroDyn v5.0.0 takes the
  radius and marine growth of the wrong end (``Morison_Init`` indexes the reversed node arrays with the end as
  written): mbsym does the same, to match OpenFAST, and :mod:`.substructure_water` warns.

:func:`substructure_member_problems` lists what :mod:`.substructure_water` does not model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...exceptions import ParameterError
from .morison import _depth_range_problems, _lookup, _rows, marine_growth, member_geometry

__all__ = ["MorisonMember", "MorisonJoint", "MorisonFrame", "morison_frame", "substructure_member_problems",
           "fill_groups"]

#: HydroDyn's relative tolerance of ``EqualRealNos`` (double precision), used where HydroDyn compares lengths.
_EQUAL = 1e-12


def _equal(a: float, b: float) -> bool:
    return abs(a - b) <= _EQUAL * max(abs(a), abs(b), 1.0)


@dataclass(frozen=True, eq=False)
class MorisonMember:
    """One cylindrical member as HydroDyn holds it (module docstring); node arrays run from its lowest end.

    Attributes
    ----------
    ident, line : int
        ``MemberID`` and its line in the HydroDyn file.
    nodes : ndarray of int, shape (N + 1,)
        Indices into :attr:`MorisonFrame.positions`.
    flipped : bool
        Whether HydroDyn reversed the member.
    axis : ndarray, shape (3,)
        Unit axis ``k`` from the first node to the last.
    dl : float
        Element length [m].
    points : ndarray, shape (N + 1, 3)
        Node positions [m] (z from the still-water level).
    bare, radius, inner, buoyant : ndarray, shape (N + 1,)
        ``R``, ``RMG = R + t_MG``, ``R_in``, ``RMG √C_b`` [m].
    growth, growth_density : ndarray, shape (N + 1,)
        Marine-growth thickness [m] and density [kg/m³].
    coefficients : dict of str to ndarray
        ``Cd``, ``Ca``, ``Cp``, ``AxCd``, ``AxCa``, ``AxCp``, ``Cb`` per node.
    hydrostatics : int
        ``MHstLMod`` (0 or 1).
    floor : int
        HydroDyn's ``i_floor``: 0 when the member starts at or above the seabed, else the (1-based) element crossing
        it, which is also the (0-based) first node above it; ``N + 1`` when the whole member is buried.
    floor_length : float
        HydroDyn's ``h_floor`` [m] (≤ 0; 0 without a cut).
    end_buoyancy : bool
        HydroDyn's ``doEndBuoyancy`` (a seabed-crossing member whose upper end plate may carry pressure).
    fill_level, fill_density : float or None
        ``FillFSLoc`` [m] and ``FillDens`` [kg/m³] of its fill group (None: not filled).
    fill_group : int or None
        Index of its fill group in :func:`fill_groups`.
    """

    ident: int
    line: int
    nodes: np.ndarray
    flipped: bool
    axis: np.ndarray
    dl: float
    points: np.ndarray
    bare: np.ndarray
    radius: np.ndarray
    inner: np.ndarray
    buoyant: np.ndarray
    growth: np.ndarray
    growth_density: np.ndarray
    coefficients: dict
    hydrostatics: int
    floor: int = 0
    floor_length: float = 0.0
    end_buoyancy: bool = False
    fill_level: float | None = None
    fill_density: float | None = None
    fill_group: int | None = None

    @property
    def n_elements(self) -> int:
        return len(self.nodes) - 1

    @property
    def z(self) -> np.ndarray:
        return self.points[:, 2]

    def slopes(self) -> tuple[np.ndarray, np.ndarray]:
        """Per node: HydroDyn's ``dRdl_p`` (mean of the neighbouring elements' ``|dRMG/dl|``) and ``dRdl_pp`` (the
        signed mean); one element at the ends."""
        d = np.diff(self.radius) / self.dl
        absolute = np.concatenate([[abs(d[0])], 0.5 * (np.abs(d[:-1]) + np.abs(d[1:])), [abs(d[-1])]])
        signed = np.concatenate([[d[0]], 0.5 * (d[:-1] + d[1:]), [d[-1]]])
        return absolute, signed

    def strips(self, added_mass: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Each node's wet strip ``Δl`` [m] and its centroid offset ``h`` [m] along :attr:`axis` (module docstring);
        ``added_mass``: HydroDyn's ``AMMod = 0`` rule. Nodes below the seabed or dry get ``Δl = 0``."""
        z, n, dl = self.z, self.n_elements, self.dl
        length, offset = np.zeros(n + 1), np.zeros(n + 1)
        for j in range(self.floor, n + 1):
            if z[j] > 0.0:
                continue
            if j == 0:
                left = 0.0
            elif j == self.floor:
                left = -self.floor_length
            elif added_mass or z[j - 1] <= 0.0:
                left = 0.5 * dl
            else:
                left = dl * z[j] / (z[j] - z[j - 1])
            if j == n:
                right = 0.0
            elif z[j + 1] <= 0.0:
                right = 0.5 * dl
            elif added_mass:
                right = -z[j] / self.axis[2]
            else:
                right = dl * z[j] / (z[j] - z[j + 1])
            length[j], offset[j] = left + right, 0.5 * (right - left)
        return length, offset


@dataclass(frozen=True, eq=False)
class MorisonJoint:
    """A HydroDyn joint: ``ident``, ``line``, ``node`` (its index in the mesh), ``position`` [m], its axial coefficients
    ``(AxCd, AxCa, AxCp, AxFDMod)`` and the member ends meeting there as ``(member index, node index in the member,
    sign)`` (``−1`` where a member starts, ``+1`` where it ends: its outward normal is ``sign · k``). The node index
    is the one whose radius and marine growth HydroDyn uses for the end plate: on a flipped member the other end's
    (module docstring)."""

    ident: int
    line: int
    node: int
    position: np.ndarray
    axial: tuple
    ends: tuple = field(default_factory=tuple)


@dataclass(frozen=True, eq=False)
class MorisonFrame:
    """HydroDyn's Morison mesh: ``positions`` (n, 3) [m], ``members``, ``joints``, ``water_depth`` [m]."""

    positions: np.ndarray
    members: tuple
    joints: tuple
    water_depth: float

    @property
    def n_nodes(self) -> int:
        return len(self.positions)


def fill_groups(hd, water_density: float) -> list[tuple[list[int], float, float, int]]:
    """The filled-member groups: ``(member IDs, FillFSLoc [m], FillDens [kg/m³], line)`` (``DEFAULT`` density: the
    water's)."""
    table = hd.tables.get("fill_groups") if "fill_groups" in hd.tables else None
    out = []
    for row, line in zip(table.rows if table else (), table.lines if table else ()):
        count = int(float(row[0]))
        members = [int(float(v)) for v in row[1:1 + count]]
        level = float(row[1 + count])
        density = row[2 + count]
        density = water_density if isinstance(density, str) and density.strip('"').upper() == "DEFAULT" \
            else float(density)
        out.append((members, level, density, line))
    return out


def _flipped(p1: np.ndarray, p2: np.ndarray) -> bool:
    """HydroDyn's rule: a member runs upward; level ones toward larger x, then larger y."""
    if _equal(p1[2], p2[2]):
        if _equal(p1[0], p2[0]):
            return bool(p1[1] > p2[1])
        return bool(p1[0] > p2[0])
    return bool(p1[2] > p2[2])


def morison_frame(hd, *, water_depth: float, water_density: float) -> MorisonFrame:
    """HydroDyn's Morison mesh of ``hd``'s cylindrical members (module docstring).

    Parameters
    ----------
    hd : HydroDynInput
        Checked first by :func:`substructure_member_problems`.
    water_depth, water_density : float, keyword-only
        SeaState's ``WtrDpth`` [m] (the seabed) and ``WtrDens`` [kg/m³] (a fill group's ``DEFAULT`` density).

    Raises
    ------
    ParameterError
        A member naming a joint, property set or coefficient row that does not exist, or of zero length.
    """
    joint_rows = _rows(hd, "joints")
    joint_index = {int(r[0]): k for k, r in enumerate(joint_rows)}
    props = {int(r[0]): (float(r[1]), float(r[2])) for r in _rows(hd, "cylinder_properties")}
    growth = _rows(hd, "marine_growth")
    groups = fill_groups(hd, water_density)
    filled = {m: (k, level, density) for k, (members, level, density, _) in enumerate(groups) for m in members}
    positions = [np.array(r[1:4], dtype=float) for r in joint_rows]
    lines = dict(zip([int(r[0]) for r in _rows(hd, "members")], hd.tables["members"].lines))
    members = []
    for row, p1, p2, _, _, coefficients in member_geometry(hd):
        ident = int(row[0])
        span = p2 - p1
        length = float(np.linalg.norm(span))
        if not length > 0.0:
            raise ParameterError(f"{hd.path}, line {lines[ident]}: HydroDyn member {ident} has zero length; give "
                                 "its joints different positions.")
        n = math.ceil(length / float(row[7]))
        first = len(positions)
        positions += [p1 + (j / n) * span for j in range(1, n)]
        nodes = [joint_index[int(row[1])], *range(first, first + n - 1), joint_index[int(row[2])]]
        sets = [_lookup(props, int(row[j]), f"member {ident}: property set") for j in (3, 4)]
        flip = _flipped(p1, p2)
        if flip:
            nodes, sets, p1, p2 = nodes[::-1], sets[::-1], p2, p1
        s = np.arange(n + 1) / n
        pts = p1 + s[:, None] * (p2 - p1)
        bare = 0.5 * sets[0][0] + s * 0.5 * (sets[1][0] - sets[0][0])
        inner1, inner2 = 0.5 * sets[0][0] - sets[0][1], 0.5 * sets[1][0] - sets[1][1]
        inner = inner1 + s * (inner2 - inner1)
        t = np.array([marine_growth(growth, zi) for zi in pts[:, 2]])
        rho = np.array([marine_growth(growth, zi, 2) for zi in pts[:, 2]])
        coef = coefficients(1.0 - s if flip else s, pts[:, 2], t > 0)
        radius = bare + t
        fill = filled.get(ident)
        floor, floor_length, ends = _seabed(pts[:, 2], (p2 - p1)[2] / length, water_depth)
        members.append(MorisonMember(
            ident, lines[ident], np.array(nodes), flip, (p2 - p1) / length, length / n, pts, bare, radius, inner,
            radius * np.sqrt(coef["Cb"]), t, rho, coef, int(row[9]), floor, floor_length, ends,
            None if fill is None else fill[1], None if fill is None else fill[2], None if fill is None else fill[0]))
    joints = []
    axial = {int(a[0]): a for a in _rows(hd, "axial_coefficients")}
    for k, r in enumerate(joint_rows):
        ends = tuple((i, _end_index(m, k), -1.0 if m.nodes[0] == k else 1.0)
                     for i, m in enumerate(members) if k in (m.nodes[0], m.nodes[-1]))
        row = _lookup(axial, int(r[4]), f"joint {int(r[0])}: axial coefficients")
        joints.append(MorisonJoint(int(r[0]), hd.tables["joints"].lines[k], k, positions[k].copy(),
                                   (float(row[1]), float(row[2]), float(row[3]), int(row[4]) if len(row) > 4 else 0),
                                   ends))
    return MorisonFrame(np.array(positions).reshape(-1, 3), tuple(members), tuple(joints), float(water_depth))


def _end_index(m: MorisonMember, node: int) -> int:
    """The node of member ``m`` whose radius and marine growth HydroDyn v5.0.0 gives its end plate at ``node``: the
    joint's own end, except on a flipped member, where ``Morison_Init`` indexes the reversed node arrays with the
    end the member was written with (joint 1: first node) and so reads the other end's values."""
    own = 0 if m.nodes[0] == node else m.n_elements
    return m.n_elements - own if m.flipped else own


def _seabed(z: np.ndarray, cos_phi: float, depth: float) -> tuple[int, float, bool]:
    """HydroDyn's ``i_floor``, ``h_floor`` and ``doEndBuoyancy`` of a member with node heights ``z`` (lowest first)."""
    if z[0] >= -depth:
        return 0, 0.0, False
    ends = False
    for j in range(1, len(z)):
        if z[j] > -depth:
            return j, (-depth - z[j]) / cos_phi, True
        if _equal(z[j], -depth):
            ends = True
    return len(z), 0.0, ends


def substructure_member_problems(hd, water_depth: float) -> list[str]:
    """What of ``hd``'s Morison members :mod:`.substructure_water` does not model (one phrase each, naming the line)."""
    out = []
    members = _rows(hd, "members")
    lines = dict(zip([int(r[0]) for r in members], hd.tables["members"].lines)) if members else {}
    joints = {int(r[0]): np.array(r[1:4], dtype=float) for r in _rows(hd, "joints")}
    props = {int(r[0]): float(r[1]) for r in _rows(hd, "cylinder_properties")}
    for row in members:
        ident = int(row[0])
        where = f"line {lines[ident]}, member {ident}"
        if int(row[5]) != 1:
            out.append(f"{where}: MSecGeom = {int(row[5])} (rectangular members are not modelled; use 1)")
            continue
        if int(row[8]) not in (1, 2, 3):
            out.append(f"{where}: MCoefMod = {int(row[8])} (1 simple, 2 depth-based or 3 member-based coefficients)")
        if int(row[9]) not in (0, 1):
            out.append(f"{where}: MHstLMod = {int(row[9])} (0 or 1; the refined hydrostatics of 2 are not modelled)")
        if row[10]:
            out.append(f"{where}: PropPot = TRUE (potential flow is not modelled on a SubDyn substructure; use FALSE)")
        if not row[7] > 0:
            out.append(f"{where}: MDivSize = {row[7]} must be > 0")
        ends = [joints.get(int(row[j])) for j in (1, 2)]
        if any(e is None for e in ends) or int(row[3]) not in props or int(row[4]) not in props:
            continue                                  # morison_frame names the missing joint or property set
        out += _member_checks(where, row, ends, [0.5 * props[int(row[j])] for j in (3, 4)], water_depth)
    out += _depth_range_problems(hd, members, lines)
    for row, line in zip(_rows(hd, "axial_coefficients"), hd.tables["axial_coefficients"].lines
                         if "axial_coefficients" in hd.tables else ()):
        if len(row) > 5 and row[5] > 0:
            out.append(f"line {line}: AxVnCOff = {row[5]} (the end drag's high-pass filter is not modelled; use 0)")
        if len(row) > 4 and int(row[4]) not in (0, 1):
            out.append(f"line {line}: AxFDMod = {int(row[4])} (0 or 1)")
    return out


def _member_checks(where: str, row, ends, radii, depth: float) -> list[str]:
    """HydroDyn's own initialization checks of a member (its fatal errors), mirrored."""
    p1, p2 = ends
    if _flipped(p1, p2):
        p1, p2, radii = p2, p1, radii[::-1]
    span = p2 - p1
    length = float(np.linalg.norm(span))
    if length <= 0.0:
        return [f"{where}: zero length"]
    sin_phi = math.hypot(span[0], span[1]) / length
    out = []
    if int(row[9]) == 1:
        for z, r, end in ((p2[2], radii[1], "upper"), (p1[2], radii[0], "lower")):
            if abs(z) < abs(r * sin_phi):
                out.append(f"{where}: its {end} end plate (z = {z:g} m) crosses the still-water level (HydroDyn "
                           "refuses it with MHstLMod = 1)")
    if p1[2] < -depth <= p2[2]:
        if span[2] / length < math.cos(math.radians(10.0)) or abs(radii[1] - radii[0]) / length > 0.1:
            out.append(f"{where}: crosses the seabed (z = {-depth:g} m) more than 10 deg from vertical or with a taper "
                       "above 0.1 (HydroDyn refuses it)")
    return out
