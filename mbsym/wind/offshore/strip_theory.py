"""Buoyancy, added mass and wave inertia of a platform's strip-theory members (HydroDyn ``PropPot = FALSE``).

A Morison member not modelled by potential flow gets all its hydrodynamics from strip theory; its viscous drag is
:mod:`.morison`'s (as for every member), the rest is here, with HydroDyn v5.0.0's conventions (read for the facts
in ``Morison.f90``: ``Morison_CalcOutput``, ``getElementHstLds_Mod1``, ``Morison_Init``'s joint terms,
``LumpDistrHydroLoads``; ``Waves.f90`` for the kinematics):

* **Buoyancy** (``MHstLMod`` 1 or 2; 0: none) at the **displaced** position, the radii (with marine growth)
  scaled by ``√C_b`` (the node's buoyancy coefficient). HydroDyn's side loads per element
  (``ρ g [V e_z − π (r₂² z₂ − r₁² z₁) k]`` and its moment when submerged) and the end plates' pressure sum to
  Archimedes' force ``ρ g V_s e_z`` through the centroid of the volume below the still-water plane. A member below
  it adds a constant volume at its displaced centroid ``R c``: ``M = (R c) × F``; a member reaching it is buoyed
  element by element (:mod:`.waterline`).
* **Marine growth** (the ``MGDpth`` table at each node's undisplaced height): it thickens the radius of every term
  (and picks the ``…MG`` coefficients), and its own mass — the shell between the bare and the grown radius, each
  linear along an element at the lower node's density, and ``ρ_MG t |A_n|`` on each joint's end plates with
  HydroDyn's plate inertia — is a rigid body on the platform: its 6 × 6 mass matrix joins the added mass, its
  weight the buoyancy (at its displaced centroid).
* **Added mass** (sides, ``AMMod`` 0: the nodes below the still-water level undisplaced). Per unit length at a
  node of radius ``R`` on axis ``k``: ``m = ρ π R² [C_a (I − k kᵀ) + 2 C_{a,ax} |dR/dl| k kᵀ]`` times the strip
  ``Δl`` (half of each neighbouring element), applied at the node with the moment ``(h k) × F`` of its strip's
  centroid offset ``h`` (as :mod:`.morison`); the node's acceleration is the platform's at that point.
  **End plates** at each joint of strip-theory members: ``A_end = ρ C_{a,ax,J} V_n V_nᵀ / |V_n|`` with
  ``V_n = Σ ± (2π/3) R³ k`` (``−`` where a member starts, ``+`` where it ends). Both are constant (undisplaced
  axes), so they join A∞ in the **mass matrix** as a 6 × 6 block about the reference point (the centripetal part
  of a node's acceleration, second order in the rates, is left out: what the mass matrix holds of A∞ too).
* **Wave inertia** (first-order waves; SeaState's acceleration ``a_w`` and dynamic pressure ``p`` at the
  **undisplaced** nodes, ``WaveDisp = 0``): per unit length
  ``f = ρ π R² [(C_a + C_p)(I − k kᵀ) + 2 C_{a,ax} |dR/dl| k kᵀ] a_w + 2 C_{p,ax} π R (dR/dl) p k``, lumped as
  the added mass; at the joints ``F = −C_{p,ax,J} A_n p + A_end a_w`` with ``A_n = Σ ± π R² k``. Summed over the
  points ``P`` (platform axes from the reference point) the load about the displaced reference point is
  ``F = Σ F_i``, ``M = Σ (R p_i) × F_i + Σ (h_i k_i) × F_i``: with ``S = Σ p_i F_iᵀ`` it is
  ``M₀ + ε:((R − I) S)`` (``M₀`` the undisplaced moment), exact in the rotation. The model takes ``F``, ``M₀`` and
  ``S`` as 15 inputs (:data:`WAVE_INERTIA_INPUTS`), tabulated from the sea like the excitation.

**Refused** (:func:`strip_problems`): members crossing the still-water level within 11.5° of it (the cut's
formulas fail as the axis lies in the plane), ``MHstLMod`` other than 0–2, filled members and rectangular ones
(:mod:`.morison`). Not modelled: an end plate cut by the surface (an element's whole volume counts from the moment
its node is under water; HydroDyn warns that its own load there "potentially has large error"), the marine growth's
and the added mass's centripetal and gyroscopic terms (second order in the rates).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ...exceptions import ParameterError
from ._casadi import _in, _out, euler_zyx
from .excitation import catmull_rom
from .morison import _lookup, _rows, marine_growth, member_geometry
from .waterline import element_buoyancy
from .wave_kinematics import wave_acceleration_pressure

__all__ = ["StripTheory", "StripWaves", "strip_theory", "strip_waves", "strip_problems", "WAVE_INERTIA_INPUTS",
           "WAVE_INERTIA_UNITS"]

#: The inputs of the strip-theory members' wave inertia: force, undisplaced moment, first moments ``S_ab = Σ p_a F_b``.
WAVE_INERTIA_INPUTS = ("StripWvsFxi", "StripWvsFyi", "StripWvsFzi", "StripWvsMxi", "StripWvsMyi", "StripWvsMzi",
                       *(f"StripWvsS{a}{b}" for a in "xyz" for b in "xyz"))
#: Their units.
WAVE_INERTIA_UNITS = {n: ("N" if n[7] == "F" else "N m") for n in WAVE_INERTIA_INPUTS}
#: A strip-theory member crossing the still-water level must rise at least this sine of its angle to the surface.
_STEEP = 0.2


@dataclass(frozen=True, eq=False)
class StripTheory:
    """The strip-theory members of a platform (module docstring), SI units, about the reference point.

    Attributes
    ----------
    volume : float
        Buoyancy volume ``ΣV`` of the members below the still-water level (radii scaled by ``√C_b``; members with
        ``MHstLMod = 0`` left out) [m³].
    centroid : ndarray (3,)
        Its centroid, platform axes from the reference point [m].
    elements : ndarray (m, 8)
        The elements of the members that reach the still-water level, buoyed element by element at their displaced
        position (:func:`~.waterline.element_buoyancy`): node 1 (3), node 2 (3) in platform axes from the reference
        point [m], their ``√C_b``-scaled radii (2) [m].
    growth_mass : float
        The marine growth's mass on the members' sides and end plates [kg] (its 6 × 6 mass matrix is in
        :attr:`added_mass`, its weight in :meth:`load`).
    growth_centroid : ndarray (3,)
        Its centroid, platform axes from the reference point [m].
    added_mass : ndarray (6, 6)
        Sides and end plates [kg, kg m, kg m²] (inertial axes, undisplaced), with the marine growth's own mass.
    points : ndarray (n, 3)
        Where the wave inertia acts: the strip nodes, then the joints (platform axes from the reference point).
    axis, offset : ndarray (n, 3), (n,)
        Unit axis ``k`` and strip centroid offset ``h`` [m] (joints: zero).
    inertia : ndarray (n, 3, 3)
        ``f = inertia @ a_w + pressure · p`` at each point [kg, for a_w in m/s²].
    pressure : ndarray (n, 3)
        [m²], for ``p`` in Pa.
    water_density, gravity : float
    reference : ndarray (3,)
        The reference point's undisplaced position [m].
    """

    volume: float
    centroid: np.ndarray
    added_mass: np.ndarray
    points: np.ndarray
    axis: np.ndarray
    offset: np.ndarray
    inertia: np.ndarray
    pressure: np.ndarray
    water_density: float
    gravity: float
    reference: np.ndarray = field(default_factory=lambda: np.zeros(3))
    elements: np.ndarray = field(default_factory=lambda: np.zeros((0, 8)))
    growth_mass: float = 0.0
    growth_centroid: np.ndarray = field(default_factory=lambda: np.zeros(3))

    @property
    def buoyancy(self) -> float:
        """The members' buoyancy in the undisplaced position [N]."""
        return float(self.load(np.zeros(6))[2])

    def wave_points(self) -> np.ndarray:
        """``(n, 3)`` undisplaced absolute positions [m] where the waves' kinematics enter."""
        return self.points + np.asarray(self.reference, dtype=float)

    def load(self, q):
        """Buoyancy and the marine growth's weight at the reference point, inertial axes [N, N m], for the platform
        DOFs ``q`` [m, rad]."""
        x = _in(q, 6, "q")
        rot = euler_zyx(x[3:6])
        rho_g = self.water_density * self.gravity
        volume, first = self.volume, self.volume * ca.mtimes(rot, ca.DM(self.centroid))
        height = self.reference[2] + x[2]
        for e in self.elements:
            a, b = ca.mtimes(rot, ca.DM(e[0:3])), ca.mtimes(rot, ca.DM(e[3:6]))
            v, vc = element_buoyancy(a, b, height + a[2], height + b[2], float(e[6]), float(e[7]),
                                     float(np.linalg.norm(e[3:6] - e[0:3])))
            volume, first = volume + v, first + vc
        weight = self.growth_mass * self.gravity
        first = rho_g * first - weight * ca.mtimes(rot, ca.DM(self.growth_centroid))
        force = ca.vertcat(0.0, 0.0, rho_g * volume - weight)
        return _out(ca.vertcat(force, ca.cross(first, ca.DM([0.0, 0.0, 1.0]))), q)

    def wave_load(self, q, terms):
        """The wave inertia at the reference point [N, N m] from the 15 :data:`WAVE_INERTIA_INPUTS` values."""
        x, w = _in(q, 6, "q"), _in(terms, 15, "terms")
        S = ca.reshape(w[6:15], 3, 3).T                      # row a, column b: Σ p_a F_b
        D = euler_zyx(x[3:6]) - ca.DM.eye(3)
        T = ca.mtimes(D, S)                                  # Σ ((R − I) p) F^T
        extra = ca.vertcat(T[1, 2] - T[2, 1], T[2, 0] - T[0, 2], T[0, 1] - T[1, 0])
        return _out(ca.vertcat(w[0:3], w[3:6] + extra), q, terms)

    def wave_terms(self, acceleration: np.ndarray, pressure: np.ndarray) -> np.ndarray:
        """``(T, 15)`` values of :data:`WAVE_INERTIA_INPUTS` from the waves' acceleration ``(T, n, 3)`` [m/s²] and
        dynamic pressure ``(T, n)`` [Pa] at :meth:`wave_points`."""
        f = np.einsum("nij,tnj->tni", self.inertia, acceleration) + pressure[:, :, None] * self.pressure[None]
        force = f.sum(axis=1)
        arm = self.points + self.offset[:, None] * self.axis
        moment = np.cross(arm[None], f).sum(axis=1)
        first = np.einsum("na,tnb->tab", self.points, f).reshape(len(f), 9)
        return np.hstack([force, moment, first])


@dataclass(frozen=True, eq=False)
class StripWaves:
    """The strip-theory members' wave inertia on the waves' time grid.

    Attributes
    ----------
    waves : IncidentWaves
    values : ndarray (N + 1, 15)
        :data:`WAVE_INERTIA_INPUTS` on ``waves.times()`` (the last sample repeats the first).
    """

    waves: object
    values: np.ndarray

    def tables(self, t: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Input tables ``name → (t, values)`` on the times ``t`` [s] (periodic cubic in time, as HydroDyn reads
        the kinematics: the terms are linear in them)."""
        values = catmull_rom(self.values, self.waves.time_step, np.atleast_1d(np.asarray(t, dtype=float)))
        return {name: (t, values[:, j]) for j, name in enumerate(WAVE_INERTIA_INPUTS)}


def strip_waves(strip: StripTheory, waves, sea) -> StripWaves:
    """:class:`StripWaves` of a sea (:class:`~.waves.IncidentWaves` and its SeaState input, whose grid the
    kinematics are read off, :func:`~.wave_kinematics.wave_acceleration_pressure`)."""
    acceleration, pressure = wave_acceleration_pressure(waves, sea, strip.wave_points(), strip.water_density)
    return StripWaves(waves, strip.wave_terms(acceleration, pressure))


def strip_problems(hd) -> list[str]:
    """What of a HydroDyn deck's strip-theory members (``PropPot = FALSE``) is not modelled, one phrase each."""
    members = _rows(hd, "members")
    if not members:
        return []
    lines = dict(zip([int(r[0]) for r in members], hd.tables["members"].lines))
    joints = {int(r[0]): np.array(r[1:4], dtype=float) for r in _rows(hd, "joints")}
    out = []
    for row in members:
        if row[10]:
            continue
        where = f"member {int(row[0])} (line {lines[int(row[0])]})"
        ends = [joints.get(int(row[j]), np.full(3, np.nan)) for j in (1, 2)]
        z = [float(e[2]) for e in ends]
        span = float(np.linalg.norm(ends[1] - ends[0]))
        if max(z) >= 0.0 and span > 0 and abs(z[1] - z[0]) < _STEEP * span:
            out.append(f"{where}: PropPot = FALSE, crossing or touching the still-water level at "
                       f"{math.degrees(math.asin(min(abs(z[1] - z[0]) / span, 1.0))):.1f} deg to it (z = {z[0]:g}, "
                       f"{z[1]:g} m): the waterline of a strip-theory member lying within "
                       f"{math.degrees(math.asin(_STEEP)):.1f} deg of the surface is not modelled")
        if int(row[9]) not in (0, 1, 2):
            out.append(f"{where}: MHstLMod = {int(row[9])} (0, 1 or 2)")
    return out


def strip_theory(hd, *, water_density: float, gravity: float, reference=(0.0, 0.0, 0.0)) -> StripTheory | None:
    """The :class:`StripTheory` of a HydroDyn input's ``PropPot = FALSE`` members (None without them).

    Parameters
    ----------
    hd : HydroDynInput
        Checked first by :func:`strip_problems` and :func:`~.morison.morison_problems`.
    water_density, gravity : float, keyword-only
        [kg/m³], [m/s²].
    reference : sequence of 3 floats, optional, keyword-only
        The platform reference point's undisplaced position [m].
    """
    members = [m for m in member_geometry(hd) if not m[0][10]]
    if not members:
        return None
    rho, ref = float(water_density), np.asarray(reference, dtype=float)
    joints = {int(r[0]): (np.array(r[1:4], dtype=float), int(r[4])) for r in _rows(hd, "joints")}
    axial = {int(r[0]): r for r in _rows(hd, "axial_coefficients")}
    growth = _rows(hd, "marine_growth")
    parts, ends = [], {}
    for row, p1, p2, r1, r2, coefficients in members:
        parts.append(_member(p1 - ref, p2 - ref, r1, r2, float(row[7]), coefficients, int(row[9]) != 0, rho,
                             float(ref[2]), growth))
        k = (p2 - p1) / np.linalg.norm(p2 - p1)
        for joint_id, sign, point, r in ((int(row[1]), -1.0, p1, r1), (int(row[2]), 1.0, p2, r2)):
            t, density = marine_growth(growth, point[2]), marine_growth(growth, point[2], 2)
            ends.setdefault(joint_id, []).append((sign * k, r + t, t, density))
    joint = _joints(ends, joints, axial, ref, rho)
    volume = sum(p["volume"] for p in parts)
    moment = sum(p["volume"] * p["centroid"] for p in parts) if volume > 0 else np.zeros(3)
    mass = sum(p["growth_mass"] for p in parts) + joint["growth_mass"]
    first = sum(p["growth_first"] for p in parts) + joint["growth_first"]
    added = sum(p["added_mass"] for p in parts) + joint["added_mass"]
    cat = {key: np.concatenate([p[key] for p in parts] + [joint[key]]) for key in
           ("points", "axis", "offset", "inertia", "pressure")}
    return StripTheory(float(volume), moment / volume if volume > 0 else np.zeros(3), added, **cat,
                       water_density=rho, gravity=float(gravity), reference=ref,
                       elements=np.vstack([p["elements"] for p in parts]), growth_mass=float(mass),
                       growth_centroid=first / mass if mass > 0 else np.zeros(3))


def _member(p1: np.ndarray, p2: np.ndarray, r1: float, r2: float, div: float, coefficients, buoyant: bool,
            rho: float, z0: float = 0.0, growth: list = ()) -> dict:
    """One member's buoyancy, added mass and wave-inertia points (module docstring); ``p1``, ``p2`` relative to the
    reference point, ``z0`` its height [m]. A member below the still-water level gives a constant volume and
    centroid, one reaching it its elements (:func:`~.waterline.element_buoyancy`)."""
    span = p2 - p1
    length = float(np.linalg.norm(span))
    if length <= 0:
        raise ParameterError(f"HydroDyn member from {p1.tolist()} to {p2.tolist()} has zero length.")
    n = math.ceil(length / div)
    dl, k = length / n, span / length
    s = np.arange(n + 1) / n
    pts = p1 + s[:, None] * span
    z = pts[:, 2] + z0
    thickness = np.array([marine_growth(growth, zi) for zi in z])
    bare = r1 + s * (r2 - r1)
    radius = bare + thickness
    c = coefficients(s, z, thickness > 0)
    slope = np.diff(radius) / dl
    signed = np.concatenate([[slope[0]], 0.5 * (slope[:-1] + slope[1:]), [slope[-1]]])
    absolute = np.concatenate([[abs(slope[0])], 0.5 * (np.abs(slope[:-1]) + np.abs(slope[1:])), [abs(slope[-1])]])
    left, right = _wet_lengths(z, dl)
    strip, offset = left + right, 0.5 * (right - left)
    keep = (z <= 0.0) & (strip > 0)
    kk = np.outer(k, k)
    area = math.pi * radius ** 2
    side = rho * area[:, None, None] * (c["Ca"][:, None, None] * (np.eye(3) - kk)
                                        + (2.0 * c["AxCa"] * absolute)[:, None, None] * kk)
    wave = rho * area[:, None, None] * ((c["Ca"] + c["Cp"])[:, None, None] * (np.eye(3) - kk)
                                        + (2.0 * c["AxCa"] * absolute)[:, None, None] * kk)
    added = sum((_point_mass(strip[i] * side[i], pts[i], offset[i] * k) for i in np.flatnonzero(keep)),
                np.zeros((6, 6)))
    density = np.array([marine_growth(growth, zi, 2) for zi in z])
    shell = _growth_shell(pts, k, bare, radius, density, dl)
    out = {"volume": 0.0, "centroid": np.zeros(3), "elements": np.zeros((0, 8)), "added_mass": added + shell[0],
           "growth_mass": shell[1], "growth_first": shell[2],
           "points": pts[keep], "axis": np.tile(k, (int(keep.sum()), 1)), "offset": offset[keep],
           "inertia": (strip[:, None, None] * wave)[keep],
           "pressure": ((strip * 2.0 * c["AxCp"] * math.pi * radius * signed)[:, None] * k)[keep]}
    if not buoyant:
        return out
    rb = radius * np.sqrt(c["Cb"])
    a, b = rb[:-1], rb[1:]
    if max(z[0], z[-1]) >= 0.0:
        out["elements"] = np.column_stack([pts[:-1], pts[1:], a, b])
        return out
    vol = math.pi * dl * (a ** 2 + a * b + b ** 2) / 3.0
    first = math.pi * dl ** 2 * (a ** 2 + 2 * a * b + 3 * b ** 2) / 12.0
    centre = pts[:-1] + (first / vol)[:, None] * k
    out["volume"], out["centroid"] = float(np.sum(vol)), vol @ centre / float(np.sum(vol))
    return out


def _wet_lengths(z: np.ndarray, dl: float) -> tuple[np.ndarray, np.ndarray]:
    """Each node's wet length toward node 1 and toward the last node (HydroDyn at the undisplaced heights ``z``:
    half of a wet neighbouring element, the wet part of one crossing the still-water level)."""
    wet = z <= 0.0
    left, right = np.zeros(z.size), np.zeros(z.size)
    for j in range(z.size - 1):
        for node, other, side in ((j, j + 1, right), (j + 1, j, left)):
            if wet[node]:
                side[node] = 0.5 * dl if wet[other] else dl * z[node] / (z[node] - z[other])
    return left, right


def _joints(ends: dict, joints: dict, axial: dict, ref: np.ndarray, rho: float) -> dict:
    """The end plates at the joints of strip-theory members (module docstring)."""
    pts, mass, pressure, added = [], [], [], np.zeros((6, 6))
    growth_mass, growth_first = 0.0, np.zeros(3)
    for ident, plates in ends.items():
        position, axial_id = joints[ident]
        vn = sum(2.0 * math.pi / 3.0 * r ** 3 * n for n, r, _, _ in plates)
        an = sum(math.pi * r ** 2 * n for n, r, _, _ in plates)
        plate = _growth_plate(plates, an, position - ref)
        added, growth_mass, growth_first = added + plate[0], growth_mass + plate[1], growth_first + plate[2]
        if position[2] > 0.0:                               # out of the water (undisplaced): HydroDyn's nodeInWater
            continue
        row = _lookup(axial, axial_id, f"joint {ident}: axial coefficients")
        size = float(np.linalg.norm(vn))
        m = rho * float(row[2]) / size * np.outer(vn, vn) if size > 1e-12 * sum(p[1] ** 3 for p in plates) \
            else np.zeros((3, 3))
        pts.append(position - ref)
        mass.append(m)
        pressure.append(-float(row[3]) * an)
        added = added + _point_mass(m, position - ref, np.zeros(3))
    return {"points": np.array(pts).reshape(-1, 3), "axis": np.zeros((len(pts), 3)), "offset": np.zeros(len(pts)),
            "inertia": np.array(mass).reshape(-1, 3, 3), "pressure": np.array(pressure).reshape(-1, 3),
            "added_mass": added, "growth_mass": growth_mass, "growth_first": growth_first}


#: Gauss–Legendre nodes and weights on [0, 1]: exact for the shell's polynomials in s (degree ≤ 6).
_GAUSS = tuple(np.polynomial.legendre.leggauss(4))


def _rigid(mass: float, first: np.ndarray, inertia: np.ndarray) -> np.ndarray:
    """6 × 6 mass matrix about the reference of a rigid body of ``mass``, first moment ``first`` (= mass × centroid)
    and inertia tensor ``inertia`` about the reference point."""
    F = _cross(first)
    return np.block([[mass * np.eye(3), -F], [F, inertia]])


def _growth_shell(pts: np.ndarray, k: np.ndarray, bare: np.ndarray, outer: np.ndarray, density: np.ndarray,
                  dl: float) -> tuple[np.ndarray, float, np.ndarray]:
    """The marine growth on a member's sides (HydroDyn's ``MarineGrowthPartSegmentCyl``: the shell between the bare
    and the grown radius, each linear along an element, at its lower node's density): its 6 × 6 mass matrix about
    the reference, mass [kg] and first moment [kg m], integrated over thin annular disks."""
    total, first, inertia = 0.0, np.zeros(3), np.zeros((3, 3))
    kk = np.outer(k, k)
    x, w = _GAUSS
    for j in range(len(pts) - 1):
        if density[j] <= 0 or (outer[j] <= bare[j] and outer[j + 1] <= bare[j + 1]):
            continue
        for xi, wi in zip(0.5 * (x + 1.0), 0.5 * w):
            ro = outer[j] + xi * (outer[j + 1] - outer[j])
            ri = bare[j] + xi * (bare[j + 1] - bare[j])
            dm = density[j] * math.pi * (ro * ro - ri * ri) * wi * dl
            p = pts[j] + xi * dl * k
            square = ro * ro + ri * ri
            total += dm
            first = first + dm * p
            inertia = inertia + dm * (0.25 * square * (np.eye(3) - kk) + 0.5 * square * kk
                                      + (p @ p) * np.eye(3) - np.outer(p, p))
    return _rigid(total, first, inertia), total, first


def _growth_plate(plates: list, an: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """The marine growth on a joint's end plates (HydroDyn's ``Mass_MG_End``, ``I_MG_End``): mass
    ``ρ_MG t |A_n|`` at the joint and the inertia ``ρ_MG t |I_n| (¼ (I − n nᵀ) + ½ n nᵀ)``, ``I_n = Σ ± π R⁴ k``
    (the grown radii), ``n`` along it."""
    t, density = plates[0][2], plates[0][3]
    if t <= 0 or density <= 0:
        return np.zeros((6, 6)), 0.0, np.zeros(3)
    mass = density * t * float(np.linalg.norm(an))
    i_n = sum(math.pi * r ** 4 * n for n, r, _, _ in plates)
    size = float(np.linalg.norm(i_n))
    n = i_n / size if size > 0 else np.array([0.0, 0.0, 1.0])
    own = density * t * size * (0.25 * (np.eye(3) - np.outer(n, n)) + 0.5 * np.outer(n, n))
    return _rigid(mass, mass * p, own + mass * ((p @ p) * np.eye(3) - np.outer(p, p))), mass, mass * p


def _cross(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _point_mass(m: np.ndarray, p: np.ndarray, h: np.ndarray) -> np.ndarray:
    """6 × 6 added mass about the reference of ``F = −m a_p`` at ``p`` with moment arm ``p + h`` (a_p: the
    acceleration of the point p, ``a − [p]× α``)."""
    P, H = _cross(p), _cross(p + h)
    return np.block([[m, -m @ P], [H @ m, -H @ m @ P]])
