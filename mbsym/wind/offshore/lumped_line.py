"""MoorDyn's lumped-mass line at rest: the spans of its segments and the force at the fairlead.

MoorDyn (OpenFAST's ``MoorDyn_Line.f90``) cuts a line of unstretched length L into ``NumSegs`` = N segments
of equal unstretched length l₀ = L/N and lumps the line at the N + 1 nodes: each internal node carries the
wet weight W = w l₀ of one segment (w = (m − ρ π d²/4) g), the two end nodes W/2; a segment stretched to
length ℓ pulls its nodes together with T = EA (ℓ/l₀ − 1); a node below the seabed is pushed up by
``kBot`` · penetration · d l₀. The fairlead node passes to the vessel the first segment's pull plus its own
weight W/2 (MoorDyn's ``FAIRTEN`` is the size of that force, ``MoorDyn_IO.f90``).

At rest in still water the chain is a polygon whose segments carry the same horizontal force H. Counting
segments j = 1 … N from the fairlead, with V the vertical force at the fairlead, segment j carries the
vertical force ``v_j = V − W/2 − (j − 1) W`` while that is positive (each node hangs one W below the
previous); where it would be negative the segment lies on the seabed (v_j = 0, the node's weight carried by
the seabed) and pulls H. So, with ``v⁺_j = max(v_j, 0)`` and ``T_j = √(H² + v⁺_j²)``::

    l = Σ_j l₀ (1 + T_j/EA) H/T_j        h = Σ_j l₀ (1 + T_j/EA) v⁺_j/T_j

the horizontal and vertical span from the anchor to the fairlead, closed-form in (H, V) as the continuous
elastic catenary's (:class:`~.catenary.CatenaryLine`, its limit as N → ∞). Given (l, h), a few Newton steps
from the continuous catenary's (H₀, V₀) solve them. MoorDyn's seabed springs ``kBot`` let the resting nodes
sink by ``p = w/(kBot d)`` (5.8 mm for the VolturnUS-S): the laid part lies p below the anchor's height, so
``h`` is counted from there, ``h + p min(1, −v_N/W)`` while the segment at the anchor lies down (v_N ≤ 0).
The node where the line leaves the seabed, partly carried by its spring, is taken as hanging. Against the
chain's full balance with the springs (every node's position solved by Newton's method; VolturnUS-S line,
spans 785-805 m) (H, V) agree within 1.1e-4 and ∂H/∂l within 1 % of the catenary's (the ripple is ±4-5 %);
4 Newton steps reach 2e-14 of the converged spans over spans 735-826 m and heights 167-205 m.

With few segments the chain is not the catenary: as the fairlead moves, the nodes lie down on the seabed one
at a time (a kink in the spans at every ``v_j = 0``), and the line's horizontal stiffness ripples about the
catenary's with every node that lifts off. For the VolturnUS-S (50 segments of 17 m) the upwind line's
∂H/∂l ripples by ±4–5 % over every 2.5 m of fairlead travel, which shortens OpenFAST's slow surge period
about the 13 m/s offset by 1.3 % against the same run with 100 segments (docs/offshore.md §7).

Not modelled here: MoorDyn's line dynamics (its nodes' own motion, internal damping, the seabed's damping
``cBot``); :mod:`.line_dynamics` puts the lines' drag and inertia on the continuous shape.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ParameterError
from .catenary import CatenaryLine

__all__ = ["LumpedLine", "LUMPED_NEWTON_STEPS"]

#: Newton steps from the continuous catenary's (H₀, V₀) (:meth:`LumpedLine.function`).
LUMPED_NEWTON_STEPS = 4


@dataclass(frozen=True)
class LumpedLine:
    """One MoorDyn line as its lumped masses at rest (module docstring).

    Parameters
    ----------
    catenary : CatenaryLine
        The same line as a continuous catenary: length L [m], wet weight w [N/m], EA [N], no seabed friction.
    segments : int
        MoorDyn's ``NumSegs`` N (≥ 1).
    penetration : float
        How far a resting node sinks into the seabed, w/(kBot d) [m] (0: a rigid seabed).
    steps : int
        Newton steps from the catenary's forces (default :data:`LUMPED_NEWTON_STEPS`).
    """

    catenary: CatenaryLine
    segments: int
    penetration: float = 0.0
    steps: int = LUMPED_NEWTON_STEPS

    def __post_init__(self) -> None:
        if not isinstance(self.catenary, CatenaryLine):
            raise ParameterError(f"LumpedLine.catenary must be a CatenaryLine; got {type(self.catenary).__name__}.")
        if self.catenary.seabed_friction:
            raise ParameterError("LumpedLine: MoorDyn's lumped line at rest has no seabed friction; the catenary "
                                 f"has a friction coefficient {self.catenary.seabed_friction}.")
        for name in ("segments", "steps"):
            value = getattr(self, name)
            if not (isinstance(value, (int, np.integer)) and value >= 1):
                raise ParameterError(f"LumpedLine.{name} must be a positive integer; got {value!r}.")
        if not (isinstance(self.penetration, (int, float)) and 0.0 <= self.penetration < self.catenary.length):
            raise ParameterError(f"LumpedLine.penetration must be a number >= 0 [m] (w / (kBot d)); got "
                                 f"{self.penetration!r}.")

    def spans(self, H, V):
        """Horizontal and vertical span (l, h) [m] of the chain at rest for fairlead forces H, V [N] (module
        docstring; numbers or CasADi expressions)."""
        L, w, EA, n = self.catenary.length, self.catenary.weight, self.catenary.axial_stiffness, self.segments
        l0 = L / n
        v = ca.fmax(V - w * l0 * (np.arange(n) + 0.5), 0.0)        # each segment's vertical force
        T = ca.sqrt(H ** 2 + v ** 2)
        stretched = l0 * (1.0 + T / EA) / T
        l, h = ca.sum1(stretched * H), ca.sum1(stretched * v)
        if self.penetration:
            laid = ca.fmin(1.0, ca.fmax(0.0, (w * l0 * (n - 0.5) - V) / (w * l0)))
            h = h - self.penetration * laid
        if isinstance(H, (ca.SX, ca.MX)) or isinstance(V, (ca.SX, ca.MX)):
            return l, h
        return float(ca.evalf(l)), float(ca.evalf(h))

    def function(self) -> ca.Function:
        """``(l, h, H₀, V₀) → (H, V)`` [m, m, N, N → N, N] (SX): the fairlead forces of the chain at rest after
        :attr:`steps` Newton steps on :meth:`spans` from the continuous catenary's forces (H₀, V₀)."""
        cached = self.__dict__.get("_function")
        if cached is not None:
            return cached
        x, p = ca.SX.sym("HV", 2), ca.SX.sym("lh", 2)
        lm, hm = self.spans(x[0], x[1])
        r = ca.vertcat(lm - p[0], hm - p[1])
        tiny = 1e-6 * self.catenary.weight * self.catenary.length
        step = ca.Function("lumped_step", [x, p], [ca.vertcat(ca.fmax(x[0], tiny), x[1])
                                                   - ca.solve(ca.jacobian(r, x), r)])
        l, h, h0, v0 = (ca.SX.sym(n) for n in ("l", "h", "H0", "V0"))
        hv = ca.vertcat(h0, v0)
        for _ in range(self.steps):
            hv = step(hv, ca.vertcat(l, h))
        fn = ca.Function("lumped_line", [l, h, h0, v0], [hv[0], hv[1]], ["l", "h", "H0", "V0"], ["H", "V"])
        object.__setattr__(self, "_function", fn)
        return fn

    def forces(self, l, h, h0, v0):
        """(H, V) [N] of :meth:`function` for numbers (floats back) or CasADi expressions."""
        out = self.function()(l, h, h0, v0)
        if any(isinstance(v, (ca.SX, ca.MX)) for v in (l, h, h0, v0)):
            return out
        return float(out[0]), float(out[1])
