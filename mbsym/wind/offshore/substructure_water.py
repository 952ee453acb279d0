"""HydroDyn's Morison loads on a bottom-fixed SubDyn substructure, as SubDyn receives them (OpenFAST v5.0.0).

With ``CompSub = 1`` OpenFAST's glue code gives HydroDyn's Morison mesh the motion of SubDyn's nodes and SubDyn the
mesh's loads as its external nodal loads ``F_ext`` (its ``LMesh``; :mod:`.substructure`). Both transfers are the NWTC
point-to-point mappings (``FAST_Mapping.f90``, ``ModMesh_Mapping.f90``: ``CreateMapping_NearestNeighbor``,
``Transfer_Loads_Point_to_Point``, read for the facts): each HydroDyn node is paired with its **nearest SubDyn
node** (the first in SubDyn's order on a tie); its force goes there with the moment ``(p_HD − p_SD) × F`` of the
offset added to its moment, and it moves with that node as a rigid arm. :func:`substructure_hydrodynamics` gives, in
SubDyn-node terms (N nodes, global axes, SI):

1. :attr:`SubstructureWater.static_loads` (6N): what HydroDyn applies to the undisplaced structure at rest in
   still water — buoyancy (``MHstLMod`` 1 with its end plates), the filled members' fluid (weight and pressure)
   and the marine growth's weight (:mod:`.morison_statics`; HydroDyn's discretization and seabed cut:
   :mod:`.morison_members`), and the drag of SeaState's steady current (``CurrMod = 1``;
   :mod:`.substructure_current`);
2. :attr:`SubstructureWater.added_mass` (6N × 6N): the loads proportional to the nodes' accelerations, ``F = −A ü``
   — side added mass (``C_a``, ``AMMod`` 0), the joints' end-plate added mass, the filled fluid's and the marine
   growth's mass — so that ``Φ_TPᵀ A Φ_TP`` is their TP-level mass (:meth:`SubstructureWater.tp_added_mass`);
3. the sea (first-order waves read off SeaState's grid, :mod:`.wave_kinematics`):
   :meth:`SubstructureWater.wave_loads` — Froude–Krylov and diffraction inertia ``(C_a + C_p)``, the axial
   dynamic-pressure terms of tapered sides and end plates, the end plates' inertia and the viscous drag, on the
   undisplaced structure **at rest**: the drag sees the water's velocity at rest (the waves' and the current's;
   with a current the waves' share is the drag of the sum less the current's own);
   :meth:`SubstructureWater.tp_wave_loads` their Guyan projection ``Φ_TPᵀ F`` as time-series inputs at the TP;
4. :meth:`SubstructureWater.drag_damping`: HydroDyn's drag takes the velocity relative to the moving node, and
   its slope ``B`` on the nodes' velocity (time-mean about the water's velocity at rest) is the first order of
   that dependence, which :mod:`.bottom_fixed` adds as a damping; :attr:`SubstructureWater.still_water_damping`
   is its value without waves: zero without a current (the drag is quadratic), the current's damping with one.

The structure's motion enters these loads through the added mass and the drag's slope. Left out: the drag's
higher orders in the nodes' velocity and its slope's correlation with the waves, the change of the buoyancy, fill
and growth loads with the displacement (a hydrostatic stiffness, first order in the rotation of the members' end
plates and axes: none for a vertical pile cut by the seabed, whose sides carry no vertical pressure), the added
mass's and the rigid parts' centripetal and gyroscopic terms (second order in the rates). The waves are read at the
undisplaced nodes, as HydroDyn does (``WaveDisp = 0``).
HydroDyn ignores ``AddF0``, ``AddCLin``, ``AddBLin`` and ``AddBQuad`` without potential flow (``HydroDyn.f90``: only
with ``PotMod = 1``), and so does this module (the IEA 15 MW monopile deck's heave ``AddBLin`` is not applied).

What OpenFAST does that matters here (and is reproduced): the nearest-node mapping above; HydroDyn's seabed cut of a
member reaching below ``−WtrDpth`` (no lower end plate, loads from the seabed up; :mod:`.morison_members`); a filled
member open to the sea through that cut has its fluid's pressure zero at the still-water level and weighs nothing
net but for the cut element's buried part (:mod:`.morison_statics`); the end plates of a member written from its
upper joint take the other end's radius and marine growth (a ``ModelWarning`` names such members).

**Refused** (:class:`~mbsym.exceptions.UnsupportedFeatureError`, :func:`substructure_water_problems`): potential
flow (``PotMod`` ≠ 0, ``PropPot``), wave stretching (``WaveStMod`` > 0), SeaState's user current (``CurrMod = 2``),
wave-current interaction (``WvCrntMod`` > 0 with waves and a current), second-order waves
(``WvDiffQTF``, ``WvSumQTF``), MacCamy–Fuchs members (``MCFD`` > 0), ``MSL2SWL`` ≠ 0, rectangular members, ``MCoefMod``
other than 1–3, ``MHstLMod`` 2, the end drag's filter (``AxVnCOff`` > 0), what HydroDyn itself refuses at
initialization (end plates cut by the still-water level, inclined or tapered members through the seabed), and
HydroDyn nodes off SubDyn's frame (farther from it than their member's radius: OpenFAST would carry their loads to
a distant node, and such a member is not part of the substructure whose motion is modelled).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ...exceptions import DimensionError, ModelWarning, UnsupportedFeatureError
from .current import current_problems
from .excitation import catmull_rom
from .frame_fem import rigid_transform
from .morison_members import MorisonFrame, morison_frame, substructure_member_problems
from .substructure_current import current_problems_with_waves, grid_current
from .morison_statics import fill_loads, growth_loads, hydrostatic_loads, joint_terms, nodal_mass
from .wave_kinematics import wave_acceleration_pressure, wave_flow
from .waves import IncidentWaves, incident_waves

__all__ = ["SubstructureWater", "substructure_hydrodynamics", "substructure_water_problems", "rest_reactions",
           "resultant"]


def _cross(v) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def resultant(loads, positions, point=(0.0, 0.0, 0.0)) -> np.ndarray:
    """Force [N] and moment [N m] about ``point`` [m] of nodal loads ``(..., 6 N)`` at ``positions`` (N, 3) [m]
    (HydroDyn's ``HydroFxi … HydroMzi`` convention: the sum about the origin, global axes)."""
    values = np.asarray(loads, dtype=float)
    n = len(positions)
    if values.shape[-1] != 6 * n:
        raise DimensionError(f"`loads` has {values.shape[-1]} columns; expected {6 * n} (6 per node).")
    nodal = values.reshape(*values.shape[:-1], n, 6)
    arm = np.asarray(positions, dtype=float) - np.asarray(point, dtype=float)
    force = nodal[..., :3].sum(axis=-2)
    moment = (nodal[..., 3:] + np.cross(arm, nodal[..., :3])).sum(axis=-2)
    return np.concatenate([force, moment], axis=-1)


@dataclass(frozen=True, eq=False)
class _WavePoints:
    """Where HydroDyn's wave loads act: strip nodes and wet joints (m points), per point its HydroDyn node, moment arm
    ``h k`` from it, ``inertia`` (3 × 3, F per wave acceleration) [kg], ``pressure`` (3,) [m²], side drag across the
    axis ``k`` and along it [kg/m], end-plate drag along ``normal`` [kg/m] and whether one-sided (``AxFDMod`` 1)."""

    node: np.ndarray
    arm: np.ndarray
    inertia: np.ndarray
    pressure: np.ndarray
    axis: np.ndarray
    drag: np.ndarray
    axial_drag: np.ndarray
    normal: np.ndarray
    end_drag: np.ndarray
    one_sided: np.ndarray


@dataclass(frozen=True, eq=False)
class SubstructureWater:
    """HydroDyn's Morison loads in SubDyn-node terms (module docstring); N SubDyn nodes, SI units, global axes.

    Attributes
    ----------
    static_loads : ndarray, shape (6 N,)
        Time-invariant nodal loads at rest in still water [N, N m] (node k: entries 6k … 6k+5).
    added_mass : ndarray, shape (6 N, 6 N)
        ``A`` [kg, kg m, kg m²]: the water's, the fill's and the growth's loads ``−A ü`` (node accelerations and
        angular accelerations). Block diagonal; not exactly symmetric (HydroDyn's strip-centroid moments).
    parts : dict of str to ndarray (6 N,)
        :attr:`static_loads` by origin: ``buoyancy``, ``fill``, ``growth``.
    tp_shapes : ndarray, shape (6 N, 6)
        ``Φ_TP`` (:attr:`~.substructure.ReducedSubstructure.tp_shapes`).
    positions : ndarray, shape (N, 3)
        SubDyn's node positions [m].
    hydrodyn : MorisonFrame
        HydroDyn's Morison mesh (:mod:`.morison_members`).
    node_map : ndarray of int, shape (n,)
        The SubDyn node each HydroDyn node is mapped to.
    waves : IncidentWaves or None
        The sea (None: still water).
    current : ndarray, shape (n, 3), or None
        SeaState's steady current at HydroDyn's nodes [m/s] (:mod:`.current`; None: no current).
    """

    static_loads: np.ndarray
    added_mass: np.ndarray
    parts: dict
    tp_shapes: np.ndarray
    positions: np.ndarray
    hydrodyn: MorisonFrame
    node_map: np.ndarray
    waves: IncidentWaves | None
    current: np.ndarray | None
    _points: _WavePoints
    _operator: np.ndarray
    _motion: np.ndarray
    _kinematics: tuple | None

    @property
    def n_nodes(self) -> int:
        """N, SubDyn's nodes."""
        return len(self.positions)

    @property
    def tp_static_load(self) -> np.ndarray:
        """``Φ_TPᵀ`` :attr:`static_loads` (6,) [N, N m]: their part of SubDyn's TP load at rest (add the substructure's
        :attr:`~.substructure.ReducedSubstructure.gravity_load` for SubDyn's ``Y1``)."""
        return self.tp_shapes.T @ self.static_loads

    def tp_added_mass(self, symmetric: bool = False) -> np.ndarray:
        """``Φ_TPᵀ A Φ_TP`` (6 × 6) [kg, kg m, kg m²] at the TP (``symmetric``: its symmetric part)."""
        out = self.tp_shapes.T @ self.added_mass @ self.tp_shapes
        return 0.5 * (out + out.T) if symmetric else out

    @property
    def still_water_damping(self) -> np.ndarray:
        """``−∂F/∂u̇`` at rest without waves (6 N × 6 N) [N s/m, …]: the current's drag slope (:meth:`drag_damping`
        about the current alone); zero without a current, the drag being quadratic in the relative velocity."""
        return self._blocks(drag_slope(self._points, self._current_at_points()[None]))

    def times(self) -> np.ndarray:
        """SeaState's time grid ``0, WaveDT, … WaveTMax`` [s] (empty in still water)."""
        return np.zeros(0) if self.waves is None else self.waves.times()

    def _kinematics_at(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Velocity, acceleration ``(T, m, 3)`` and pressure ``(T, m)`` at the wave points (periodic cubic in time)."""
        velocity, acceleration, pressure = self._kinematics
        if t is not None:
            step, times = self.waves.time_step, np.atleast_1d(np.asarray(t, dtype=float))
            flat = catmull_rom(np.concatenate([velocity.reshape(len(velocity), -1), acceleration.reshape(
                len(velocity), -1), pressure], axis=1), step, times)
            n = velocity.shape[1] * 3
            velocity, acceleration, pressure = (flat[:, :n].reshape(len(times), -1, 3),
                                                flat[:, n:2 * n].reshape(len(times), -1, 3), flat[:, 2 * n:])
        node = self._points.node
        return velocity[:, node], acceleration[:, node], pressure[:, node]

    def point_forces(self, t=None, *, inertia: bool = True, drag: bool = True) -> np.ndarray:
        """The waves' forces ``(T, 3 m)`` [N] at the wave points (before the moment arms and the mapping); with a
        current the drag's part is ``D(u + U) − D(U)``, the current's own drag ``D(U)`` being in
        :attr:`static_loads`."""
        p = self._points
        if self._kinematics is None:
            count = 0 if t is None else len(np.atleast_1d(t))
            return np.zeros((count, 3 * len(p.node)))
        v, a, pressure = self._kinematics_at(t)
        f = np.zeros_like(v)
        if inertia:
            f += np.einsum("mij,tmj->tmi", p.inertia, a) + pressure[:, :, None] * p.pressure[None]
        if drag:
            steady = self._current_at_points()
            f += drag_forces(p, v + steady[None]) - drag_forces(p, steady[None])
        return f.reshape(len(f), -1)

    def _current_at_points(self) -> np.ndarray:
        """SeaState's current ``(m, 3)`` [m/s] at the wave points (zero without one)."""
        return np.zeros((len(self._points.node), 3)) if self.current is None else self.current[self._points.node]

    def wave_loads(self, t=None, *, inertia: bool = True, drag: bool = True) -> np.ndarray:
        """The waves' nodal loads ``(len(t), 6 N)`` [N, N m] on the structure at rest (module docstring).

        Parameters
        ----------
        t : array_like, optional
            Times [s]; default SeaState's grid (:meth:`times`). Between its samples the kinematics are interpolated
            as HydroDyn reads them (periodic cubic), then the loads computed (the drag is not linear in them).
        inertia, drag : bool, keyword-only
            Include the inertia (Froude–Krylov, diffraction, pressure) and the drag terms.
        """
        if self.waves is None and t is None:
            return np.zeros((0, 6 * self.n_nodes))
        return self.point_forces(t, inertia=inertia, drag=drag) @ self._operator.T

    def tp_wave_loads(self, t=None, **terms) -> np.ndarray:
        """``Φ_TPᵀ`` :meth:`wave_loads` ``(len(t), 6)`` [N, N m]: the waves' part of SubDyn's TP load with the
        structure at rest (surge … yaw order, global axes at the TP reference point)."""
        return self.wave_loads(t, **terms) @ self.tp_shapes

    def drag_damping(self, t=None) -> np.ndarray:
        """The time-mean slope ``B̄ = −⟨∂F/∂u̇⟩`` (6 N × 6 N) [N s/m, …] of HydroDyn's drag on the node velocities,
        about the water's velocity at rest (waves and current: ``F(v_w + U − ṙ) ≈ F(v_w + U) − B ṙ``).

        Per strip ``∂(c |v_n| v_n)/∂v = c (|v_n| P + v_n v_nᵀ/|v_n|)`` (``P = I − k kᵀ``), the axial and end-plate
        terms alike; each strip moves with its HydroDyn node (the node's velocity, as HydroDyn takes it). In still
        water it is the current's alone (zero without one); ``t`` [s]: the times of the mean (default SeaState's
        grid).
        """
        p = self._points
        steady = self._current_at_points()
        if self._kinematics is None:
            v = steady[None]
        else:
            v = self._kinematics_at(t)[0] + steady[None]
        return self._blocks(drag_slope(p, v))

    def _blocks(self, slope: np.ndarray) -> np.ndarray:
        """Per-point slopes ``(m, 3, 3)`` as a nodal damping (6 N × 6 N) through the points' arms and the mapping."""
        m = len(self._points.node)
        blocks = np.zeros((3 * m, 3 * m))
        for k in range(m):
            blocks[3 * k:3 * k + 3, 3 * k:3 * k + 3] = slope[k]
        return self._operator @ blocks @ self._motion

    def tp_drag_damping(self, t=None) -> np.ndarray:
        """``Φ_TPᵀ`` :meth:`drag_damping` ``Φ_TP`` (6 × 6) at the TP."""
        return self.tp_shapes.T @ self.drag_damping(t) @ self.tp_shapes

    def resultant(self, loads, point=(0.0, 0.0, 0.0)) -> np.ndarray:
        """:func:`resultant` of nodal loads ``(..., 6 N)`` at SubDyn's nodes."""
        return resultant(loads, self.positions, point)


def substructure_water_problems(hydrodyn, seastate=None, *, water_depth: float, msl_to_swl: float = 0.0) -> list[str]:
    """What of a HydroDyn and SeaState input :func:`substructure_hydrodynamics` does not model (one phrase each,
    naming the file, line and key)."""
    hd, sea = hydrodyn, seastate
    out = []

    def where(deck, key):
        return f"{deck.path}, line {deck.lines.get(key, '?')}, key '{key}'"

    if hd.potential_model != 0:
        out.append(f"{where(hd, 'PotMod')}: PotMod = {hd.potential_model} (potential flow) on a SubDyn substructure is "
                   "not modelled; use 0 (strip theory on every member)")
    out += [f"{hd.path}, {p}" for p in substructure_member_problems(hd, water_depth)]
    if sea is None:
        return out
    offset = msl_to_swl if sea.msl_to_swl == "default" else float(sea.msl_to_swl)
    if offset != 0.0:
        out.append(f"{where(sea, 'MSL2SWL')}: MSL2SWL = {offset:g} m is not modelled; use 0")
    if sea.wave_model != 0 and sea.stretching_model != 0:
        out.append(f"{where(sea, 'WaveStMod')}: WaveStMod = {sea.stretching_model} (wave stretching) is not modelled; "
                   "use 0")
    out += [f"{where(sea, 'CurrMod')}: {p}" for p in current_problems(sea)]
    out += [f"{where(sea, 'WvCrntMod')}: {p}" for p in current_problems_with_waves(sea)]
    if sea.wave_model != 0:
        for key, on in (("WvDiffQTF", sea.difference_qtf), ("WvSumQTF", sea.sum_qtf)):
            if on:
                out.append(f"{where(sea, key)}: second-order wave kinematics are not modelled; set {key} False")
        if float(sea.maccamy_fuchs_radius or 0.0) > 0.0:
            out.append(f"{where(sea, 'MCFD')}: MacCamy-Fuchs members (MCFD = {sea.maccamy_fuchs_radius}) are not "
                       "modelled; use 0")
    return out


def substructure_hydrodynamics(hydrodyn, seastate, substructure, *, water_density: float, gravity: float,
                               water_depth: float, msl_to_swl: float = 0.0) -> SubstructureWater:
    """HydroDyn's Morison loads on a SubDyn substructure's nodes (module docstring).

    Parameters
    ----------
    hydrodyn : HydroDynInput
        From :func:`~mbsym.wind.deck.hydrodyn.read_hydrodyn` (``PotMod`` 0: every member by strip theory).
    seastate : SeaStateInput or None
        From :func:`~mbsym.wind.deck.seastate.read_seastate`; None or ``WaveMod`` 0: still water.
    substructure : Substructure
        The SubDyn model (:class:`~.substructure.Substructure`): its nodes receive the loads.
    water_density, gravity, water_depth : float, keyword-only
        SeaState's ``WtrDens`` [kg/m³] and ``WtrDpth`` [m] (the seabed; resolved against the ``.fst``), the
        ``.fst``'s ``Gravity`` [m/s²].
    msl_to_swl : float, keyword-only
        The ``.fst``'s ``MSL2SWL`` [m], for a SeaState ``MSL2SWL`` of ``default`` (must be 0).

    Returns
    -------
    SubstructureWater

    Raises
    ------
    UnsupportedFeatureError
        What :func:`substructure_water_problems` lists, and HydroDyn nodes off SubDyn's frame.
    ParameterError
        A member naming a joint, property set or coefficient row that does not exist.

    Examples
    --------
    >>> water = substructure_hydrodynamics(read_hydrodyn(hd_file), read_seastate(sea_file), sub,
    ...                                    water_density=1025.0, gravity=9.81, water_depth=30.0)  # doctest: +SKIP
    >>> water.tp_wave_loads(np.arange(0.0, 60.0, 0.05)).shape  # doctest: +SKIP
    (1200, 6)
    """
    problems = substructure_water_problems(hydrodyn, seastate, water_depth=water_depth, msl_to_swl=msl_to_swl)
    if problems:
        raise UnsupportedFeatureError("HydroDyn on a SubDyn substructure: " + "; ".join(problems) + ".")
    if hydrodyn.wave_displaced and seastate is not None and (seastate.wave_model != 0 or seastate.current_model):
        line = hydrodyn.lines.get("WaveDisp", "?")
        warnings.warn(f"{hydrodyn.path}, line {line}, key 'WaveDisp': WaveDisp = 1 reads "
                      "the waves and the current at the displaced nodes; mbsym reads them at the undisplaced ones (the "
                      "same at rest, second order in the motion of a bottom-fixed structure).", ModelWarning,
                      stacklevel=2)
    rho, g = float(water_density), float(gravity)
    frame = morison_frame(hydrodyn, water_depth=float(water_depth), water_density=rho)
    _warn_flipped_ends(frame, hydrodyn.path)
    sd = substructure.frame
    positions = np.asarray(sd.positions, dtype=float)
    node_map = _nearest(frame.positions, positions)
    _check_on_frame(frame, sd, hydrodyn.path)
    fill, fill_mass = fill_loads(frame, hydrodyn, rho, g)
    growth, growth_mass = growth_loads(frame, g)
    parts_hd = {"buoyancy": hydrostatic_loads(frame, rho, g), "fill": fill, "growth": growth}
    transforms = [rigid_transform(frame.positions[h] - positions[s]) for h, s in enumerate(node_map)]
    n = len(positions)
    parts = {}
    for name, loads in parts_hd.items():
        out = np.zeros((n, 6))
        for h, s in enumerate(node_map):
            out[s] += transforms[h].T @ loads[h]
        parts[name] = out.reshape(-1)
    hd_mass = nodal_mass(frame, rho) + fill_mass + growth_mass
    mass = np.zeros((6 * n, 6 * n))
    for h, s in enumerate(node_map):
        if np.any(hd_mass[h]):
            mass[6 * s:6 * s + 6, 6 * s:6 * s + 6] += transforms[h].T @ hd_mass[h] @ transforms[h]
    points = _wave_points(frame, rho)
    operator, motion = _point_operators(points, frame.positions, positions, node_map)
    waves, kinematics = None, None
    if seastate is not None and seastate.wave_model != 0:
        waves = incident_waves(seastate, gravity=g, water_depth=float(water_depth))
        kinematics = _kinematics(waves, seastate, frame.positions, points.node, rho)
    current = None
    if seastate is not None and seastate.current_model:
        # SeaState adds the current to its grid's velocity; HydroDyn's drag takes the sum (module docstring)
        current = grid_current(seastate, float(water_depth), frame.positions)
        parts["current"] = operator @ drag_forces(points, current[points.node][None])[0].reshape(-1)
    tp_shapes = np.asarray(substructure.guyan().tp_shapes, dtype=float)
    return SubstructureWater(sum(parts.values()), mass, parts, tp_shapes, positions, frame, node_map, waves, current,
                             points, operator, motion, kinematics)


def _warn_flipped_ends(frame: MorisonFrame, path: str) -> None:
    """Name the members written downward whose end plates HydroDyn gives the other end's radius or growth."""
    for m in frame.members:
        joints = [frame.positions[m.nodes[j]][2] >= -frame.water_depth for j in (0, -1)]
        differ = not (np.isclose(m.radius[0], m.radius[-1]) and np.isclose(m.growth_density[0], m.growth_density[-1]))
        if m.flipped and differ and any(joints):
            warnings.warn(f"{path}, line {m.line}, member {m.ident}: written from its upper joint, so HydroDyn v5.0.0 "
                          "(Morison_Init) gives its end plates the radius and marine growth of the member's other "
                          "end; mbsym does the same, to match OpenFAST. Write the member from its lower joint "
                          "(MJointID1 the lower one) for the plates' own values.", ModelWarning, stacklevel=3)


def _nearest(source: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The NWTC nearest-neighbour map: for each source point the first target point at the smallest distance."""
    distance = np.linalg.norm(source[:, None, :] - target[None, :, :], axis=2)
    return np.argmin(distance, axis=1)


def _check_on_frame(frame: MorisonFrame, sd, path: str) -> None:
    """Refuse HydroDyn member nodes (at or above the seabed) farther from SubDyn's elements than their radius."""
    ends = np.asarray(sd.positions, dtype=float)[np.asarray(sd.elements, dtype=int)]
    a, b = ends[:, 0], ends[:, 1]
    span = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", span, span), 1e-300)
    for m in frame.members:
        for j in range(min(m.floor, m.n_elements), m.n_elements + 1):
            p = m.points[j]
            t = np.clip(np.einsum("ij,ij->i", p - a, span) / length2, 0.0, 1.0)
            gap = float(np.min(np.linalg.norm(p - (a + t[:, None] * span), axis=1)))
            if gap > max(m.radius[j], 1e-3):
                raise UnsupportedFeatureError(
                    f"{path}, line {m.line}, member {m.ident}: its node at {np.round(p, 3).tolist()} m is {gap:.3g} m "
                    f"from SubDyn's frame, more than its radius {m.radius[j]:.3g} m. OpenFAST would carry its loads to "
                    "the nearest SubDyn node with that lever arm; mbsym models HydroDyn members that lie on the "
                    "SubDyn structure only. Move the member onto a SubDyn member or add the member to SubDyn.")


def _wave_points(frame: MorisonFrame, rho: float) -> _WavePoints:
    """The side strips (drag and inertia) and the wet joints' end plates (module docstring)."""
    rows = []
    for m in frame.members:
        length, offset = m.strips()
        slope, signed = m.slopes()
        c, k, r = m.coefficients, m.axis, m.radius
        kk = np.outer(k, k)
        for j in np.flatnonzero(length > 0.0):
            inertia = rho * math.pi * r[j] ** 2 * ((c["Ca"][j] + c["Cp"][j]) * (np.eye(3) - kk)
                                                   + 2 * c["AxCa"][j] * slope[j] * kk)
            rows.append((m.nodes[j], offset[j] * k, length[j] * inertia,
                         length[j] * 2 * c["AxCp"][j] * math.pi * r[j] * signed[j] * k, k,
                         length[j] * c["Cd"][j] * rho * r[j], length[j] * 0.5 * c["AxCd"][j] * rho * math.pi * r[j]
                         * slope[j], np.zeros(3), 0.0, False))
    for node, added, pressure, normal, drag, mode in joint_terms(frame, rho):
        if frame.positions[node][2] <= 0.0:
            rows.append((node, np.zeros(3), added, pressure, np.zeros(3), 0.0, 0.0, normal,
                         (0.5 if mode == 1 else 0.25) * rho * drag, mode == 1))
    fields = list(zip(*rows)) if rows else [()] * 10
    shapes = ((), (3,), (3, 3), (3,), (3,), (), (), (3,), (), ())
    arrays = [np.array(f, dtype=float).reshape(-1, *s) for f, s in zip(fields, shapes)]
    return _WavePoints(arrays[0].astype(int), *arrays[1:9], arrays[9].astype(bool))


def drag_forces(p: _WavePoints, v: np.ndarray) -> np.ndarray:
    """HydroDyn's drag ``(T, m, 3)`` [N] at the wave points for the water's velocity ``v`` (T, m, 3) [m/s] relative to
    the points (``Morison.f90``, ``Morison_CalcOutput``: the sides' ``C_d ρ r |v_n| v_n`` across the axis and the
    axial ``½ AxCd ρ π r dr/dl |v_k| v_k``, the end plates' ``|v_n| v_n`` along their normal, one-sided with
    ``AxFDMod`` 1)."""
    along = np.einsum("tmi,mi->tm", v, p.axis)
    across = v - along[:, :, None] * p.axis[None]
    size = np.linalg.norm(across, axis=2)
    f = (p.drag * size)[:, :, None] * across + (p.axial_drag * np.abs(along) * along)[:, :, None] * p.axis
    vn = np.einsum("tmi,mi->tm", v, p.normal)
    side = np.where(p.one_sided, np.maximum(vn, 0.0), vn)
    return f + (p.end_drag * np.abs(vn) * side)[:, :, None] * p.normal


def drag_slope(p: _WavePoints, v: np.ndarray) -> np.ndarray:
    """``⟨∂D/∂v⟩`` ``(m, 3, 3)`` [kg/s] of :func:`drag_forces`, averaged over the T samples of ``v`` (T, m, 3)."""
    along = np.einsum("tmi,mi->tm", v, p.axis)
    across = v - along[:, :, None] * p.axis[None]
    size = np.linalg.norm(across, axis=2)
    unit = np.divide(across, size[:, :, None], out=np.zeros_like(across), where=size[:, :, None] > 0)
    plane = np.eye(3)[None] - np.einsum("mi,mj->mij", p.axis, p.axis)
    slope = p.drag[:, None, None] * (size.mean(axis=0)[:, None, None] * plane
                                     + np.einsum("tm,tmi,tmj->mij", size, unit, unit) / len(v))
    slope += (2.0 * p.axial_drag * np.abs(along).mean(axis=0))[:, None, None] * np.einsum("mi,mj->mij", p.axis,
                                                                                           p.axis)
    vn = np.einsum("tmi,mi->tm", v, p.normal)
    end = np.where(p.one_sided, 2.0 * np.maximum(vn, 0.0), 2.0 * np.abs(vn)).mean(axis=0)
    return slope + (p.end_drag * end)[:, None, None] * np.einsum("mi,mj->mij", p.normal, p.normal)


def _point_operators(p: _WavePoints, hd_positions, sd_positions, node_map) -> tuple[np.ndarray, np.ndarray]:
    """``G`` (6 N × 3 m): a point force's SubDyn-node load (its own arm and the mapping's offset); ``V`` (3 m × 6 N):
    the velocity of each point's HydroDyn node from SubDyn's node motion."""
    n, m = len(sd_positions), len(p.node)
    load, motion = np.zeros((6 * n, 3 * m)), np.zeros((3 * m, 6 * n))
    for k, h in enumerate(p.node):
        s = node_map[h]
        offset = hd_positions[h] - sd_positions[s]
        load[6 * s:6 * s + 3, 3 * k:3 * k + 3] = np.eye(3)
        load[6 * s + 3:6 * s + 6, 3 * k:3 * k + 3] = _cross(offset + p.arm[k])
        motion[3 * k:3 * k + 3, 6 * s:6 * s + 6] = rigid_transform(offset)[:3]
    return load, motion


def _kinematics(waves: IncidentWaves, sea, positions: np.ndarray, nodes: np.ndarray, rho: float) -> tuple:
    """Velocity, acceleration ``(T + 1, n, 3)`` and dynamic pressure ``(T + 1, n)`` at every HydroDyn node that
    carries a wave point (zero elsewhere) on SeaState's grid."""
    used = np.unique(nodes)
    velocity = np.zeros((waves.n_steps + 1, len(positions), 3))
    acceleration, pressure = np.zeros_like(velocity), np.zeros(velocity.shape[:2])
    if len(used):
        velocity[:, used] = wave_flow(waves, sea, positions[used]).velocity
        acceleration[:, used], pressure[:, used] = wave_acceleration_pressure(waves, sea, positions[used], rho)
    return velocity, acceleration, pressure


def rest_reactions(substructure, nodal_loads) -> np.ndarray:
    """SubDyn's base reactions ``ReactFXss … ReactMZss`` ``(..., 6)`` [N, N m] of a Guyan substructure held at rest
    (TP fixed) under the nodal loads ``(..., 6 N)`` besides gravity, about SubDyn's base point ``(0, 0, −WtrDpth)``:
    the elements' elastic forces at the reaction joints on the static solution of the interior (``SttcSolve``) under
    gravity and the loads, less the joints' own external loads (``SDOut_MapOutputs``: not their weight, the element
    gravity term of its element forces being zero in v5.0.0). Quasi-static: exact for a Guyan reduction."""
    sub = substructure
    if sub.settings.n_modes != 0 or not sub.settings.static_improvement:
        raise UnsupportedFeatureError(f"{sub.settings.path}: rest_reactions needs a Guyan reduction (Nmodes = 0) with "
                                      "SttcSolve = True (SubDyn's quasi-static interior).")
    reduced = sub.guyan()
    frame = sub.frame
    loads = np.atleast_2d(np.asarray(nodal_loads, dtype=float))
    total = loads + np.asarray(frame.gravity_load, dtype=float)[None]
    fixed = np.asarray(sub.fixed_dofs, dtype=int)
    stiffness = np.asarray(frame.stiffness, dtype=float)[fixed]
    base = np.asarray(sub.base_point, dtype=float)
    out = np.zeros((len(total), 6))
    for row, f, external in zip(out, total, loads):
        displacement = reduced.node_displacements(np.zeros(6), static_loads=f).reshape(-1)
        forces = stiffness @ displacement - external[fixed]
        for k in range(len(fixed) // 6):
            block = forces[6 * k:6 * k + 6]
            arm = np.asarray(frame.positions[fixed[6 * k] // 6], dtype=float) - base
            row += np.r_[block[:3], block[3:] + np.cross(arm, block[:3])]
    return out.reshape(*np.shape(nodal_loads)[:-1], 6)
