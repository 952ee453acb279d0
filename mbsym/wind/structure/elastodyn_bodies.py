"""ElastoDyn-equivalent flexible blade and tower bodies (shape integrals).

ElastoDyn does not integrate continuous mode shapes: each blade and the tower are
point masses at element mid-points (``BldNodes`` / ``TwrNodes`` equal elements),
with nodal displacements, an axial shortening quadratic in the DOFs, and the
generalized stiffness and damping of ElastoDyn's ``Coeff`` routine (see
``docs/elastodyn_notes.md`` §1, §3). This module rebuilds exactly those
quantities from :class:`~mbsym.wind.TurbineParameters` and packs them into
:class:`~mbsym.beam.ShapeIntegrals` with :func:`mbsym.beam.lumped.lumped_shape_integrals`,
so that a :class:`~mbsym.FlexibleBody` moves like ElastoDyn's blade or tower.

Blade body frame (ElastoDyn's pitched blade frame ``j``)
--------------------------------------------------------
Origin at the blade root (``HubRad`` from the apex), ``z = j3`` along the blade,
``x = j1`` (out of plane, downwind at zero pitch and cone), ``y = j2`` (in plane,
**against** the direction of rotation for ElastoDyn's positive rotor speed);
``(j1, j2, j3)`` is right-handed. ElastoDyn rotates the local principal axes by
the structural twist ``theta`` so that the flap curvature points along
``L1 = cos(theta) j1 - sin(theta) j2`` and the edge curvature along
``L2 = sin(theta) j1 + cos(theta) j2``: in body axes the principal axes are
``R_z(-theta)`` applied to ``(x, y)``. We keep ElastoDyn's sign exactly, so a
unit ``FlapDOF1`` coordinate puts the NREL 5 MW tip at ``(0.99103, -0.12657)``
in ``(x, y)``. These curvatures are integrated twice from the root with
ElastoDyn's midpoint/trapezoid recurrences (``TwistedSF``), and the axial
shortening uses the twisted slopes (``AxRedBld``). The stiffness is ElastoDyn's
untwisted ``KBF`` (with ``FlStTunr``) and ``KBE``, with no flap-edge coupling,
and the damping is ElastoDyn's column-wise ``CBF`` / ``CBE``. The coordinates
are ElastoDyn's ``q_B1F1``, ``q_B1F2``, ``q_B1E1`` (tip deflection [m]).

Tower body frame
----------------
Origin at the tower base (``TowerBsHt``), ``z`` up along the tower, ``x``
fore-aft (downwind), ``y`` side-side (IEC). The shapes are ElastoDyn's analytic
polynomials at the nodes (no twist), the shortening ``AxRedTFA`` / ``AxRedTSS``,
the stiffness ``KTFA`` / ``KTSS`` (with ``FAStTunr`` / ``SSStTunr``) and the
damping ``CTFA`` / ``CTSS``. **Side-side sign:** ElastoDyn's internal SS DOF
moves the top toward ``-y``; our SS coordinate moves it toward ``+y``. Hence
``Q_TSS1 (ElastoDyn output) = -q_SS1 (ours)`` and ``q_SS1 = TTDspSS``; the
stiffness and damping blocks are unchanged by the flip (the FA and SS blocks do
not couple).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ...beam.lumped import lumped_shape_integrals
from ...beam.sid import ShapeIntegrals, damping_matrix
from ...bodies.rigid import RigidBody
from ...exceptions import ParameterError
from .elastodyn_nodes import blade_nodes, mode_shape, tower_nodes, tower_top_mass
from ..deck.parameters import TurbineParameters

__all__ = [
    "BLADE_DOFS", "TOWER_DOFS", "ElastoDynBladeData", "ElastoDynTowerData",
    "blade_elastodyn_data", "tower_elastodyn_data", "blade_shape_integrals",
    "tower_shape_integrals", "blade_rotation", "rigid_blade"]

#: ElastoDyn's blade DOF flags, in the order of :class:`ElastoDynBladeData` arrays.
BLADE_DOFS: tuple[str, ...] = ("FlapDOF1", "FlapDOF2", "EdgeDOF")
#: ElastoDyn's tower DOF flags, in the order of :class:`ElastoDynTowerData` arrays.
TOWER_DOFS: tuple[str, ...] = ("TwFADOF1", "TwFADOF2", "TwSSDOF1", "TwSSDOF2")


@dataclass(frozen=True, eq=False)
class ElastoDynBladeData:
    """One blade as ElastoDyn discretises it; shape order ``BLADE_DOFS`` (F1, F2, E1).

    Attributes
    ----------
    span : ndarray (N,)
        Node distance from the blade root [m] (``RNodes``).
    element_length, element_mass : ndarray (N,)
        ``DRNodes`` [m] and ``BElmntMass`` [kg].
    twist : ndarray (N,)
        Structural twist at the nodes used for the shapes [rad] (0 if untwisted).
    length, tip_mass : float
        ``BldFlexL`` [m], ``TipMass`` [kg].
    displacement, slope : ndarray (3, N, 2)
        Twisted shapes at the nodes, components (x = j1, y = j2) per unit DOF
        [m/m], [1/m] (``TwistedSF(.., 0)`` and ``(.., 1)``).
    tip_displacement, tip_slope : ndarray (3, 2)
        The same at the tip.
    axial_reduction : ndarray (3, 3, N)
        ``AxRedBld(i, j, J)`` [1/m]; ``tip_axial_reduction`` (3, 3) at the tip.
    flap_stiffness : ndarray (2, 2)
        ``KBF`` with the tuners [N/m]; ``edge_stiffness`` (1, 1) ``KBE`` [N/m].
    flap_damping : ndarray (2, 2)
        ``CBF`` [N s/m] (column-wise rule); ``edge_damping`` (1, 1) ``CBE``.
    flap_mass, edge_mass : ndarray (2,), (1,)
        Untwisted generalized masses ``MBF``, ``MBE`` including the tip mass [kg]
        (ElastoDyn uses them only for frequencies and damping).
    flap_frequency, edge_frequency : ndarray (2,), (1,)
        ``FreqBF(:, 1)``, ``FreqBE(:, 1)``: without tip mass, non-rotating [Hz].
    """

    span: np.ndarray
    element_length: np.ndarray
    element_mass: np.ndarray
    twist: np.ndarray
    length: float
    tip_mass: float
    displacement: np.ndarray
    slope: np.ndarray
    tip_displacement: np.ndarray
    tip_slope: np.ndarray
    axial_reduction: np.ndarray
    tip_axial_reduction: np.ndarray
    flap_stiffness: np.ndarray
    edge_stiffness: np.ndarray
    flap_damping: np.ndarray
    edge_damping: np.ndarray
    flap_mass: np.ndarray
    edge_mass: np.ndarray
    flap_frequency: np.ndarray
    edge_frequency: np.ndarray

    @property
    def stiffness(self) -> np.ndarray:
        """``blkdiag(KBF, KBE)`` in F1, F2, E1 order [N/m]."""
        return _blkdiag(self.flap_stiffness, self.edge_stiffness)

    @property
    def damping(self) -> np.ndarray:
        """``blkdiag(CBF, CBE)`` in F1, F2, E1 order [N s/m]."""
        return _blkdiag(self.flap_damping, self.edge_damping)

    @property
    def mass_matrix(self) -> np.ndarray:
        """Twisted Kane mass matrix of the blade DOFs at ``q = 0`` (F1, F2, E1) [kg]."""
        u, ut = self.displacement, self.tip_displacement
        return np.einsum("J,iJa,jJa->ij", self.element_mass, u, u) + self.tip_mass * ut @ ut.T


@dataclass(frozen=True, eq=False)
class ElastoDynTowerData:
    """The tower as ElastoDyn discretises it; shape order ``TOWER_DOFS`` (FA1, FA2, SS1, SS2).

    Attributes
    ----------
    height, element_length, element_mass : ndarray (N,)
        ``HNodes`` above the tower base [m], ``DHNodes`` [m], ``TElmntMass`` [kg].
    length, top_mass : float
        ``TwrFlexL`` [m]; ``TwrTpMass`` (rotor + nacelle + yaw bearing) [kg].
    displacement, slope : ndarray (4, N, 2)
        Analytic shapes at the nodes in body (x, y) [m/m], [1/m]; the SS shapes
        point along **+y** (ElastoDyn's internal SS DOF along -y, see module docs).
    tip_displacement, tip_slope : ndarray (4, 2)
        At the top: the unit DOF direction (ElastoDyn displaces the top by the DOF
        value itself, even where the coefficients do not sum to 1) and ``SHP'(1)``.
    axial_reduction : ndarray (4, 4, N)
        ``AxRedTFA`` / ``AxRedTSS`` [1/m] (FA-SS entries 0); ``tip_axial_reduction``
        (4, 4) at the top.
    fa_stiffness, ss_stiffness : ndarray (2, 2)
        ``KTFA``, ``KTSS`` with the tuners [N/m].
    fa_damping, ss_damping : ndarray (2, 2)
        ``CTFA``, ``CTSS`` [N s/m] (column-wise rule).
    fa_mass, ss_mass : ndarray (2,)
        Tower-only generalized masses ``sum m phi^2`` [kg] (ElastoDyn's ``MTFA`` minus
        ``TwrTpMass``).
    fa_frequency, ss_frequency : ndarray (2,)
        ``FreqTFA(:, 1)``, ``FreqTSS(:, 1)``: tower alone, no gravity [Hz].
    """

    height: np.ndarray
    element_length: np.ndarray
    element_mass: np.ndarray
    length: float
    top_mass: float
    displacement: np.ndarray
    slope: np.ndarray
    tip_displacement: np.ndarray
    tip_slope: np.ndarray
    axial_reduction: np.ndarray
    tip_axial_reduction: np.ndarray
    fa_stiffness: np.ndarray
    ss_stiffness: np.ndarray
    fa_damping: np.ndarray
    ss_damping: np.ndarray
    fa_mass: np.ndarray
    ss_mass: np.ndarray
    fa_frequency: np.ndarray
    ss_frequency: np.ndarray

    @property
    def stiffness(self) -> np.ndarray:
        """``blkdiag(KTFA, KTSS)`` in FA1, FA2, SS1, SS2 order [N/m]."""
        return _blkdiag(self.fa_stiffness, self.ss_stiffness)

    @property
    def damping(self) -> np.ndarray:
        """``blkdiag(CTFA, CTSS)`` in FA1, FA2, SS1, SS2 order [N s/m]."""
        return _blkdiag(self.fa_damping, self.ss_damping)


def _blkdiag(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.zeros((a.shape[0] + b.shape[0],) * 2)
    out[:a.shape[0], :a.shape[0]] = a
    out[a.shape[0]:, a.shape[0]:] = b
    return out


def _node_recurrence(values: np.ndarray, lengths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ElastoDyn's integration from the root on mid-point nodes (last axis = nodes).

    ``y(1) = d1 f1 / 2``, ``y(J) = y(J-1) + d_{J-1} f_{J-1} / 2 + d_J f_J / 2`` and
    ``y_tip = y(N) + d_N f_N / 2`` (used for slopes, displacements and AxRed).
    """
    half = 0.5 * lengths * values
    total = np.cumsum(2.0 * half, axis=-1)
    return total - half, total[..., -1]


def _untwisted_stiffness(curvature: np.ndarray, ei: np.ndarray, lengths: np.ndarray,
                         tuner: np.ndarray) -> np.ndarray:
    """``sqrt(t_I t_L) sum_J EI_J d_J phi_I'' phi_L''`` (ElastoDyn's KBF, KBE, KTFA, KTSS)."""
    k = (curvature * ei * lengths) @ curvature.T
    return k * np.sqrt(np.outer(tuner, tuner))


def _column_damping(k: np.ndarray, mass_no_tip: np.ndarray, ratios: np.ndarray) -> np.ndarray:
    """``C[:, L] = zeta_L K[:, L] / (pi f_L)`` with ``f_L = sqrt(K_LL / M_LL) / 2 pi``."""
    return damping_matrix(k, np.diag(mass_no_tip), ratios, method="stiffness-proportional")


def blade_elastodyn_data(turbine: TurbineParameters, blade: int = 0, *,
                         twist: bool = True) -> ElastoDynBladeData:
    """ElastoDyn's twisted blade shapes and generalized matrices (``SetBladeParameters``, ``Coeff``).

    Parameters
    ----------
    turbine : TurbineParameters
    blade : int
        Blade index, 0-based.
    twist : bool, keyword-only
        Project the curvatures on the twisted principal axes, as ElastoDyn does
        (default). ``False`` sets the twist to zero (for studies only).

    Returns
    -------
    ElastoDynBladeData

    Raises
    ------
    ParameterError
        Blade index out of range.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> data = blade_elastodyn_data(nrel5mw())
    >>> [round(float(v), 5) for v in data.tip_displacement[0]]
    [0.99103, -0.12657]
    """
    nodes = blade_nodes(turbine, blade)
    b, length = turbine.blades[blade], turbine.blade_flexible_length
    dr, x = nodes.length, nodes.fraction
    theta = nodes.structural_twist if twist else np.zeros_like(x)
    c, s = np.cos(theta), np.sin(theta)
    flap_curv = mode_shape(b.flap_mode_shapes, x, length, derivative=2)      # (2, N)
    edge_curv = mode_shape(b.edge_mode_shapes, x, length, derivative=2)      # (1, N)
    kappa = np.concatenate([np.stack([flap_curv * c, -flap_curv * s], axis=-1),
                            np.stack([edge_curv * s, edge_curv * c], axis=-1)])  # (3, N, 2)
    slope, tip_slope = _node_recurrence(np.moveaxis(kappa, -1, 1), dr)          # (3, 2, N), (3, 2)
    disp, tip_disp = _node_recurrence(slope, dr)
    ax, ax_tip = _node_recurrence(np.einsum("iaJ,jaJ->ijJ", slope, slope), dr)
    element_mass = nodes.mass_density * dr
    tip = float(turbine.tip_mass[blade])
    flap_phi = mode_shape(b.flap_mode_shapes, x, length)
    edge_phi = mode_shape(b.edge_mode_shapes, x, length)
    kbf = _untwisted_stiffness(flap_curv, nodes.flap_stiffness, dr, b.flap_stiffness_tuner)
    kbe = _untwisted_stiffness(edge_curv, nodes.edge_stiffness, dr, np.ones(1))
    mbf, mbe = flap_phi**2 @ element_mass, edge_phi**2 @ element_mass            # without tip mass
    return ElastoDynBladeData(
        span=nodes.span, element_length=dr, element_mass=element_mass, twist=theta,
        length=length, tip_mass=tip, displacement=np.moveaxis(disp, 1, -1),
        slope=np.moveaxis(slope, 1, -1), tip_displacement=tip_disp, tip_slope=tip_slope,
        axial_reduction=ax, tip_axial_reduction=ax_tip, flap_stiffness=kbf, edge_stiffness=kbe,
        flap_damping=_column_damping(kbf, mbf, b.flap_damping_ratio),
        edge_damping=_column_damping(kbe, mbe, b.edge_damping_ratio),
        flap_mass=mbf + tip, edge_mass=mbe + tip,
        flap_frequency=np.sqrt(np.diag(kbf) / mbf) / (2 * math.pi),
        edge_frequency=np.sqrt(np.diag(kbe) / mbe) / (2 * math.pi),
    )


def tower_elastodyn_data(turbine: TurbineParameters) -> ElastoDynTowerData:
    """ElastoDyn's tower shapes and generalized matrices (``SetTowerParameters``, ``Coeff``).

    Parameters
    ----------
    turbine : TurbineParameters

    Returns
    -------
    ElastoDynTowerData

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> data = tower_elastodyn_data(nrel5mw())
    >>> round(float(data.fa_stiffness[0, 0]) / 1e6, 4)
    1.9109
    """
    tower, nodes = turbine.tower, tower_nodes(turbine)
    length, dh, x = turbine.tower_flexible_length, nodes.length, nodes.fraction
    element_mass = nodes.mass_density * dh
    shapes = np.vstack([tower.fa_mode_shapes, tower.ss_mode_shapes])           # (4, 5)
    direction = np.array([[1.0, 0.0]] * 2 + [[0.0, 1.0]] * 2)                  # FA -> x, SS -> +y

    def at(where: np.ndarray, d: int) -> np.ndarray:
        return mode_shape(shapes, where, length, derivative=d)[:, :, None] * direction[:, None, :]

    disp, slope = at(x, 0), at(x, 1)                                            # (4, N, 2)
    # ElastoDyn moves the top by the DOF value itself (rZO), whatever SHP(1) is (0.9999 for the
    # 5 MW SS modes); the top slope is the analytic SHP'(1).
    tip_disp, tip_slope = direction.copy(), at(np.ones(1), 1)[:, 0]
    ax, ax_tip = _node_recurrence(np.einsum("iJa,jJa->ijJ", slope, slope), dh)
    curv = mode_shape(shapes, x, length, derivative=2)
    kfa = _untwisted_stiffness(curv[:2], nodes.fa_stiffness, dh, tower.fa_stiffness_tuner)
    kss = _untwisted_stiffness(curv[2:], nodes.ss_stiffness, dh, tower.ss_stiffness_tuner)
    gen_mass = mode_shape(shapes, x, length) ** 2 @ element_mass              # tower only
    return ElastoDynTowerData(
        height=nodes.height, element_length=dh, element_mass=element_mass, length=length,
        top_mass=tower_top_mass(turbine), displacement=disp, slope=slope,
        tip_displacement=tip_disp, tip_slope=tip_slope, axial_reduction=ax,
        tip_axial_reduction=ax_tip, fa_stiffness=kfa, ss_stiffness=kss,
        fa_damping=_column_damping(kfa, gen_mass[:2], tower.fa_damping_ratio),
        ss_damping=_column_damping(kss, gen_mass[2:], tower.ss_damping_ratio),
        fa_mass=gen_mass[:2], ss_mass=gen_mass[2:],
        fa_frequency=np.sqrt(np.diag(kfa) / gen_mass[:2]) / (2 * math.pi),
        ss_frequency=np.sqrt(np.diag(kss) / gen_mass[2:]) / (2 * math.pi),
    )


def _dof_indices(dofs: Sequence[str], allowed: tuple[str, ...], what: str) -> list[int]:
    names = [dofs] if isinstance(dofs, str) else list(dofs)
    unknown = [d for d in names if d not in allowed]
    if not names or unknown or len(set(names)) != len(names):
        raise ParameterError(f"{what} DOFs must be a non-empty selection without repeats from "
                             f"{list(allowed)}; got {names}" + (f" (unknown: {unknown})." if unknown else "."))
    return [allowed.index(d) for d in names]


def _select_data(u: np.ndarray, ut: np.ndarray, s_tip: np.ndarray, ax: np.ndarray, ax_tip: np.ndarray,
                 k: np.ndarray, c: np.ndarray, idx: list[int]) -> tuple[np.ndarray, ...]:
    """Keep the shapes ``idx`` (in that order) of the per-shape arrays and matrices."""
    sq = np.ix_(idx, idx)
    return u[idx], ut[idx], s_tip[idx], ax[sq], ax_tip[sq], k[sq], c[sq]


def blade_shape_integrals(turbine: TurbineParameters, blade: int = 0, *,
                          dofs: Sequence[str] = BLADE_DOFS, twist: bool = True) -> ShapeIntegrals:
    """ElastoDyn-equivalent shape integrals of one blade (lumped nodes, twisted shapes).

    Parameters
    ----------
    turbine : TurbineParameters
    blade : int
        Blade index, 0-based.
    dofs : sequence of str, keyword-only
        Blade DOFs to keep, in the order of the body's coordinates, from
        ``("FlapDOF1", "FlapDOF2", "EdgeDOF")`` (default: all three). Stiffness and
        damping are the corresponding blocks of ElastoDyn's matrices (the column-wise
        damping uses each mode's own frequency, whatever DOFs are kept).
    twist : bool, keyword-only
        ElastoDyn's twisted shapes (default); ``False`` for an untwisted study blade.

    Returns
    -------
    ShapeIntegrals
        Body frame: root at the origin, ``x = j1`` (flap at zero twist), ``y = j2``,
        ``z = j3`` along the blade (module docstring). Attach the body at ``HubRad``
        along the coned blade axis; the engine adds the hub-radius part of the
        centrifugal stiffening through ``kg_t`` with the root's acceleration.

    Raises
    ------
    ParameterError
        Unknown or repeated DOF names, or a blade index out of range.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> sid = blade_shape_integrals(nrel5mw(), dofs=("FlapDOF1", "EdgeDOF"))
    >>> sid.n_e, round(float(sid.me[0, 0]), 3)
    (2, 933.904)
    """
    idx = _dof_indices(dofs, BLADE_DOFS, "blade")
    d = blade_elastodyn_data(turbine, blade, twist=twist)
    u, ut, st, ax, axt, k, c = _select_data(d.displacement, d.tip_displacement, d.tip_slope,
                                            d.axial_reduction, d.tip_axial_reduction,
                                            d.stiffness, d.damping, idx)
    return lumped_shape_integrals(d.span, d.element_mass, u, ax, length=d.length, tip_displacement=ut,
                                  tip_slope=st, tip_axial_reduction=axt, stiffness=k, damping=c,
                                  tip_mass=d.tip_mass)


def tower_shape_integrals(turbine: TurbineParameters, *, dofs: Sequence[str] = TOWER_DOFS,
                          top_mass_included: bool = False) -> ShapeIntegrals:
    """ElastoDyn-equivalent shape integrals of the tower (lumped nodes, analytic shapes).

    Parameters
    ----------
    turbine : TurbineParameters
    dofs : sequence of str, keyword-only
        Tower DOFs to keep, in the order of the body's coordinates, from
        ``("TwFADOF1", "TwFADOF2", "TwSSDOF1", "TwSSDOF2")`` (default: all four).
        Our SS coordinates are positive toward +y: ``q_SS = -Q_TSS`` of ElastoDyn.
    top_mass_included : bool, keyword-only
        ``False`` (default): the body is the tower alone; model the rotor-nacelle
        assembly with bodies attached at the top and pass its mass as
        ``FlexibleBody(..., top_mass=...)`` so that its weight loads the tower.
        ``True``: ``TwrTpMass`` is lumped as a point mass at the top (in every
        inertial sum and in ``kg_t`` / ``kg_omega``), a simplified RNA without
        offset or rotary inertia.

    Returns
    -------
    ShapeIntegrals
        Body frame: base at the origin (``TowerBsHt``), ``z`` up, ``x`` fore-aft,
        ``y`` side-side.

    Raises
    ------
    ParameterError
        Unknown or repeated DOF names.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> sid = tower_shape_integrals(nrel5mw(), dofs=("TwFADOF1",))
    >>> round(float(sid.me[0, 0]), 2), round(float(sid.end_rotation[1, 0]), 7)
    (53932.25, 0.0185205)
    """
    idx = _dof_indices(dofs, TOWER_DOFS, "tower")
    d = tower_elastodyn_data(turbine)
    u, ut, st, ax, axt, k, c = _select_data(d.displacement, d.tip_displacement, d.tip_slope,
                                            d.axial_reduction, d.tip_axial_reduction,
                                            d.stiffness, d.damping, idx)
    return lumped_shape_integrals(d.height, d.element_mass, u, ax, length=d.length, tip_displacement=ut,
                                  tip_slope=st, tip_axial_reduction=axt, stiffness=k, damping=c,
                                  tip_mass=d.top_mass if top_mass_included else 0.0)


def blade_rotation(gamma: float, cone: float, pitch: float) -> np.ndarray:
    """Blade frame (ElastoDyn's j1, j2, j3 as columns) in hub axes (IEC x, y, z).

    Hub axes relate to ElastoDyn's g frame by g1 = x, g2 = z, g3 = -y; the blade is
    rotated by ``gamma`` [rad] about x, coned by ``cone`` and pitched by ``pitch``
    (notes §4). ``j3`` is the blade axis (radial).
    """
    g1, g2, g3 = np.array([1.0, 0, 0]), np.array([0, 0, 1.0]), np.array([0, -1.0, 0])
    g2p = np.cos(gamma) * g2 + np.sin(gamma) * g3
    g3p = -np.sin(gamma) * g2 + np.cos(gamma) * g3
    i1 = np.cos(cone) * g1 - np.sin(cone) * g3p
    i2 = g2p
    i3 = np.sin(cone) * g1 + np.cos(cone) * g3p
    j1 = np.cos(pitch) * i1 - np.sin(pitch) * i2
    j2 = np.sin(pitch) * i1 + np.cos(pitch) * i2
    return np.column_stack([j1, j2, i3])


def rigid_blade(data: "ElastoDynBladeData", name: str) -> RigidBody:
    """One rigid blade of ElastoDyn's node masses (no rotary inertia of the elements)."""
    m = np.append(np.asarray(data.element_mass), data.tip_mass)
    z = np.append(np.asarray(data.span), data.length)
    mass = float(m.sum())
    zc = float(m @ z / mass)
    i_xx = float(m @ (z - zc) ** 2)
    return RigidBody(name, mass=mass, com=[0.0, 0.0, zc], inertia=[i_xx, i_xx, 0.0])
