"""Drag and inertia of quasi-static mooring lines (MoorDyn's line loads on the catenary's shape).

A quasi-static line (:class:`~.catenary.CatenaryLine`) has no drag and no mass of its own: its shape
follows the fairlead at once. MoorDyn's lumped-mass lines move through the water, and their drag
and inertia damp the platform and lengthen its periods (measured on ``fl_decay_a``: without them a
decay is 5–13 % off MoorDyn's, docs/offshore.md §6). This module keeps the quasi-static shape and
gives it MoorDyn's line loads:

* the line is cut into ``n`` segments of equal unstretched length along its arc; the nodes sit on
  the catenary's shape (:meth:`~.catenary.CatenaryLine.profile`), a differentiable function of the
  fairlead position ``r`` (through the solved fairlead forces H, V);
* a node moves with ``ṗ_i = G_i ṙ``, ``G_i = ∂p_i/∂r`` the shape's sensitivity to the fairlead
  (H, V follow by the implicit-function theorem of the span equations);
* Morison drag on each node in still water, with MoorDyn v2's conventions (its ``MoorDyn_Line.f90``):
  ``f_i = −½ ρ d Δs_i [C_dn |v_n| v_n + π C_dt |v_t| v_t]`` with ``v_t``, ``v_n`` the node velocity
  along and across the local tangent and ``Δs_i`` the node's unstretched length (half a segment at
  the ends);
* the node's mass and added mass, ``M_i = m Δs_i I + ρ (π d²/4) Δs_i [C_an (I − t tᵀ) + C_at t tᵀ]``;
* both back to the fairlead by virtual work: the drag as a fairlead force ``Σ G_iᵀ f_i``, the inertia
  as a fairlead mass ``M_r = Σ G_iᵀ M_i G_i`` (3 × 3), which the platform sees as ``J_rᵀ M_r J_r`` on
  its six DOFs (``J_r = ∂r/∂q``).

Approximations (stated in docs/offshore.md §6): the shape is the static catenary at every instant,
so there are no line waves and no transverse line dynamics of their own; the node acceleration is
``G_i r̈`` (the convective part ``Ġ_i ṙ`` and the configuration dependence of ``M_r`` in the
platform's equations are left out: second order in the velocities); no seabed stiffness, damping or
friction forces on moving nodes, no internal (axial) damping (the catenary is much softer in bending
than in stretch: the line stretches by ~1e-5 per second in a decay); the lines are fully submerged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ParameterError
from .catenary import CatenaryLine

__all__ = ["LineHydrodynamics", "line_nodes", "node_drag", "node_mass", "fairlead_terms"]

_SMOOTH = 1e-6          # m/s: |v| as sqrt(v·v + 1e-12), smooth at rest (linear models), negligible otherwise


@dataclass(frozen=True)
class LineHydrodynamics:
    """Mass and Morison coefficients of one line (MoorDyn's line-type columns).

    Parameters
    ----------
    diameter : float
        Volume-equivalent diameter d [m] (``Diam``).
    mass_per_length : float
        Mass in air per unstretched length [kg/m] (``MassDen``).
    drag_normal, drag_axial : float
        C_dn and C_dt [-] (``Cd``, ``CdAx``) on the areas d and π d per unit length.
    added_mass_normal, added_mass_axial : float
        C_an and C_at [-] (``Ca``, ``CaAx``) on the displaced volume π d²/4 per unit length.
    segments : int
        Number of segments the line is cut into (MoorDyn's ``NumSegs``).
    """

    diameter: float
    mass_per_length: float
    drag_normal: float
    drag_axial: float
    added_mass_normal: float
    added_mass_axial: float
    segments: int = 20

    def __post_init__(self) -> None:
        for name in ("diameter", "mass_per_length", "drag_normal", "drag_axial", "added_mass_normal",
                     "added_mass_axial"):
            value = float(getattr(self, name))
            if not (math.isfinite(value) and value >= 0):
                raise ParameterError(f"LineHydrodynamics.{name} must be a finite number >= 0; got {value}.")
        if self.diameter <= 0:
            raise ParameterError(f"LineHydrodynamics.diameter must be > 0; got {self.diameter}.")
        if not (isinstance(self.segments, (int, np.integer)) and self.segments >= 1):
            raise ParameterError(f"LineHydrodynamics.segments must be an integer >= 1; got {self.segments!r}.")

    @classmethod
    def from_moordyn(cls, line_type, segments: int) -> "LineHydrodynamics":
        """From a MoorDyn line type (:class:`~mbsym.wind.deck.moordyn.MooringLineType`) and ``NumSegs``."""
        return cls(line_type.diameter, line_type.mass_per_length, line_type.drag_transverse, line_type.drag_axial,
                   line_type.added_mass_transverse, line_type.added_mass_axial, int(segments))

    @property
    def weights(self) -> np.ndarray:
        """The nodes' share of the line as fractions of its length (trapezoid: half at the ends) [-]."""
        w = np.full(self.segments + 1, 1.0 / self.segments)
        w[[0, -1]] /= 2
        return w


def line_nodes(line: CatenaryLine, segments: int, H, V, anchor, fairlead):
    """Node positions and unit tangents (each 3 × (segments + 1)) of a line from anchor to fairlead [m, -].

    ``H``, ``V``: the fairlead forces [N] (CasADi or numbers); ``anchor`` (numbers) and ``fairlead``
    (a 3-vector) in inertial axes; nodes at equal unstretched arc lengths.
    """
    s = ca.DM(np.linspace(0.0, line.length, segments + 1)).T
    x, z = (ca.DM(v).T if isinstance(v, np.ndarray) else v for v in line.profile(H, V, s))   # rows
    fairlead = fairlead if isinstance(fairlead, (ca.SX, ca.MX)) else ca.DM(np.asarray(fairlead, dtype=float))
    anchor = ca.DM(np.asarray(anchor, dtype=float))
    d = fairlead[0:2] - anchor[0:2]
    e = ca.vertcat(d / ca.sqrt(ca.sumsqr(d)), 0)                 # horizontal direction anchor → fairlead
    ez = ca.DM([0.0, 0.0, 1.0])
    points = ca.repmat(anchor, 1, segments + 1) + ca.mtimes(e, x) + ca.mtimes(ez, z)
    # the tangent is along the line force (H e + V(s) e_z)/T, V(s) the vertical force at s (0 on the seabed)
    w, L = line.weight, line.length
    vs = ca.fmax(V - w * L, 0) + w * ca.fmax(s - ca.fmax(L - V / w, 0), 0)
    tension = ca.sqrt(H ** 2 + vs ** 2)
    tangents = ca.mtimes(e, H / tension) + ca.mtimes(ez, vs / tension)
    return points, tangents


def node_drag(props: LineHydrodynamics, length: float, water_density: float, tangents, velocities):
    """Still-water Morison drag on the nodes (3 × n) [N] for their velocities (3 × n) [m/s] (module docstring)."""
    rho, d = water_density, props.diameter
    forces = []
    for i, share in enumerate(props.weights * length):
        t, v = tangents[:, i], velocities[:, i]
        vt = ca.dot(v, t) * t
        vn = v - vt
        mag_n = ca.sqrt(ca.sumsqr(vn) + _SMOOTH ** 2)
        mag_t = ca.sqrt(ca.sumsqr(vt) + _SMOOTH ** 2)
        forces.append(-0.5 * rho * d * share * (props.drag_normal * mag_n * vn
                                                + math.pi * props.drag_axial * mag_t * vt))
    return ca.horzcat(*forces)


def node_mass(props: LineHydrodynamics, length: float, water_density: float, tangent, share: float):
    """Mass and added mass (3 × 3) [kg] of a node with unit tangent ``tangent`` and ``share`` of the line."""
    ds = share * length
    volume = math.pi * props.diameter ** 2 / 4 * ds
    tt = ca.mtimes(tangent, tangent.T)
    return (props.mass_per_length * ds * ca.DM.eye(3)
            + water_density * volume * (props.added_mass_normal * (ca.DM.eye(3) - tt) + props.added_mass_axial * tt))


def fairlead_terms(line: CatenaryLine, props: LineHydrodynamics, water_density: float, anchor) -> ca.Function:
    """``(r, HV, ṙ) → (drag [N], mass [kg], points [m], velocities [m/s])`` of one line (SX Function).

    ``r`` the fairlead position, ``HV`` its solved catenary forces (H, V) at ``r``, ``ṙ`` its velocity
    (inertial axes). ``drag`` is the line's drag as a fairlead force ``Σ G_iᵀ f_i``, ``mass`` the
    fairlead mass ``Σ G_iᵀ M_i G_i`` (3 × 3), with ``G_i`` the nodes' total sensitivity to the fairlead
    (H, V following the spans by the implicit-function theorem).
    """
    r, hv, rd = ca.SX.sym("r", 3), ca.SX.sym("HV", 2), ca.SX.sym("rd", 3)
    n = props.segments
    points, tangents = line_nodes(line, n, hv[0], hv[1], anchor, r)
    flat = ca.vec(points)
    d = r[0:2] - ca.DM(np.asarray(anchor[:2], dtype=float))
    spans_r = ca.vertcat(ca.sqrt(ca.sumsqr(d)), r[2] - float(anchor[2]))
    spans_hv = ca.vertcat(*line.spans(hv[0], hv[1]))
    dhv_dr = ca.solve(ca.jacobian(spans_hv, hv), ca.jacobian(spans_r, r))
    G = ca.jacobian(flat, r) + ca.mtimes(ca.jacobian(flat, hv), dhv_dr)       # 3(n+1) × 3
    velocities = ca.reshape(ca.mtimes(G, rd), 3, n + 1)
    forces = node_drag(props, line.length, water_density, tangents, velocities)
    drag = ca.mtimes(G.T, ca.vec(forces))
    mass = ca.DM.zeros(3, 3)
    for i, share in enumerate(props.weights):
        Gi = G[3 * i:3 * i + 3, :]
        mass = mass + ca.mtimes([Gi.T, node_mass(props, line.length, water_density, tangents[:, i], share), Gi])
    return ca.Function("line_terms", [r, hv, rd], [drag, mass, points, velocities], ["r", "HV", "rd"],
                       ["drag", "mass", "points", "velocities"], {"cse": True})
