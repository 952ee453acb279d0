"""The tower's aerodynamics: its drag, and its disturbance of the flow the blades see (AeroDyn 15).

AeroDyn's tower is a line of nodes at the elevations ``TwrElev`` [m] with diameter ``TwrDiam``, drag
coefficient ``TwrCd`` and (Eames shadow) turbulence intensity ``TwrTI``. Three switches use it; the
conventions are AeroDyn v5's (AeroDyn.f90 ``ADTwr_CalcOutput``, ``CalculateTowerInfluence``,
``TwrInfl_NearestLine2Element``, ``TwrInfl_NearestPoint``), written here from their equations.

**Drag** (``TwrAero = True``). A tower section of diameter ``D`` in the relative flow ``V`` (wind minus
the section's velocity) carries per unit length

    f = ½ ρ C_d D |V_n| V_n,    V_n = V − (V·t) t

with ``t`` the tower's axis: only the flow across the tower loads it (:func:`drag_per_length`).

**Disturbance of the blade inflow** (``TwrPotent``, ``TwrShadow``). For a point ``P`` (a blade node),
take the nearest point of the tower line: its foot on the line when the projection falls between the
line's ends (``z̄ = 0``), else the end node, where ``z̄ = 2 (P − end)·t / D`` and the local distances are
stretched by ``1 / cos(π z̄ / 2)`` (the influence tapers to zero one radius beyond the end). In the axes
``x̂`` along the relative flow across the tower there (``W = |V_n|``) and ``ŷ = t × x̂``, with
``x̄, ȳ`` the point's distances along them divided by the local radius ``D/2``:

- potential flow around a cylinder (``TwrPotent = 1``): ``u = (ȳ² − x̄²)/(x̄² + ȳ²)²``,
  ``v = −2 x̄ ȳ/(x̄² + ȳ²)²``; with Bak's correction (``TwrPotent = 2``) ``x̄ + 0.1`` in those and
  ``+ C_d x̄ / (2π (x̄² + ȳ²))``, ``+ C_d ȳ / (2π (x̄² + ȳ²))`` added;
- shadow downstream (``x̄ > 0``): Powles (``TwrShadow = 1``) ``u = −C_d/√r̄ cos²(π ȳ / (2 √r̄))`` inside
  ``|ȳ| < √r̄`` (``r̄ = √(x̄² + ȳ²)``), Eames (``TwrShadow = 2``) ``u = −C_d/(TI x̄ √(2π))
  exp(−½ (ȳ/(TI x̄))²)``; the shadow deficit is held above −0.5;

and the flow at ``P`` changes by ``W (u x̂ + v ŷ)``. Points closer than 1 % of ``D`` to the tower's
surface or farther than 20 ``D`` are left undisturbed. Both are valid for small tower deflections: the
tower is taken as the straight line between its lowest and highest AeroDyn nodes as they move (the
deflected tower's bow changes the blade-to-tower distance by less than 1 % of the ~10 m clearances).

The flow the tower sees is, as in AeroDyn, the wind at the tower minus the tower's velocity; this module
takes the wind at the disturbed point itself (the same in a uniform or sheared wind at one height; in a
turbulent field the two points are a clearance apart, and the deficit is a few % of the wind).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ParameterError

__all__ = ["TowerAero", "drag_per_length", "POTENTIAL_MODELS", "SHADOW_MODELS"]

#: TwrPotent: 0 none, 1 baseline potential flow, 2 potential flow with Bak's correction.
POTENTIAL_MODELS = (0, 1, 2)
#: TwrShadow: 0 none, 1 Powles, 2 Eames.
SHADOW_MODELS = (0, 1, 2)
_TRUE = ("true", "t", ".true.")
_BAK_OFFSET = 0.1            # Bak, Madsen, Johansen (2001): x̄ shifted by 0.1 radius (AeroDyn's TwrPotent = 2)
_SHADOW_FLOOR = -0.5         # AeroDyn: the shadow deficit is limited to half the wind
_NEAR, _FAR = 0.01, 20.0     # AeroDyn: undisturbed within 1 % of D of the surface and beyond 20 D


@dataclass(frozen=True, eq=False)
class TowerAero:
    """AeroDyn's tower table and switches (module docstring).

    Attributes
    ----------
    elevation, diameter, drag_coefficient, turbulence_intensity : ndarray (N,)
        ``TwrElev`` [m], ``TwrDiam`` [m], ``TwrCd`` [-], ``TwrTI`` [-], elevations increasing.
    potential : int
        ``TwrPotent`` (:data:`POTENTIAL_MODELS`).
    shadow : int
        ``TwrShadow`` (:data:`SHADOW_MODELS`).
    drag : bool
        ``TwrAero``: the drag loads the tower.
    """

    elevation: np.ndarray
    diameter: np.ndarray
    drag_coefficient: np.ndarray
    turbulence_intensity: np.ndarray
    potential: int = 0
    shadow: int = 0
    drag: bool = False

    def __post_init__(self) -> None:
        arrays = {}
        for name in ("elevation", "diameter", "drag_coefficient", "turbulence_intensity"):
            value = np.array(getattr(self, name), dtype=float).reshape(-1)
            value.setflags(write=False)
            arrays[name] = value
            object.__setattr__(self, name, value)
        z = arrays["elevation"]
        if z.size < 2 or not np.all(np.isfinite(z)) or np.any(np.diff(z) <= 0):
            raise ParameterError(f"TowerAero.elevation (TwrElev) must hold at least 2 increasing heights [m]; got "
                                 f"{z.tolist()}.")
        for name in ("diameter", "drag_coefficient", "turbulence_intensity"):
            if arrays[name].size != z.size:
                raise ParameterError(f"TowerAero.{name} has {arrays[name].size} values for {z.size} tower nodes.")
        if np.any(arrays["diameter"] <= 0) or not np.all(np.isfinite(arrays["diameter"])):
            raise ParameterError(f"TowerAero.diameter (TwrDiam) must be positive [m]; got {arrays['diameter'].tolist()}.")
        if np.any(arrays["drag_coefficient"] < 0):
            raise ParameterError("TowerAero.drag_coefficient (TwrCd) must be >= 0.")
        if self.potential not in POTENTIAL_MODELS:
            raise ParameterError(f"TowerAero.potential (TwrPotent) must be one of {POTENTIAL_MODELS}; got "
                                 f"{self.potential!r}.")
        if self.shadow not in SHADOW_MODELS:
            raise ParameterError(f"TowerAero.shadow (TwrShadow) must be one of {SHADOW_MODELS}; got {self.shadow!r}.")
        if self.shadow == 2 and np.any(arrays["turbulence_intensity"] <= 0):
            raise ParameterError("the Eames tower shadow (TwrShadow = 2) needs TwrTI > 0 at every tower node.")
        object.__setattr__(self, "drag", bool(self.drag))

    @classmethod
    def from_aerodyn(cls, aerodyn) -> "TowerAero | None":
        """The tower of an AeroDyn input, or None when none of ``TwrPotent``, ``TwrShadow``, ``TwrAero`` is on.

        Raises
        ------
        ParameterError
            A switch is on but the tower table is missing or invalid; a switch value AeroDyn does not have.
        """
        extra = dict(aerodyn.extra or {})
        potential = _switch(extra.get("TwrPotent", "0"), "TwrPotent", aerodyn.source)
        shadow = _switch(extra.get("TwrShadow", "0"), "TwrShadow", aerodyn.source)
        drag = str(extra.get("TwrAero", "False")).strip().strip("\"'").lower() in _TRUE
        if not (potential or shadow or drag):
            return None
        if aerodyn.tower_elevation is None or np.size(aerodyn.tower_elevation) < 2:
            raise ParameterError(f"{aerodyn.source}: TwrPotent/TwrShadow/TwrAero need the tower table (NumTwrNds >= 2 "
                                 "rows of TwrElev, TwrDiam, TwrCd, TwrTI).")
        ti = aerodyn.tower_ti if aerodyn.tower_ti is not None and np.size(aerodyn.tower_ti) else \
            np.zeros_like(aerodyn.tower_elevation)
        return cls(aerodyn.tower_elevation, aerodyn.tower_diameter, aerodyn.tower_drag, ti, potential=potential,
                   shadow=shadow, drag=drag)

    @property
    def disturbs_inflow(self) -> bool:
        """Whether the tower changes the flow at the blades (``TwrPotent`` or ``TwrShadow``)."""
        return bool(self.potential or self.shadow)

    def nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """Trapezoidal integration weights [m] of the tower nodes and their elevations [m]: ``Σ w f`` is the
        resultant of a load per unit length ``f`` varying linearly between the nodes (AeroDyn's line mesh)."""
        z = self.elevation
        w = np.zeros_like(z)
        w[:-1] += 0.5 * np.diff(z)
        w[1:] += 0.5 * np.diff(z)
        return w, z

    def disturbance(self, points: Any, wind: Any, start: Any, end: Any, start_velocity: Any = None,
                    end_velocity: Any = None) -> Any:
        """The change of the flow at ``points`` caused by the tower (module docstring) [m/s].

        Parameters
        ----------
        points : SX or DM (3, N)
            Where the flow is disturbed (blade nodes), ground axes [m].
        wind : SX or DM (3, N)
            The undisturbed wind at the points [m/s].
        start, end : SX or DM (3, 1)
            The tower's lowest and highest AeroDyn nodes (``TwrElev[0]``, ``TwrElev[-1]``), ground axes [m].
        start_velocity, end_velocity : SX or DM (3, 1), optional
            Their velocities [m/s] (default at rest); the tower's velocity at a point of the line is
            interpolated linearly between them, and the tower sees the wind minus it.

        Returns
        -------
        SX or DM (3, N)
            The velocity to add to the wind at the points [m/s].
        """
        n = points.size2()
        axis = end - start
        length = ca.norm_2(axis)
        t = axis / length
        rel = points - ca.repmat(start, 1, n)
        s = ca.mtimes(t.T, rel) / length                                   # 0 … 1 between the ends
        inside = ca.logic_and(s >= 0, s <= 1)
        s_end = ca.if_else(s > 1, 1.0, 0.0)
        s_near = ca.if_else(inside, s, s_end)
        foot = ca.repmat(start, 1, n) + ca.mtimes(axis, s_near)
        r = points - foot
        h = self.elevation[0] + s_near * (self.elevation[-1] - self.elevation[0])
        diameter = _interp(self.elevation, self.diameter, h)
        cd = _interp(self.elevation, self.drag_coefficient, h)
        zbar = ca.if_else(inside, 0.0, 2.0 * ca.mtimes(t.T, r) / diameter)
        taper = ca.cos(0.5 * math.pi * ca.fmin(ca.fabs(zbar), 1.0))
        flow = wind
        if start_velocity is not None:
            flow = flow - ca.mtimes(start_velocity, 1.0 - s_near) - ca.mtimes(end_velocity, s_near)
        across = flow - ca.mtimes(t, ca.mtimes(t.T, flow))                  # V_n: the flow across the tower
        w2 = ca.sum1(across**2)
        w = ca.sqrt(w2 + 1e-12)
        side = _cross(t, across)
        scale = 2.0 / (diameter * ca.fmax(taper, 1e-6) * w)
        xbar, ybar = ca.sum1(r * across) * scale, ca.sum1(r * side) * scale
        u = self._potential(xbar, ybar, cd) + self._shadow(xbar, ybar, cd, _interp(self.elevation,
                                                                                   self.turbulence_intensity, h))
        v = self._potential_side(xbar, ybar, cd)
        clearance = ca.sqrt(ca.sum1(r**2)) - 0.5 * diameter
        active = ca.logic_and(ca.logic_and(ca.fabs(zbar) < 1, clearance > _NEAR * diameter),
                              clearance <= _FAR * diameter)
        u, v = ca.if_else(active, u, 0.0), ca.if_else(active, v, 0.0)
        return across * ca.repmat(u, 3, 1) + side * ca.repmat(v, 3, 1)

    def _potential(self, xbar: Any, ybar: Any, cd: Any) -> Any:
        if not self.potential:
            return 0.0
        x = xbar + (_BAK_OFFSET if self.potential == 2 else 0.0)
        r2 = x**2 + ybar**2
        u = (ybar**2 - x**2) / r2**2
        return u + cd * x / (2 * math.pi * r2) if self.potential == 2 else u

    def _potential_side(self, xbar: Any, ybar: Any, cd: Any) -> Any:
        if not self.potential:
            return 0.0
        x = xbar + (_BAK_OFFSET if self.potential == 2 else 0.0)
        r2 = x**2 + ybar**2
        v = -2.0 * x * ybar / r2**2
        return v + cd * ybar / (2 * math.pi * r2) if self.potential == 2 else v

    def _shadow(self, xbar: Any, ybar: Any, cd: Any, ti: Any) -> Any:
        if not self.shadow:
            return 0.0
        if self.shadow == 1:                                                # Powles
            root = ca.sqrt(ca.sqrt(xbar**2 + ybar**2))
            deficit = ca.if_else(ca.fabs(ybar) < root, -cd / root * ca.cos(0.5 * math.pi * ybar / root) ** 2, 0.0)
        else:                                                               # Eames
            spread = ti * ca.fmax(xbar, 1e-9)
            deficit = -cd / (spread * math.sqrt(2 * math.pi)) * ca.exp(-0.5 * (ybar / spread) ** 2)
        return ca.if_else(xbar > 0, ca.fmax(deficit, _SHADOW_FLOOR), 0.0)


def drag_per_length(flow: Any, axis: Any, diameter, drag_coefficient, rho: Any) -> Any:
    """AeroDyn's tower drag per unit length, ``½ ρ C_d D |V_n| V_n`` [N/m] (module docstring).

    Parameters
    ----------
    flow : SX or DM (3, N)
        Relative flow at the tower nodes (wind minus the node's velocity) [m/s].
    axis : SX or DM (3, N) or (3, 1)
        Unit tower axis at the nodes.
    diameter, drag_coefficient : array_like (N,)
        ``TwrDiam`` [m], ``TwrCd`` [-].
    rho : SX or float
        Air density [kg/m³].
    """
    n = flow.size2()
    if axis.size2() == 1:
        axis = ca.repmat(axis, 1, n)
    across = flow - axis * ca.repmat(ca.sum1(axis * flow), 3, 1)
    speed = ca.sqrt(ca.sum1(across**2) + 1e-12)
    q = 0.5 * rho * ca.DM(np.asarray(drag_coefficient, dtype=float) * np.asarray(diameter, dtype=float)).T * speed
    return across * ca.repmat(q, 3, 1)


def _interp(grid: np.ndarray, values: np.ndarray, at: Any) -> Any:
    """Piecewise-linear ``values(grid)`` at the (symbolic) row ``at``, held at the ends (collinear pieces merged,
    constant ones left out: one clamp per change of slope)."""
    slopes = np.diff(values) / np.diff(grid)
    keep = [0] + [k for k in range(1, slopes.size) if not np.isclose(slopes[k], slopes[k - 1], rtol=1e-9, atol=1e-12)]
    ends = keep[1:] + [slopes.size]
    out = values[0] + 0.0 * at
    for k, stop in zip(keep, ends):
        if slopes[k] != 0.0:
            out = out + slopes[k] * (ca.fmin(ca.fmax(at, grid[k]), grid[stop]) - grid[k])
    return out


def _cross(a: Any, B: Any) -> Any:
    """``a × B[:, j]`` for every column (a: 3 x 1)."""
    return ca.vertcat(a[1] * B[2, :] - a[2] * B[1, :], a[2] * B[0, :] - a[0] * B[2, :],
                      a[0] * B[1, :] - a[1] * B[0, :])


def _switch(text: str, key: str, source) -> int:
    value = str(text).strip().strip("\"'").lower()
    if value in _TRUE:
        return 1
    if value in ("false", "f", ".false."):
        return 0
    try:
        return int(float(value))
    except ValueError:
        raise ParameterError(f"{source}: {key} must be an integer switch; got {text!r}.") from None
