"""The submerged volume of a cylindrical or conical element cut by the still-water plane, and its centroid.

A strip-theory member that crosses the still-water level (HydroDyn ``PropPot = FALSE``, ``MHstLMod = 1``) is
buoyed element by element at its **displaced** position: HydroDyn v5.0.0's ``getElementHstLds_Mod1`` (read for the
facts) gives each element's side pressure for three cases — both nodes below the plane ``z = 0``, the lower one
below and the upper one above, both above — and the member's end plates their own. Summed over a member whose end
plates are each under water or out of it, side and end pressures give Archimedes' force ``ρ g V_s e_z`` through
the centroid of the submerged volume ``V_s`` (the pressure at the free surface is zero), so this module gives, per
element, ``V_s`` and ``V_s c`` with ``c`` its centroid:

* **submerged** (frustum of radii ``r₁``, ``r₂``, length ``l`` along the unit axis ``k``):
  ``V = π l (r₁² + r₁r₂ + r₂²)/3``, ``V h = π l² (r₁² + 2r₁r₂ + 3r₂²)/12`` along ``k`` from node 1;
* **cut** at ``h₀ = l z₁/(z₁ − z₂)`` along the axis from the submerged node (``γ`` the angle between the axis and
  the plane's normal, ``cos γ = k_z``): a straight cylinder, exactly,
  ``V = π r² h₀``, ``V h = π r² (4 h₀² + r² tan²γ)/8`` along ``k``, ``V ρ = −π r⁴ tan γ / 4`` along the
  horizontal ``r̂`` (``sin γ r̂ = e_z − k_z k``); a cone (slope ``s = dr/dl``), with the elliptic waterplane of
  semi-axes ``a₀ = r_h/(C₁ cos γ)``, ``b₀ = r_h/√C₁`` (``r_h = r₁ + s h₀``, ``C₁ = 1 − s² tan²γ``) and
  ``C₂ = a₀ b₀ r_h cos γ − r₁³``: ``V = π C₂/(3s)``, ``V h = π (a₀b₀ r_h² cos γ/C₁ − r₁⁴ − 4 r₁ C₂/3)/(4 s²)``,
  ``V ρ = −π a₀ b₀ r_h² sin γ/(4 C₁)``;
* **dry**: nothing.

Only the element's total matters on a rigid platform, so HydroDyn's split between its two nodes is not needed.
"""

from __future__ import annotations

import math

import casadi as ca

__all__ = ["element_buoyancy", "TAPER_TOLERANCE"]

#: |dr/dl| below which an element is a straight cylinder (HydroDyn's ``abs(dRdl) < 0.0001``).
TAPER_TOLERANCE = 1e-4
#: Smallest cos γ used (an element lying in the plane has no defined cut; such members are refused).
_COS_MIN = 1e-3


def _full(r1: float, r2: float, length: float) -> tuple[float, float]:
    volume = math.pi * length * (r1 * r1 + r1 * r2 + r2 * r2) / 3.0
    first = math.pi * length ** 2 * (r1 * r1 + 2.0 * r1 * r2 + 3.0 * r2 * r2) / 12.0
    return volume, first


def _cut(p1, k, z1, z2, r1: float, slope: float, length: float):
    """``(V, V c)`` of the element below the plane when node 1 (at ``p1``, height ``z1 < 0``) is submerged and
    node 2 (``z2 ≥ 0``) is not; ``k`` from node 1 to node 2."""
    h0 = length * z1 / (z1 - z2)
    cos = ca.fmax(k[2], _COS_MIN)
    w = ca.vertcat(0.0, 0.0, 1.0) - k[2] * k                 # sin γ · r̂
    tan2 = ca.sumsqr(w) / (cos * cos)
    if abs(slope) < TAPER_TOLERANCE:
        volume = math.pi * r1 * r1 * h0
        along = math.pi * r1 * r1 * (4.0 * h0 * h0 + r1 * r1 * tan2) / 8.0
        radial = -math.pi * r1 ** 4 / (4.0 * cos) * w
    else:
        rh = r1 + slope * h0
        c1 = 1.0 - slope * slope * tan2
        a0b0 = rh * rh / (c1 * cos * ca.sqrt(c1))
        c2 = a0b0 * rh * cos - r1 ** 3
        volume = math.pi * c2 / (3.0 * slope)
        along = math.pi * (a0b0 * rh * rh * cos / c1 - r1 ** 4 - 4.0 * r1 * c2 / 3.0) / (4.0 * slope * slope)
        radial = -math.pi * a0b0 * rh * rh / (4.0 * c1) * w
    return volume, volume * p1 + along * k + radial


def element_buoyancy(p1, p2, z1, z2, r1: float, r2: float, length: float):
    """``(V_s, V_s c)`` of one element below the still-water plane (module docstring), CasADi expressions.

    Parameters
    ----------
    p1, p2 : casadi (3)
        The element's nodes, displaced (any origin: ``c`` comes in the same one) [m].
    z1, z2 : casadi scalar
        Their heights above the still-water level [m].
    r1, r2 : float
        Radii at the nodes (HydroDyn's ``√C_b``-scaled ones) [m].
    length : float
        The element's length [m].
    """
    k = (p2 - p1) / length
    volume, first = _full(r1, r2, length)
    full = (volume, volume * p1 + first * k)
    slope = (r2 - r1) / length
    up = _cut(p1, k, z1, z2, r1, slope, length)              # node 1 under water, node 2 above
    down = _cut(p2, -k, z2, z1, r2, -slope, length)          # node 2 under water, node 1 above
    below1, below2 = z1 < 0, z2 < 0
    v = ca.if_else(below1, ca.if_else(below2, full[0], up[0]), ca.if_else(below2, down[0], 0.0))
    vc = ca.if_else(below1, ca.if_else(below2, full[1], up[1]), ca.if_else(below2, down[1], ca.DM.zeros(3)))
    return v, vc
