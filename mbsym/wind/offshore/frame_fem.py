"""The finite-element frame of a SubDyn substructure: beam elements, concentrated masses, assembly.

Built as OpenFAST v5's SubDyn builds it (``SD_FEM.f90``, ``FEM.f90``), for circular beams on cantilever
joints:

- **Discretization.** The nodes are the joints in file order, then, member by member, the ``NDiv − 1``
  equally spaced nodes that split each member into ``NDiv`` elements. Diameter and thickness vary
  linearly along a tapered member; an element takes the mean of its two end values:
  outer radius r = (D₁ + D₂)/4, thickness t = (t₁ + t₂)/2, inner radius r − t (0 if t = 0);
  A = π(r² − rᵢ²), Ixx = Iyy = π(r⁴ − rᵢ⁴)/4, J = 2 Ixx (polar and torsion constant); E, G and ρ of
  the member's first property set.
- **Element axes** (``GetDirCos``): local z along the member from joint 1 to joint 2; for a member that is
  not vertical local x = (Δy, −Δx, 0)/Δxy and y = z × x; a vertical member keeps global axes (pointing
  up) or x, −y, −z (pointing down); then the member spin MSpin about local z. The matrix ``dc`` maps
  local to global components, xg = dc · xl, and element matrices are dc·Kₑ·dcᵀ on each 3-block.
- **Stiffness.** Two-node Timoshenko beam (``FEMMod`` 3) with Φ = 12 E I /(κ G A L²) per bending plane, or
  Euler–Bernoulli (``FEMMod`` 1, Φ = 0); EA/L axially, G J/L in torsion. The shear coefficient of a pipe
  with ν = E/(2G) − 1 and m = (Dᵢ/D)², D = 2r, Dᵢ = D − 2t (Steinboeck et al., eq. 13 of the SubDyn
  theory manual): κ = 6(1+ν)²(1+m)² / [(1+m)²(7 + 14ν + 8ν²) + 4m(5 + 10ν + 4ν²)] (SubDyn applies
  this formula also to solid sections, t = 0, where it gives m = 1).
- **Mass.** The consistent mass of the cubic beam with rotary inertia ρI for bending (also for
  Timoshenko elements, as SubDyn), ρAL/3, /6 axially and ρJL/3, /6 in torsion.
- **Gravity** (``ElemG``): each element puts half its weight w L (w = ρ A g) on each node, and the moments
  (−w L² ℓy/12, +w L² ℓx/12, 0) on node 1 and the opposite on node 2 (ℓ: the unit member axis). A
  concentrated mass adds −m g along z and the moment r × (0, 0, −m g) of its offset r.
- **Concentrated masses** (``rigidBodyMassMatrix``): the 6×6 rigid-body mass of mass m with inertia J
  (about its centre of mass, entries as in the file) at offset r from its joint.

All joints are cantilever, so each node has the six DOFs (ux, uy, uz, θx, θy, θz) in global axes and
node k owns rows 6k … 6k+5.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..deck.subdyn import SubDynSettings

__all__ = ["FrameModel", "build_frame", "direction_cosines", "pipe_section", "beam_stiffness", "beam_mass",
           "beam_gravity", "point_mass_matrix", "rigid_transform", "small_rotation_matrix", "small_rotation_angles"]


def direction_cosines(p1, p2, spin: float = 0.0) -> tuple[np.ndarray, float]:
    """SubDyn's element axes: the matrix mapping local to global components, and the length [m].

    Parameters
    ----------
    p1, p2 : array_like, shape (3,)
        End points [m].
    spin : float
        Rotation about the member axis [rad] (``MSpin``).

    Returns
    -------
    dc : ndarray, shape (3, 3)
        Columns: local x, y, z axes in global components.
    length : float
    """
    d = np.asarray(p2, float) - np.asarray(p1, float)
    length = float(np.linalg.norm(d))
    dxy = math.hypot(d[0], d[1])
    if dxy == 0.0:  # SubDyn tests EqualRealNos(Dxy, 0)
        dc = np.diag([1.0, -1.0, -1.0]) if d[2] < 0 else np.eye(3)
    else:
        dc = np.array([[d[1] / dxy, d[0] * d[2] / (length * dxy), d[0] / length],
                       [-d[0] / dxy, d[2] * d[1] / (length * dxy), d[1] / length],
                       [0.0, -dxy / length, d[2] / length]])
    c, s = math.cos(spin), math.sin(spin)
    return dc @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]), length


def pipe_section(d1: float, t1: float, d2: float, t2: float, young: float, shear: float,
                 timoshenko: bool) -> dict[str, float]:
    """Section of a pipe element between end diameters/thicknesses (d1, t1), (d2, t2) [m], as SubDyn.

    Returns
    -------
    dict
        ``area`` [m²], ``ixx`` = ``iyy`` [m⁴], ``jzz`` [m⁴] (polar and torsion), ``kappa`` [-] (0 for
        Euler–Bernoulli).
    """
    r = 0.25 * (d1 + d2)
    t = 0.5 * (t1 + t2)
    ri = 0.0 if t == 0.0 else r - t
    area = math.pi * (r * r - ri * ri)
    ixx = 0.25 * math.pi * (r ** 4 - ri ** 4)
    kappa = 0.0
    if timoshenko:
        nu = young / (2.0 * shear) - 1.0
        m = ((2.0 * r - 2.0 * t) / (2.0 * r)) ** 2
        kappa = (6.0 * (1.0 + nu) ** 2 * (1.0 + m) ** 2) / (
            (1.0 + m) ** 2 * (7.0 + 14.0 * nu + 8.0 * nu ** 2) + 4.0 * m * (5.0 + 10.0 * nu + 4.0 * nu ** 2))
    return {"area": area, "ixx": ixx, "iyy": ixx, "jzz": 2.0 * ixx, "kappa": kappa}


def _rotate(local: np.ndarray, dc: np.ndarray) -> np.ndarray:
    t = np.kron(np.eye(4), dc)
    return t @ local @ t.T


def _bending_blocks(rows: tuple[int, int, int, int], sign: float, block: np.ndarray, out: np.ndarray) -> None:
    """Scatter a (w1, φ1, w2, φ2) 4×4 block; rotation θ = sign·φ (φ = dw/dz)."""
    s = np.array([1.0, sign, 1.0, sign])
    out[np.ix_(rows, rows)] += block * np.outer(s, s)


def beam_stiffness(area: float, length: float, ixx: float, iyy: float, jzz: float, young: float, shear: float,
                   kappa: float, timoshenko: bool, dc: np.ndarray) -> np.ndarray:
    """12×12 stiffness of a two-node beam in global axes (node 1 DOFs then node 2) [N/m, N, N m/rad]."""
    k = np.zeros((12, 12))
    L = length
    for rows, sign, inertia in (((0, 4, 6, 10), 1.0, iyy), ((1, 3, 7, 9), -1.0, ixx)):
        phi = 12.0 * young * inertia / (shear * kappa * area * L * L) if timoshenko else 0.0
        c = young * inertia / (L ** 3 * (1.0 + phi))
        block = c * np.array([[12.0, 6 * L, -12.0, 6 * L], [6 * L, (4 + phi) * L * L, -6 * L, (2 - phi) * L * L],
                              [-12.0, -6 * L, 12.0, -6 * L], [6 * L, (2 - phi) * L * L, -6 * L, (4 + phi) * L * L]])
        _bending_blocks(rows, sign, block, k)
    for i, j, value in ((2, 8, young * area / L), (5, 11, shear * jzz / L)):
        k[np.ix_((i, j), (i, j))] += value * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return _rotate(k, dc)


def beam_mass(area: float, length: float, ixx: float, iyy: float, jzz: float, density: float,
              dc: np.ndarray) -> np.ndarray:
    """12×12 consistent mass of a two-node beam with rotary inertia, in global axes [kg, kg m, kg m²]."""
    m = np.zeros((12, 12))
    L = length
    t = density * area * L
    for rows, sign, inertia in (((0, 4, 6, 10), 1.0, iyy), ((1, 3, 7, 9), -1.0, ixx)):
        r = density * inertia
        block = t / 420.0 * np.array([[156.0, 22 * L, 54.0, -13 * L], [22 * L, 4 * L * L, 13 * L, -3 * L * L],
                                      [54.0, 13 * L, 156.0, -22 * L], [-13 * L, -3 * L * L, -22 * L, 4 * L * L]])
        block += r / (30.0 * L) * np.array([[36.0, 3 * L, -36.0, 3 * L], [3 * L, 4 * L * L, -3 * L, -L * L],
                                            [-36.0, -3 * L, 36.0, -3 * L], [3 * L, -L * L, -3 * L, 4 * L * L]])
        _bending_blocks(rows, sign, block, m)
    for i, j, value in ((2, 8, t), (5, 11, density * jzz * L)):
        m[np.ix_((i, j), (i, j))] += value * np.array([[1.0 / 3.0, 1.0 / 6.0], [1.0 / 6.0, 1.0 / 3.0]])
    return _rotate(m, dc)


def beam_gravity(area: float, length: float, density: float, gravity: float, dc: np.ndarray) -> np.ndarray:
    """SubDyn's lumped weight of an element: 12 nodal forces [N] and moments [N m], global axes."""
    w = density * area * gravity
    f = np.zeros(12)
    f[2] = f[8] = -0.5 * length * w
    c = length * length * w / 12.0
    f[3], f[4] = -c * dc[1, 2], c * dc[0, 2]
    f[9], f[10] = -f[3], -f[4]
    return f


def point_mass_matrix(mass: float, inertia, offset) -> np.ndarray:
    """6×6 rigid-body mass at a joint of a mass whose centre is at ``offset`` [m] from it.

    ``inertia`` = (Jxx, Jyy, Jzz, Jxy, Jxz, Jyz) [kg m²] about the centre of mass, tensor entries.
    """
    jxx, jyy, jzz, jxy, jxz, jyz = inertia
    x, y, z = offset
    s = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])  # r×
    j = np.array([[jxx, jxy, jxz], [jxy, jyy, jyz], [jxz, jyz, jzz]])
    out = np.zeros((6, 6))
    out[:3, :3] = mass * np.eye(3)
    out[:3, 3:] = -mass * s
    out[3:, :3] = mass * s
    out[3:, 3:] = j - mass * s @ s
    return out


def rigid_transform(offset) -> np.ndarray:
    """6×6 T with (u, θ) of a point at ``offset`` [m] from a reference = T · (u, θ) of the reference
    (small rotations: u_point = u_ref + θ × offset)."""
    x, y, z = offset
    t = np.eye(6)
    t[:3, 3:] = np.array([[0.0, z, -y], [-z, 0.0, x], [y, -x, 0.0]])
    return t


def small_rotation_matrix(theta) -> np.ndarray:
    """OpenFAST's ``SmllRotTrans``: the orthonormal DCM (global → rotated axes) of small rotations θ [rad];
    to first order I − [θ×]."""
    a, b, c = (float(v) for v in theta)
    w = math.sqrt(1.0 - 0.25 * (a * a + b * b + c * c))
    return np.array([[1.0 - 0.5 * (b * b + c * c), 0.5 * a * b + c * w, 0.5 * a * c - b * w],
                     [0.5 * a * b - c * w, 1.0 - 0.5 * (a * a + c * c), 0.5 * b * c + a * w],
                     [0.5 * a * c + b * w, 0.5 * b * c - a * w, 1.0 - 0.5 * (a * a + b * b)]])


def small_rotation_angles(dcm) -> np.ndarray:
    """OpenFAST's ``GetSmllRotAngs``: the small rotation angles [rad] of a DCM (global → rotated), the
    inverse of :func:`small_rotation_matrix`."""
    d = np.asarray(dcm, float)
    return np.array([d[1, 2] - d[2, 1], d[2, 0] - d[0, 2], d[0, 1] - d[1, 0]]) / math.sqrt(np.trace(d) + 1.0)


@dataclass(frozen=True, eq=False)
class FrameModel:
    """The assembled frame (see the module docstring).

    Attributes: ``positions`` (n, 3) node positions [m]; ``joint_ids`` the joint ID of each node (None for
    nodes that subdivide a member); ``elements`` (nₑ, 2) node indices; ``element_member`` the member ID of
    each element; ``element_length``, ``element_area`` [m, m²], ``element_density`` [kg/m³];
    ``member_nodes`` member ID → node indices from joint 1 to joint 2; ``stiffness``, ``mass`` (6n, 6n);
    ``gravity_load`` (6n,) nodal weights [N, N m]; ``point_masses`` (node, weight [N], offset (3,) [m]) of
    each concentrated mass; ``reaction_nodes``, ``interface_nodes`` node indices in file order.
    """

    positions: np.ndarray
    joint_ids: tuple
    elements: np.ndarray
    element_member: tuple[int, ...]
    element_length: np.ndarray
    element_area: np.ndarray
    element_density: np.ndarray
    member_nodes: dict[int, tuple[int, ...]]
    stiffness: np.ndarray
    mass: np.ndarray
    gravity_load: np.ndarray
    point_masses: tuple[tuple[int, float, np.ndarray], ...]
    reaction_nodes: tuple[int, ...]
    interface_nodes: tuple[int, ...]

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return len(self.positions)

    def node_of_joint(self, joint_id: int) -> int:
        """Node index of a joint ID."""
        return self.joint_ids.index(joint_id)

    def steel_mass(self) -> float:
        """Σ ρ A L of the elements [kg]."""
        return float(np.sum(self.element_density * self.element_area * self.element_length))


def build_frame(settings: SubDynSettings, gravity: float) -> FrameModel:
    """Discretize and assemble the frame of ``settings`` (module docstring) with gravity ``gravity`` [m/s²].

    Parameters
    ----------
    settings : SubDynSettings
        From :func:`~mbsym.wind.deck.subdyn.read_subdyn`.
    gravity : float
        Gravitational acceleration [m/s²] (OpenFAST's ``Gravity`` of the ``.fst``).

    Returns
    -------
    FrameModel
    """
    joint_ids = [j.id for j in settings.joints]
    positions = [np.array(j.position, float) for j in settings.joints]
    n_div = settings.n_divisions
    timoshenko = settings.fem_model == 3
    member_nodes, elements, sections = {}, [], []
    for member in settings.members:
        a, b = joint_ids.index(member.joint1), joint_ids.index(member.joint2)
        s1, s2 = settings.section(member.prop1), settings.section(member.prop2)
        nodes = [a]
        for j in range(1, n_div):
            positions.append(positions[a] + j * (positions[b] - positions[a]) / n_div)
            joint_ids.append(None)
            nodes.append(len(positions) - 1)
        nodes.append(b)
        member_nodes[member.id] = tuple(nodes)
        d = [s1.diameter + j * (s2.diameter - s1.diameter) / n_div for j in range(n_div + 1)]
        t = [s1.thickness + j * (s2.thickness - s1.thickness) / n_div for j in range(n_div + 1)]
        for j in range(n_div):
            elements.append((nodes[j], nodes[j + 1], member))
            sections.append(pipe_section(d[j], t[j], d[j + 1], t[j + 1], s1.young, s1.shear, timoshenko) |
                            {"young": s1.young, "shear": s1.shear, "density": s1.density})
    pos = np.array(positions)
    n = len(pos)
    k, m, fg = np.zeros((6 * n, 6 * n)), np.zeros((6 * n, 6 * n)), np.zeros(6 * n)
    lengths, areas, densities = [], [], []
    for (a, b, member), sec in zip(elements, sections):
        dc, length = direction_cosines(pos[a], pos[b], member.spin)
        dofs = np.r_[6 * a:6 * a + 6, 6 * b:6 * b + 6]
        args = (sec["area"], length, sec["ixx"], sec["iyy"], sec["jzz"])
        k[np.ix_(dofs, dofs)] += beam_stiffness(*args, sec["young"], sec["shear"], sec["kappa"], timoshenko, dc)
        m[np.ix_(dofs, dofs)] += beam_mass(*args, sec["density"], dc)
        fg[dofs] += beam_gravity(sec["area"], length, sec["density"], gravity, dc)
        lengths.append(length)
        areas.append(sec["area"])
        densities.append(sec["density"])
    points = []
    for cm in settings.concentrated_masses:
        node = joint_ids.index(cm.joint)
        dofs = np.r_[6 * node:6 * node + 6]
        m[np.ix_(dofs, dofs)] += point_mass_matrix(cm.mass, cm.inertia, cm.offset)
        weight = cm.mass * gravity
        fg[6 * node + 2] -= weight
        fg[6 * node + 3] -= weight * cm.offset[1]
        fg[6 * node + 4] += weight * cm.offset[0]
        points.append((node, weight, np.array(cm.offset, float)))
    return FrameModel(pos, tuple(joint_ids), np.array([(a, b) for a, b, _ in elements], dtype=int).reshape(-1, 2),
                      tuple(member.id for _, _, member in elements), np.array(lengths), np.array(areas),
                      np.array(densities), member_nodes, k, m, fg, tuple(points),
                      tuple(joint_ids.index(j) for j in settings.reactions),
                      tuple(joint_ids.index(j) for j in settings.interfaces))
