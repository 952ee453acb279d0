"""Sector-averaged blade inflow (AeroDyn 15's ``SectAvg = True``), for the blade-element rotor.

AeroDyn v5.0.0 (AeroDyn.f90 ``SetSectAvgInflow``, called from ``SetInputs`` before ``SetInputsForBEMT``;
inputs ``SectAvgWeighting``, ``SectAvgNPoints``, ``SectAvgPsiBwd``, ``SectAvgPsiFwd`` read in AeroDyn_IO.f90 with
the defaults 1, 5, −60°, 60°), written here from its equations. For every blade node ``A`` (AeroDyn's node: the
aerodynamic centre, at its displaced position) and the hub ``H`` with its x axis ``x̂`` (the shaft axis as the hub
turns):

- split ``r = A − H`` into ``r_∥ = (r·x̂) x̂`` and ``r_⊥ = r − r_∥``; with ``e_r = r_⊥/|r_⊥|`` and ``e_t = x̂ × e_r``
  (the direction the rotor turns about ``x̂``), the sector's points are
  ``P_i = H + r_∥ + |r_⊥| (cos ψ_i e_r + sin ψ_i e_t)``, ``ψ_i = ψ_bwd + (i − 1)(ψ_fwd − ψ_bwd)/(N − 1)``,
  ``i = 1 … N``: ``N`` points on the node's circle about the shaft, evenly spread from ``ψ_bwd`` behind the blade
  to ``ψ_fwd`` ahead of it (both ends included; a node on the axis keeps ``N`` copies of itself);
- the undisturbed wind is sampled at the ``P_i`` at the current time and averaged with uniform weights ``1/N``
  (``SectAvgWeighting = 1``, the only weighting AeroDyn v5 has);
- the tower's disturbance (``TwrPotent``, ``TwrShadow``), if any, is added to the average at the node itself
  (AeroDyn's "option 2": disturbed after averaging);
- the average replaces the node's wind: the relative velocity is the average minus the node's velocity, projected
  on the annulus axes as without it. (AeroDyn's ``Skew_Mod = −1`` projection of the node wind on the disk normal is
  not applied to the average; mbsym refuses that mode anyway.)

The rate of the averaged wind along the node's motion (DBEMT's and UA's wind rate, :meth:`velocities`) moves every
sector point rigidly with the node about the shaft: ``v_i = v_H + R_x̂(ψ_i)(v_A − v_H)``.

The rotor-effective rung cannot take it: its wind is one hub-height speed, uniform over the disk, and it has no
blade nodes whose sectors could sample a field (:mod:`mbsym.wind.deck.aero_audit` refuses it there).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ParameterError

__all__ = ["SectorAverage"]

_TRUE = ("true", "t", ".true.")
#: AeroDyn v5's defaults (AeroDyn_IO.f90 ParseVarWDefault): weighting, points per sector, backward and forward [deg].
DEFAULTS = {"SectAvgWeighting": 1, "SectAvgNPoints": 5, "SectAvgPsiBwd": -60.0, "SectAvgPsiFwd": 60.0}


@dataclass(frozen=True)
class SectorAverage:
    """AeroDyn's sector average of the wind over each blade node (module docstring).

    Attributes
    ----------
    n_points : int
        ``SectAvgNPoints``: points per sector, ≥ 2 (AeroDyn refuses fewer than 2: its spacing divides by N − 1).
    psi_backward, psi_forward : float
        ``SectAvgPsiBwd`` ≤ 0 < ``SectAvgPsiFwd``: where the sector starts and ends, relative to the blade, in the
        direction the rotor turns [rad].
    """

    n_points: int = 5
    psi_backward: float = math.radians(-60.0)
    psi_forward: float = math.radians(60.0)

    def __post_init__(self) -> None:
        if not isinstance(self.n_points, (int, np.integer)) or self.n_points < 2:
            raise ParameterError(f"SectorAverage.n_points (SectAvgNPoints) must be an integer >= 2; got "
                                 f"{self.n_points!r}.")
        if not (self.psi_backward <= 0.0 <= self.psi_forward and self.psi_forward > self.psi_backward):
            raise ParameterError(f"SectorAverage needs psi_backward <= 0 <= psi_forward, psi_forward > psi_backward "
                                 f"(SectAvgPsiBwd, SectAvgPsiFwd); got {self.psi_backward!r}, {self.psi_forward!r} "
                                 "rad.")

    @classmethod
    def from_aerodyn(cls, aerodyn) -> "SectorAverage | None":
        """The sector average of an AeroDyn input (``default`` values as AeroDyn's), or None when ``SectAvg``
        is off or absent.

        Raises
        ------
        ParameterError
            A weighting other than 1 (uniform), fewer than 2 points, or a sector AeroDyn refuses.
        """
        extra = dict(aerodyn.extra or {})
        if str(extra.get("SectAvg", "False")).strip().strip("\"'").lower() not in _TRUE:
            return None
        values = {}
        for key, default in DEFAULTS.items():
            text = str(extra.get(key, "default")).strip().strip("\"'")
            try:
                values[key] = default if text.lower() == "default" else float(text)
            except ValueError:
                raise ParameterError(f"{aerodyn.source}: {key} must be a number or 'default'; got {text!r}.") from None
        if values["SectAvgWeighting"] != 1:
            raise ParameterError(f"{aerodyn.source}: SectAvgWeighting = {values['SectAvgWeighting']:g}; AeroDyn v5 "
                                 "has only the uniform weighting (1).")
        n = values["SectAvgNPoints"]
        if n != int(n):
            raise ParameterError(f"{aerodyn.source}: SectAvgNPoints must be an integer; got {n:g}.")
        return cls(int(n), math.radians(values["SectAvgPsiBwd"]), math.radians(values["SectAvgPsiFwd"]))

    def angles(self) -> np.ndarray:
        """The sector's azimuth offsets ``ψ_i`` [rad], backward to forward."""
        return np.linspace(self.psi_backward, self.psi_forward, self.n_points)

    def _polar(self, nodes: Any, hub: Any, axis: Any) -> tuple[Any, Any, Any, Any]:
        n = nodes.size2()
        x = ca.repmat(axis, 1, n)
        r = nodes - ca.repmat(hub, 1, n)
        along = x * ca.repmat(ca.sum1(x * r), 3, 1)
        perp = r - along
        radius = ca.sqrt(ca.sum1(perp**2) + 1e-24)
        e_r = perp / ca.repmat(radius, 3, 1)
        e_t = ca.vertcat(x[1, :] * e_r[2, :] - x[2, :] * e_r[1, :], x[2, :] * e_r[0, :] - x[0, :] * e_r[2, :],
                         x[0, :] * e_r[1, :] - x[1, :] * e_r[0, :])
        return along, radius, e_r, e_t

    def points(self, nodes: Any, hub: Any, axis: Any) -> Any:
        """The sector points of every node (module docstring), ground axes [m].

        Parameters
        ----------
        nodes : SX or DM (3, N)
            The blade nodes (aerodynamic centres) [m].
        hub : SX or DM (3, 1)
            The hub centre [m].
        axis : SX or DM (3, 1)
            The hub's unit x axis.

        Returns
        -------
        SX or DM (3, N·M)
            Point ``i`` of node ``j`` in column ``i·N + j`` (sector by sector: :meth:`average` undoes it).
        """
        along, radius, e_r, e_t = self._polar(nodes, hub, axis)
        n = nodes.size2()
        base = ca.repmat(hub, 1, n) + along
        rho = ca.repmat(radius, 3, 1)
        return ca.horzcat(*[base + rho * (math.cos(p) * e_r + math.sin(p) * e_t) for p in self.angles()])

    def velocities(self, nodes: Any, node_velocities: Any, hub: Any, hub_velocity: Any, axis: Any) -> Any:
        """The sector points' velocities when they turn rigidly with their node about the hub axis,
        ``v_H + R_x̂(ψ_i)(v_A − v_H)`` [m/s], columns as :meth:`points`."""
        along, _, e_r, e_t = self._polar(nodes, hub, axis)
        n = nodes.size2()
        x = ca.repmat(axis, 1, n)
        rel = node_velocities - ca.repmat(hub_velocity, 1, n)
        vx, vr, vt = ca.sum1(rel * x), ca.sum1(rel * e_r), ca.sum1(rel * e_t)
        out = []
        for p in self.angles():
            c, s = math.cos(p), math.sin(p)
            out.append(ca.repmat(hub_velocity, 1, n) + x * ca.repmat(vx, 3, 1)
                       + e_r * ca.repmat(c * vr - s * vt, 3, 1) + e_t * ca.repmat(s * vr + c * vt, 3, 1))
        return ca.horzcat(*out)

    def average(self, values: Any) -> Any:
        """The uniform average over each node's sector of ``values`` (3, N·M) laid out as :meth:`points`."""
        m = self.n_points
        n = values.size2() // m
        return sum(values[:, i * n:(i + 1) * n] for i in range(m)) / m
