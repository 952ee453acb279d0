"""The tower's disturbance of the blade inflow in the rotor-effective surfaces: the steady BEM sees it at every azimuth.

AeroDyn's ``TwrPotent`` and ``TwrShadow`` change the flow at each blade node as the blade passes the tower
(:mod:`mbsym.wind.aero.tower`); the blade-element rotor carries that 3P. The rotor-effective rung holds the rotor's
loads averaged over a revolution (its performance surfaces, :mod:`mbsym.wind.aero.surfaces`), so its part of the
tower's influence is the **azimuth average** of the loads with the disturbed inflow: this module gives the steady
BEM (:func:`mbsym.wind.aero.bem.solve_bem`) the change of each node's normal and tangential velocity at each
azimuth, and the BEM solves every azimuth with it, as AeroDyn's BEMT solves the disturbed inflow.

Geometry (ElastoDyn's, undeflected; ``t`` the shaft tilt ``ShftTilt``): the tower is the vertical line of
AeroDyn's tower nodes through the yaw axis; the shaft's downwind axis is ``c = (cos t, 0, sin t)`` (x downwind, z
up) and the rotor apex sits at ``OverHang c`` above the tower top by ``Twr2Shft``, so at the hub height
``TowerHt + Twr2Shft + OverHang sin t`` (ElastoDyn's). The blade at azimuth ψ points along
``e_r = cos ψ e₀ + sin ψ (c × e₀)`` and moves along ``e_t = c × e_r`` (rotation about ``c`` by the right-hand
rule, clockwise seen from upwind), ``e₀`` the in-plane part of the horizontal wind (up for a shaft tilted with its
upwind end up: the BEM's ψ = 0, the skewed disk's downwind side). A node at ``(p_r, p_t, p_x)`` in the BEM's
rotating axes (precone, prebend and sweep included) sits at ``apex + p_r e_r + p_t e_t + p_x c``. The wind is
horizontal with 1 m/s along the shaft (the BEM's unit); the disturbance ``Δ`` is linear in the wind speed, so
the surfaces stay functions of tip-speed ratio and pitch alone. The node's velocities change by

    ΔV_x = n · Δ,   ΔV_y = −e_t · Δ,

``n = cos(cone) c − sin(cone) e_r`` its normal (cone = precone + the node's curve angle) and ``V_y`` counted
against the motion, as the BEM counts them.

What the average leaves out: the 3P itself (the blade-element rung has it), and the change of the blade-to-tower
clearance with the tower's deflection, the platform's pitch and the rotor's yaw (a rigid rotation of the whole
turbine keeps the clearance; a tower-top deflection of 1 m moves it by ~5 % of a 20 m clearance, and the average
changes with its square). For an upwind rotor the potential flow's average nearly vanishes: across a line in front
of the cylinder ``∫ (ȳ² − x̄²)/(x̄² + ȳ²)² dȳ = 0``, so only the loads' nonlinearity and the varying clearance
along the span remain (on the IEA 15 MW, tests/wind/aero/test_tower_average.py). A downwind rotor's shadow is a
first-order deficit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ParameterError

__all__ = ["RotorPlacement", "tower_inflow_change", "TOWER_AZIMUTHS"]

#: Azimuths of the averaged BEM when the tower disturbs the inflow: 10° apart (the potential flow's dip spans
#: 20-40° of a revolution on the IEA 15 MW and NREL 5 MW; 36 and 144 azimuths give thrust and torque
#: coefficients within 1e-5 of each other there, tests/wind/aero/test_tower_average.py).
TOWER_AZIMUTHS = 36


@dataclass(frozen=True)
class RotorPlacement:
    """Where the rotor sits relative to the tower (ElastoDyn's undeflected geometry).

    Attributes
    ----------
    overhang : float
        ``OverHang``: yaw axis to rotor apex along the shaft [m] (negative upwind).
    apex_height : float
        Height of the rotor apex above the tower's datum, ``TowerHt + Twr2Shft + OverHang sin(ShftTilt)`` [m]
        (the hub height: ElastoDyn's; the same datum as AeroDyn's ``TwrElev``).
    shaft_tilt : float
        ``ShftTilt`` [rad] (negative: the upwind end up).
    """

    overhang: float
    apex_height: float
    shaft_tilt: float

    def __post_init__(self) -> None:
        for name in ("overhang", "apex_height", "shaft_tilt"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise ParameterError(f"RotorPlacement.{name} must be a finite number; got {value!r}.")
        if not abs(self.shaft_tilt) < math.radians(60.0):
            raise ParameterError(f"RotorPlacement.shaft_tilt must be within ±60 deg [rad]; got {self.shaft_tilt!r}.")

    @classmethod
    def from_elastodyn(cls, params) -> "RotorPlacement":
        """From :func:`~mbsym.wind.deck.openfast.read_openfast`'s parameters (``overhang``, ``hub_height``,
        ``shaft_tilt``)."""
        return cls(overhang=float(params.overhang), apex_height=float(params.hub_height),
                   shaft_tilt=float(params.shaft_tilt))

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        """The shaft's downwind axis ``c`` and the BEM's ψ = 0 direction ``e₀`` (module docstring), ground axes."""
        t = self.shaft_tilt
        c = np.array([math.cos(t), 0.0, math.sin(t)])
        up = np.array([-math.sin(t), 0.0, math.cos(t)])
        return c, (-up if t > 0 else up)

    def apex(self) -> np.ndarray:
        """The rotor apex, ground axes with the tower's axis at x = y = 0 [m]."""
        return np.array([self.overhang * math.cos(self.shaft_tilt), 0.0, self.apex_height])


def azimuths(n: int) -> np.ndarray:
    """The BEM's azimuths ψ_k = 2π (k + ½)/n [rad] (those of :func:`mbsym.wind.aero.bem.solve_bem`)."""
    return 2.0 * math.pi * (np.arange(n) + 0.5) / n


def tower_inflow_change(geometry: dict, cone: np.ndarray, placement: RotorPlacement, tower,
                        n_azimuth: int = TOWER_AZIMUTHS) -> tuple[np.ndarray, np.ndarray]:
    """The change of each node's velocities by the tower, for 1 m/s of wind along the shaft (module docstring).

    Parameters
    ----------
    geometry : dict
        The BEM rotor's geometry (``pos``: (n, 3) node positions in the rotating axes ``e_r, e_t, c`` [m]).
    cone : ndarray (n,)
        Precone plus each node's curve angle [rad].
    placement : RotorPlacement
    tower : TowerAero
        With ``disturbs_inflow``.
    n_azimuth : int, optional
        Azimuths (:data:`TOWER_AZIMUTHS`).

    Returns
    -------
    dvx, dvy : ndarray (n_azimuth, n)
        Added to the BEM's ``V_x`` and ``V_y`` [m/s per m/s of wind along the shaft].
    """
    if not getattr(tower, "disturbs_inflow", False):
        raise ParameterError("tower_inflow_change needs a TowerAero whose potential flow or shadow is on "
                             "(TwrPotent or TwrShadow).")
    if not (isinstance(n_azimuth, int) and n_azimuth >= 4):
        raise ParameterError(f"n_azimuth must be an integer >= 4; got {n_azimuth!r}.")
    c, e0 = placement.axes()
    side = np.cross(c, e0)
    psi = azimuths(n_azimuth)[:, None, None]
    e_r = np.cos(psi) * e0 + np.sin(psi) * side                              # (n_az, 1, 3)
    e_t = np.cross(c, e_r)
    pos = geometry["pos"]
    points = placement.apex() + pos[:, 0, None] * e_r + pos[:, 1, None] * e_t + pos[:, 2, None] * c
    skew = abs(placement.shaft_tilt)
    wind = c + math.tan(skew) * e0                                            # horizontal, 1 m/s along c
    flat = points.reshape(-1, 3)
    start = ca.DM([0.0, 0.0, float(tower.elevation[0])])
    end = ca.DM([0.0, 0.0, float(tower.elevation[-1])])
    delta = np.asarray(tower.disturbance(ca.DM(flat.T), ca.DM(np.tile(wind, (flat.shape[0], 1)).T), start, end))
    delta = delta.T.reshape(points.shape)
    normal = np.cos(cone)[:, None] * c - np.sin(cone)[:, None] * e_r
    return np.sum(normal * delta, axis=-1), -np.sum(e_t * delta, axis=-1)
