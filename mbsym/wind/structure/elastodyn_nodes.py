"""ElastoDyn-style discretisation and integration of tower and blade properties.

ElastoDyn splits the flexible tower (length TowerHt - TowerBsHt) into TwrNodes and
each blade (length TipRad - HubRad) into BldNodes **equal** elements, places one
analysis node at each element midpoint, interpolates the distributed input
properties linearly (in the station fraction) onto the nodes and multiplies by
the adjustment factors (AdjTwMa, AdjFASt, AdjSSSt, AdjBlMs, AdjFlSt, AdjEdSt).
Every integral is then a midpoint sum, element length times the value at the
node.  This module reproduces those definitions (subroutine ``Coeff`` of
OpenFAST's ``ElastoDyn.f90``) so that results can be compared with ElastoDyn's
``.ED.sum`` summary and used to build ElastoDyn-equivalent models:

* blade mass, first and second mass moments **about the blade root** and the
  blade centre of mass measured **from the root** (ElastoDyn's BldMass,
  FirstMom, SecondMom, BldCG), tip masses included at the tip;
* rotor mass (hub + blades) and rotor inertia about the shaft axis,
  ``HubIner + sum_k (SecondMom + BldMass*HubRad*(2*BldCG + HubRad)) cos^2(PreCone_k)``
  (3 blades; for 2 blades ElastoDyn's hub term is handled like ``Hubg1Iner``);
* tower mass and tower-top mass (rotor + nacelle + yaw bearing);
* generalized masses and stiffnesses of the polynomial mode shapes, the tower's
  gravitational and the blades' centrifugal stiffening terms, and the natural
  frequencies ElastoDyn derives from them (FreqTFA, FreqTSS, FreqBF, FreqBE).
  ElastoDyn v5 no longer prints these frequencies in its summary; they are
  uncoupled (one mode at a time, no twist coupling) by definition.

Concentrated tower masses (``NTwCMass``, ``TwCMass`` at ``TwCMassHtFract``) join the mass density of the tower
element that holds them, as ElastoDyn's ``SetTowerParameters`` does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import ParameterError
from ..deck.parameters import TurbineParameters

__all__ = [
    "TowerNodes", "BladeNodes", "RotorMassProperties", "TowerModalProperties",
    "BladeModalProperties", "tower_nodes", "blade_nodes", "rotor_mass_properties",
    "tower_mass", "tower_top_mass", "tower_modal_properties", "blade_modal_properties",
    "mode_shape",
]

_POWERS = np.arange(2, 7)


@dataclass(frozen=True)
class TowerNodes:
    """Tower analysis nodes (element midpoints), ElastoDyn's HNodes table.

    Attributes
    ----------
    fraction : ndarray
        Node height over the flexible length, (j - 1/2)/TwrNodes [-] (TwFract).
    height : ndarray
        Node height above the tower base (TowerBsHt) [m] (HNodes).
    length : ndarray
        Element lengths [m] (DHNodes).
    mass_density, fa_stiffness, ss_stiffness : ndarray
        Interpolated properties with the adjustment factors applied [kg/m], [N m^2].
    """

    fraction: np.ndarray
    height: np.ndarray
    length: np.ndarray
    mass_density: np.ndarray
    fa_stiffness: np.ndarray
    ss_stiffness: np.ndarray


@dataclass(frozen=True)
class BladeNodes:
    """Blade analysis nodes (element midpoints), ElastoDyn's RNodes table.

    Attributes
    ----------
    fraction : ndarray
        Node span over the flexible length [-] (BlFract column of the summary).
    span : ndarray
        Distance from the blade root [m] (ElastoDyn's internal RNodes).
    radius : ndarray
        Distance from the rotor apex along the blade, ``span + HubRad`` [m] (the
        RNodes column ElastoDyn prints).
    length : ndarray
        Element lengths [m] (DRNodes).
    structural_twist : ndarray
        [rad].
    mass_density, flap_stiffness, edge_stiffness : ndarray
        Interpolated properties with the adjustment factors applied [kg/m], [N m^2].
    """

    fraction: np.ndarray
    span: np.ndarray
    radius: np.ndarray
    length: np.ndarray
    structural_twist: np.ndarray
    mass_density: np.ndarray
    flap_stiffness: np.ndarray
    edge_stiffness: np.ndarray


@dataclass(frozen=True)
class RotorMassProperties:
    """ElastoDyn's rotor mass summary.  Per-blade tuples are in blade order.

    Attributes
    ----------
    blade_mass : tuple of float
        [kg], tip mass included.
    first_mass_moment : tuple of float
        About the blade root [kg m].
    second_mass_moment : tuple of float
        About the blade root [kg m^2].
    blade_cg : tuple of float
        Centre of mass from the blade root [m].
    rotor_mass : float
        Hub plus blades [kg].
    rotor_inertia : float
        About the shaft axis, hub included [kg m^2].
    """

    blade_mass: tuple[float, ...]
    first_mass_moment: tuple[float, ...]
    second_mass_moment: tuple[float, ...]
    blade_cg: tuple[float, ...]
    rotor_mass: float
    rotor_inertia: float


@dataclass(frozen=True)
class TowerModalProperties:
    """Generalized properties of ElastoDyn's tower modes (modes 1 and 2).

    Attributes
    ----------
    fa_mass, ss_mass : ndarray, shape (2,)
        Generalized mass of the tower alone, sum m dh phi^2 [kg].
    top_mass : float
        Tower-top mass [kg]; it adds to the generalized mass (phi = 1 at the top).
    fa_stiffness, ss_stiffness : ndarray, shape (2, 2)
        Elastic generalized stiffness with the modal tuners applied [N/m].
    fa_gravity_stiffness, ss_gravity_stiffness : ndarray, shape (2,)
        Gravitational (destabilising, negative) generalized stiffness [N/m].
    fa_frequency, ss_frequency : ndarray, shape (2,)
        Without gravity and without the top mass [Hz] (ElastoDyn FreqT*(:,1)).
    fa_frequency_loaded, ss_frequency_loaded : ndarray, shape (2,)
        With gravity and the top mass [Hz] (ElastoDyn FreqT*(:,2)).
    """

    fa_mass: np.ndarray
    ss_mass: np.ndarray
    top_mass: float
    fa_stiffness: np.ndarray
    ss_stiffness: np.ndarray
    fa_gravity_stiffness: np.ndarray
    ss_gravity_stiffness: np.ndarray
    fa_frequency: np.ndarray
    ss_frequency: np.ndarray
    fa_frequency_loaded: np.ndarray
    ss_frequency_loaded: np.ndarray


@dataclass(frozen=True)
class BladeModalProperties:
    """Generalized properties of ElastoDyn's blade modes (flap 1, 2 and edge 1).

    Attributes
    ----------
    flap_mass : ndarray, shape (2,)
        Generalized mass including the tip mass [kg].
    edge_mass : ndarray, shape (1,)
        [kg].
    flap_stiffness : ndarray, shape (2, 2)
        Elastic generalized stiffness with the tuners applied [N/m].
    edge_stiffness : ndarray, shape (1,)
        [N/m].
    flap_centrifugal_stiffness, edge_centrifugal_stiffness : ndarray
        Centrifugal generalized stiffness per unit rotor speed squared,
        shapes (2,) and (1,) [kg] (multiply by Omega^2 [rad^2/s^2]).
    flap_frequency, edge_frequency : ndarray
        Non-rotating, without tip mass [Hz] (ElastoDyn FreqB*(:,1)).
    flap_frequency_rotating, edge_frequency_rotating : ndarray
        With tip mass and centrifugal stiffening at ``rotor_speed`` [Hz]
        (ElastoDyn FreqB*(:,3)).
    rotor_speed : float
        Speed used for the rotating frequencies [rad/s].
    """

    flap_mass: np.ndarray
    edge_mass: np.ndarray
    flap_stiffness: np.ndarray
    edge_stiffness: np.ndarray
    flap_centrifugal_stiffness: np.ndarray
    edge_centrifugal_stiffness: np.ndarray
    flap_frequency: np.ndarray
    edge_frequency: np.ndarray
    flap_frequency_rotating: np.ndarray
    edge_frequency_rotating: np.ndarray
    rotor_speed: float


def mode_shape(coefficients: np.ndarray, fraction: np.ndarray, length: float, *,
               derivative: int = 0) -> np.ndarray:
    """Evaluate ElastoDyn's polynomial mode shape (function ``SHP``).

    Parameters
    ----------
    coefficients : array_like, shape (5,) or (m, 5)
        Coefficients of x^2 ... x^6 [-].
    fraction : array_like, shape (n,)
        x = position over the flexible length [-].
    length : float
        Flexible length [m].
    derivative : {0, 1, 2}, keyword-only
        Order of the derivative with respect to position (not fraction).

    Returns
    -------
    ndarray, shape (n,) or (m, n)
        phi [-], phi' [1/m] or phi'' [1/m^2].

    Examples
    --------
    >>> float(mode_shape([0.5, 0.5, 0, 0, 0], [1.0], 10.0)[0])
    1.0
    """
    if derivative not in (0, 1, 2):
        raise ParameterError(f"derivative must be 0, 1 or 2; got {derivative!r}.")
    c = np.asarray(coefficients, dtype=float)
    x = np.asarray(fraction, dtype=float)[:, None]
    factor = {0: np.ones(5), 1: _POWERS, 2: _POWERS * (_POWERS - 1)}[derivative]
    basis = factor * x ** (_POWERS - derivative) / length**derivative  # (n, 5)
    return c @ basis.T


def _elements(n: int, flexible_length: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    length = np.full(n, flexible_length / n)
    position = (np.arange(n) + 0.5) * flexible_length / n
    return position / flexible_length, position, length


def tower_nodes(turbine: TurbineParameters) -> TowerNodes:
    """Interpolate the tower properties onto ElastoDyn's TwrNodes analysis nodes.

    Parameters
    ----------
    turbine : TurbineParameters

    Returns
    -------
    TowerNodes

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> nodes = tower_nodes(nrel5mw())
    >>> round(float(nodes.height[0]), 3), round(float(nodes.mass_density[0]), 3)
    (2.19, 5501.26)
    """
    tower = turbine.tower
    fraction, height, length = _elements(turbine.n_tower_nodes, turbine.tower_flexible_length)
    def interp(values: np.ndarray) -> np.ndarray:
        return np.interp(fraction, tower.station_fraction, values)
    density = interp(tower.adjusted_mass_density)
    for at, mass in zip(np.atleast_1d(tower.point_mass_fraction), np.atleast_1d(tower.point_mass)):
        # ElastoDyn (SetTowerParameters): the element whose upper end reaches the mass's height takes it
        reach = np.nonzero(fraction + 0.5 * length / turbine.tower_flexible_length >= float(at))[0]
        i = int(reach[0]) if reach.size else len(fraction) - 1
        density[i] += float(mass) / length[i]
    return TowerNodes(fraction, height, length, density, interp(tower.adjusted_fa_stiffness),
                      interp(tower.adjusted_ss_stiffness))


def blade_nodes(turbine: TurbineParameters, blade: int = 0) -> BladeNodes:
    """Interpolate one blade's properties onto ElastoDyn's BldNodes analysis nodes.

    Parameters
    ----------
    turbine : TurbineParameters
    blade : int
        Blade index, 0-based.

    Returns
    -------
    BladeNodes

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> nodes = blade_nodes(nrel5mw())
    >>> round(float(nodes.radius[0]), 3), round(float(nodes.mass_density[0]), 3)
    (3.309, 787.554)
    """
    if not 0 <= blade < turbine.number_of_blades:
        raise ParameterError(f"blade index {blade} out of range; the turbine has "
                             f"{turbine.number_of_blades} blades (indices 0..).")
    b = turbine.blades[blade]
    fraction, span, length = _elements(turbine.n_blade_nodes, turbine.blade_flexible_length)
    def interp(values: np.ndarray) -> np.ndarray:
        return np.interp(fraction, b.station_fraction, values)
    return BladeNodes(fraction, span, span + turbine.hub_radius, length,
                      interp(b.structural_twist), interp(b.adjusted_mass_density),
                      interp(b.adjusted_flap_stiffness), interp(b.adjusted_edge_stiffness))


def rotor_mass_properties(turbine: TurbineParameters) -> RotorMassProperties:
    """Blade and rotor mass properties as ElastoDyn's summary prints them.

    Parameters
    ----------
    turbine : TurbineParameters

    Returns
    -------
    RotorMassProperties

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> round(rotor_mass_properties(nrel5mw()).rotor_mass, 3)
    109389.842
    """
    masses, firsts, seconds, cgs = [], [], [], []
    flexible = turbine.blade_flexible_length
    for k in range(turbine.number_of_blades):
        nodes = blade_nodes(turbine, k)
        element_mass = nodes.mass_density * nodes.length
        tip = turbine.tip_mass[k]
        masses.append(float(element_mass.sum() + tip))
        firsts.append(float(element_mass @ nodes.span + tip * flexible))
        seconds.append(float(element_mass @ nodes.span**2 + tip * flexible**2))
        cgs.append(firsts[-1] / masses[-1])
    hub_inertia = turbine.hub_inertia
    if turbine.number_of_blades == 2:  # ElastoDyn's Hubg1Iner for teetering hubs
        hub_inertia = ((turbine.hub_inertia - turbine.hub_mass
                        * (turbine.undersling - turbine.hub_cm) ** 2)
                       / math.cos(turbine.delta3) ** 2)
    r_hub = turbine.hub_radius
    inertia = hub_inertia + sum(
        (s + m * r_hub * (2.0 * cg + r_hub)) * math.cos(cone) ** 2
        for s, m, cg, cone in zip(seconds, masses, cgs, turbine.precone))
    return RotorMassProperties(tuple(masses), tuple(firsts), tuple(seconds), tuple(cgs),
                               turbine.hub_mass + sum(masses), inertia)


def tower_mass(turbine: TurbineParameters) -> float:
    """Mass of the flexible tower, sum of element masses [kg] (ElastoDyn TwrMass).

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> round(tower_mass(nrel5mw()), 3)
    347460.232
    """
    nodes = tower_nodes(turbine)
    return float(nodes.mass_density @ nodes.length)


def tower_top_mass(turbine: TurbineParameters) -> float:
    """Rotor + nacelle + yaw-bearing mass [kg] (ElastoDyn TwrTpMass).

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> round(tower_top_mass(nrel5mw()), 3)
    349389.842
    """
    return (rotor_mass_properties(turbine).rotor_mass + turbine.nacelle_mass
            + turbine.yaw_bearing_mass)


def _frequency(stiffness: np.ndarray, mass: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.sqrt(stiffness / mass) / (2.0 * math.pi)


def tower_modal_properties(turbine: TurbineParameters, *,
                           gravity: float | None = None) -> TowerModalProperties:
    """Generalized masses, stiffnesses and frequencies of the tower modes.

    Parameters
    ----------
    turbine : TurbineParameters
    gravity : float, optional, keyword-only
        [m/s^2]; defaults to ``turbine.simulation.gravity``.

    Returns
    -------
    TowerModalProperties

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> modal = tower_modal_properties(nrel5mw())
    >>> round(float(modal.fa_stiffness[0, 0]) / 1e6, 2)
    1.91
    """
    g = turbine.simulation.gravity if gravity is None else gravity
    tower, nodes = turbine.tower, tower_nodes(turbine)
    length = turbine.tower_flexible_length
    element_mass = nodes.mass_density * nodes.length
    top = tower_top_mass(turbine)
    # Mass above each node: half of its own element, everything above, and the top mass.
    above = np.cumsum(element_mass[::-1])[::-1] - 0.5 * element_mass + top
    results = {}
    for side, shapes, tuner, stiff in (
            ("fa", tower.fa_mode_shapes, tower.fa_stiffness_tuner, nodes.fa_stiffness),
            ("ss", tower.ss_mode_shapes, tower.ss_stiffness_tuner, nodes.ss_stiffness)):
        phi = mode_shape(shapes, nodes.fraction, length)
        slope = mode_shape(shapes, nodes.fraction, length, derivative=1)
        curvature = mode_shape(shapes, nodes.fraction, length, derivative=2)
        mass = (phi**2) @ element_mass
        k = (curvature * stiff * nodes.length) @ curvature.T * np.sqrt(np.outer(tuner, tuner))
        k_grav = -(slope**2) @ (above * nodes.length) * g
        results[side] = (mass, k, k_grav, _frequency(np.diag(k), mass),
                         _frequency(np.diag(k) + k_grav, mass + top))
    fa, ss = results["fa"], results["ss"]
    return TowerModalProperties(fa[0], ss[0], top, fa[1], ss[1], fa[2], ss[2], fa[3], ss[3],
                                fa[4], ss[4])


def blade_modal_properties(turbine: TurbineParameters, blade: int = 0, *,
                           rotor_speed: float | None = None) -> BladeModalProperties:
    """Generalized masses, stiffnesses and frequencies of one blade's modes.

    Parameters
    ----------
    turbine : TurbineParameters
    blade : int
        Blade index, 0-based.
    rotor_speed : float, optional, keyword-only
        [rad/s] for the centrifugal stiffening; defaults to the initial rotor speed
        (as in ElastoDyn).

    Returns
    -------
    BladeModalProperties

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> modal = blade_modal_properties(nrel5mw(), rotor_speed=0.0)
    >>> [round(float(f), 3) for f in modal.flap_frequency]
    [0.676, 1.958]
    """
    omega = turbine.initial_conditions.rotor_speed if rotor_speed is None else rotor_speed
    b, nodes = turbine.blades[blade], blade_nodes(turbine, blade)
    length, tip = turbine.blade_flexible_length, turbine.tip_mass[blade]
    element_mass = nodes.mass_density * nodes.length
    # First moment about the rotor axis of everything outboard of each node (FMomAbvNd).
    # ElastoDyn puts each half element at the element end (outer half at the outer end).
    outer_half = 0.5 * element_mass * (nodes.radius + 0.5 * nodes.length)
    inner_half = 0.5 * element_mass * (nodes.radius - 0.5 * nodes.length)
    both = np.cumsum((outer_half + inner_half)[::-1])[::-1]
    moment_above = outer_half + np.append(both[1:], 0.0) + tip * turbine.tip_radius
    results = []
    for shapes, stiff, tuner in ((b.flap_mode_shapes, nodes.flap_stiffness, b.flap_stiffness_tuner),
                                 (b.edge_mode_shapes, nodes.edge_stiffness, np.ones(1))):
        phi = mode_shape(shapes, nodes.fraction, length)
        slope = mode_shape(shapes, nodes.fraction, length, derivative=1)
        curvature = mode_shape(shapes, nodes.fraction, length, derivative=2)
        mass = (phi**2) @ element_mass + tip
        k = (curvature * stiff * nodes.length) @ curvature.T * np.sqrt(np.outer(tuner, tuner))
        k_cent = (slope**2) @ (moment_above * nodes.length)
        results.append((mass, k, k_cent, _frequency(np.diag(k), mass - tip),
                        _frequency(np.diag(k) + k_cent * omega**2, mass)))
    flap, edge = results
    return BladeModalProperties(flap[0], edge[0], flap[1], np.diag(edge[1]), flap[2], edge[2],
                                flap[3], edge[3], flap[4], edge[4], float(omega))
