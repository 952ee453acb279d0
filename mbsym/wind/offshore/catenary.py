"""Quasi-static elastic catenary of one mooring line with seabed contact (MAP++'s line model).

A line of unstretched length L, weight in water w per unit length, axial stiffness EA and
seabed friction coefficient C_B hangs between an anchor on the sea floor and a fairlead a
horizontal distance l and a height h above it. With H and V the horizontal and vertical
force at the fairlead (MAP++ documentation, "Theory"; Jonkman 2007, NREL/TP-500-41958 §4.2):

* line clear of the seabed (V ≥ w L)::

    l = H/w [asinh(V/H) − asinh((V − wL)/H)] + H L / EA
    h = H/w [√(1 + (V/H)²) − √(1 + ((V − wL)/H)²)] + (V L − w L²/2) / EA

* part L_B = L − V/w resting on the seabed (V < w L)::

    l = L_B + H/w asinh(V/H) + H L / EA
        + C_B w / (2 EA) [−L_B² + (L_B − H/(C_B w)) max(L_B − H/(C_B w), 0)]
    h = H/w [√(1 + (V/H)²) − 1] + V² / (2 EA w)

(the friction term vanishes for C_B = 0, MoorDyn's default seabed). Given (l, h) the two
equations are solved for (H, V) by Newton's method inside a CasADi ``rootfinder`` (started
from MAP++'s initial guess of Peyrot and Goulois), so H and V — and every load built from them
— are differentiable in the fairlead position (implicit-function theorem). Line inertia,
drag and the seabed's stiffness are not modelled here (:mod:`.line_dynamics` adds drag and inertia
on the quasi-static shape).

The shape (:meth:`CatenaryLine.profile`) at unstretched arc length s from the anchor, with
L_B = max(L − V/w, 0) on the seabed, V_A = max(V − wL, 0) the vertical force at the anchor (or at
the touchdown point) and σ = max(s − L_B, 0) the arc length along the hanging part::

    x(s) = min(s, L_B) + ∫₀^min(s, L_B) T_B/EA ds'
           + H/w [asinh((V_A + wσ)/H) − asinh(V_A/H)] + H σ/EA
    z(s) = H/w [√(1 + ((V_A + wσ)/H)²) − √(1 + (V_A/H)²)] + (V_A σ + wσ²/2)/EA

with the tension on the seabed T_B(s) = max(H − C_B w (L_B − s), 0); at s = L it is (l, h) above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ParameterError, SolverError

__all__ = ["CatenaryLine", "wet_weight"]


def wet_weight(mass_per_length: float, diameter: float, water_density: float, gravity: float) -> float:
    """Weight in water per unit length [N/m]: (m − ρ π d²/4) g, as MoorDyn and MAP++ compute it."""
    return (mass_per_length - water_density * math.pi * diameter ** 2 / 4.0) * gravity


def _spans(H, V, L: float, w: float, EA: float, CB: float):
    """(l, h) of the elastic catenary for fairlead forces (H, V) (module docstring)."""
    va = V - w * L
    free_l = H / w * (ca.asinh(V / H) - ca.asinh(va / H)) + H * L / EA
    free_h = H / w * (ca.sqrt(1 + (V / H) ** 2) - ca.sqrt(1 + (va / H) ** 2)) + (V * L - w * L ** 2 / 2) / EA
    lb = L - V / w
    friction = 0.0
    if CB > 0:
        slack = lb - H / (CB * w)
        friction = CB * w / (2 * EA) * (-lb ** 2 + slack * ca.fmax(slack, 0))
    touch_l = lb + H / w * ca.asinh(V / H) + H * L / EA + friction
    touch_h = H / w * (ca.sqrt(1 + (V / H) ** 2) - 1) + V ** 2 / (2 * EA * w)
    lifted = V >= w * L
    return ca.if_else(lifted, free_l, touch_l), ca.if_else(lifted, free_h, touch_h)


@dataclass(frozen=True)
class CatenaryLine:
    """One quasi-static elastic mooring line (see the module docstring).

    Parameters
    ----------
    length : float
        Unstretched length L [m].
    weight : float
        Weight in water per unit length w [N/m] (:func:`wet_weight`).
    axial_stiffness : float
        EA [N].
    seabed_friction : float, optional
        C_B [-] (MAP++'s ``CB``; 0 for MoorDyn's frictionless seabed).

    Examples
    --------
    >>> line = CatenaryLine(850.0, wet_weight(685.0, 0.333, 1025.0, 9.81), 3.27e9)
    >>> H, V = line.solve(779.6, 186.0)
    >>> 1.0e6 < H < 3.0e6 and 1.0e6 < V < line.weight * line.length
    True
    """

    length: float
    weight: float
    axial_stiffness: float
    seabed_friction: float = 0.0

    def __post_init__(self) -> None:
        for name in ("length", "weight", "axial_stiffness"):
            value = float(getattr(self, name))
            if not (math.isfinite(value) and value > 0):
                raise ParameterError(f"CatenaryLine.{name} must be a finite number > 0; got {value}.")
        if not (math.isfinite(self.seabed_friction) and self.seabed_friction >= 0):
            raise ParameterError(f"CatenaryLine.seabed_friction must be >= 0; got {self.seabed_friction}.")

    def spans(self, H, V):
        """Horizontal and vertical span (l, h) [m] for fairlead forces H, V [N] (numbers or CasADi)."""
        l, h = _spans(H, V, self.length, self.weight, self.axial_stiffness, self.seabed_friction)
        if isinstance(H, (ca.SX, ca.MX)) or isinstance(V, (ca.SX, ca.MX)):
            return l, h
        return float(ca.evalf(l)), float(ca.evalf(h))

    def profile(self, H, V, s):
        """Horizontal and vertical distance (x, z) [m] from the anchor of the points at unstretched arc
        lengths ``s`` [m] (0 at the anchor, L at the fairlead) for fairlead forces H, V [N] (module
        docstring); CasADi expressions (or numbers for numeric arguments), elementwise in ``s``."""
        L, w, EA, CB = self.length, self.weight, self.axial_stiffness, self.seabed_friction
        s = ca.DM(s) if not isinstance(s, (ca.SX, ca.MX)) else s
        lb = ca.fmax(L - V / w, 0)
        va = ca.fmax(V - w * L, 0)
        on_bed = ca.fmin(s, lb)
        sigma = ca.fmax(s - lb, 0)
        # stretch of the resting part: the integral of T_B = max(a + b s', 0), a = H - C_B w L_B, b = C_B w
        a, b = H - CB * w * lb, CB * w
        start = ca.fmax(lb - H / (CB * w), 0) if CB > 0 else 0.0
        run = ca.fmax(on_bed - start, 0)
        stretch = (a * run + b / 2 * ((start + run) ** 2 - start ** 2)) / EA
        vs = va + w * sigma
        x = on_bed + stretch + H / w * (ca.asinh(vs / H) - ca.asinh(va / H)) + H * sigma / EA
        z = H / w * (ca.sqrt(1 + (vs / H) ** 2) - ca.sqrt(1 + (va / H) ** 2)) + (va * sigma + w * sigma ** 2 / 2) / EA
        if any(isinstance(v, (ca.SX, ca.MX)) for v in (H, V, s)):
            return x, z
        return np.array(ca.evalf(x), dtype=float).ravel(), np.array(ca.evalf(z), dtype=float).ravel()

    def initial_guess(self, l, h):
        """MAP++'s starting point (Peyrot and Goulois): λ from the span, H0 = w l / (2 λ), V0 = w/2 (h / tanh λ + L)."""
        L, w = self.length, self.weight
        chord = ca.sqrt(l ** 2 + h ** 2)
        lam = ca.if_else(L <= chord, 0.2, ca.sqrt(3 * ((L ** 2 - h ** 2) / ca.fmax(l ** 2, 1e-12) - 1)))
        lam = ca.fmax(lam, 0.2)
        return ca.fabs(w * l / (2 * lam)), w / 2 * (h / ca.tanh(lam) + L)

    def function(self) -> ca.Function:
        """CasADi ``Function`` ``(l, h) → (H, V)`` [m → N]: Newton on the span equations
        (a ``rootfinder``; derivatives by the implicit-function theorem)."""
        x, p = ca.SX.sym("HV", 2), ca.SX.sym("lh", 2)
        l_model, h_model = self.spans(x[0], x[1])
        residual = ca.Function("catenary_residual", [x, p], [ca.vertcat(l_model - p[0], h_model - p[1])])
        solver = ca.rootfinder("catenary", "newton", residual, {"abstol": 1e-6, "max_iter": 100,
                                                                 "error_on_fail": True})
        lh = ca.MX.sym("lh", 2)
        guess = ca.vertcat(*self.initial_guess(lh[0], lh[1]))
        HV = solver(guess, lh)
        return ca.Function("catenary", [lh], [HV[0], HV[1]], ["lh"], ["H", "V"])

    def solve(self, l: float, h: float) -> tuple[float, float]:
        """Fairlead forces (H, V) [N] for the spans l, h [m] (numbers).

        Raises
        ------
        SolverError
            When Newton does not converge (e.g. a span longer than the stretched line can reach).
        """
        if not (l > 0 and math.isfinite(l) and math.isfinite(h)):
            raise ParameterError(f"the horizontal span must be > 0 and both spans finite; got l={l}, h={h}.")
        try:
            H, V = self.function()(ca.DM([l, h]))
        except RuntimeError as err:
            raise SolverError(f"the catenary of a {self.length} m line did not converge for spans l={l} m, "
                              f"h={h} m ({err}). Check the line length against the anchor-fairlead distance.") from None
        return float(H), float(V)

    def anchor_tension(self, H: float, V: float) -> float:
        """Tension at the anchor [N]: √(H² + (V − wL)²) when lifted, else the horizontal force left
        after friction on the resting part, max(H − C_B w L_B, 0) (MAP++)."""
        w, L = self.weight, self.length
        if V >= w * L:
            return math.hypot(H, V - w * L)
        return max(H - self.seabed_friction * w * (L - V / w), 0.0)
