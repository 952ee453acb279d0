"""The nacelle's drag (AeroDyn 15's ``NacelleDrag = True``).

AeroDyn v5.0.0 (AeroDyn.f90 ``RotCalcNacelleDrag``; inputs of the "Nacelle Properties" section read in
AeroDyn_IO.f90) loads the nacelle with a drag force from three projected areas and drag coefficients in the
nacelle axes (x downwind along the nacelle, y to its left, z up), written here from its equations:

- the flow is the undisturbed wind at the nacelle's reference point (ElastoDyn's ``NacelleMotion``: the yaw
  bearing, the tower top) minus that point's velocity, ``V`` (ground axes); only its horizontal part
  ``V_h = (V_x, V_y)`` enters;
- ``a`` and ``b`` are ``V_h``'s components along and across the horizontal projection of the nacelle's x axis
  (``a = |V_h| cos γ``, ``b = |V_h| sin γ``, ``γ`` the wind's direction relative to the nacelle's yaw), and
  ``s = sin τ`` with ``τ = −atan2(x_z, x_x)`` the nacelle x axis' tilt (``x_x``, ``x_z`` its ground components);
- with ``A_i C_{d,i}`` the products of ``NacArea`` and ``NacCd``, AeroDyn's projected area ``K = A_1 C_{d,1}
  |cos γ| + A_2 C_{d,2} |sin γ| + A_3 C_{d,3} |s|`` and its force magnitude ``½ ρ |V_h|² K``, split as
  ``(|cos γ|, |sin γ|, |s|)`` with the signs of ``cos γ``, ``sin γ``, ``s``: in nacelle axes

      F = ½ ρ |V_h|² K (cos γ, sin γ, s) = ½ ρ K' (a, b, |V_h| s),
      K' = |V_h| K = A_1 C_{d,1} |a| + A_2 C_{d,2} |b| + A_3 C_{d,3} |s| |V_h|;

- the moment about the reference point is ``M = r_AC × F`` with ``r_AC = NacDragAC`` (nacelle axes).

AeroDyn applies ``F`` and ``M`` at the nacelle's reference point (its ``NacelleLoad`` mesh, mapped onto
ElastoDyn's ``NacelleLoads`` at the yaw bearing: FAST_Mapping.f90), and writes them as ``NcFdx … NcMdz``
(nacelle axes) and, with no buoyancy, ``NcFxi … NcMzi`` (ground axes). The vertical wind and the vertical
velocity do not enter (AeroDyn's ``hubHeigthWindSpeed(1:2)``); the force along z comes from the tilt alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ParameterError

__all__ = ["NacelleDrag", "NACELLE_CHANNELS"]

_TRUE = ("true", "t", ".true.")
#: AeroDyn's nacelle-drag channels (v5.0.0 OutListParameters) and units: nacelle axes, then ground axes.
NACELLE_CHANNELS = ("NcFdx", "NcFdy", "NcFdz", "NcMdx", "NcMdy", "NcMdz", "NcFxi", "NcFyi", "NcFzi", "NcMxi",
                    "NcMyi", "NcMzi")


@dataclass(frozen=True, eq=False)
class NacelleDrag:
    """AeroDyn's nacelle drag (module docstring).

    Attributes
    ----------
    area : ndarray (3,)
        ``NacArea``: projected areas normal to the nacelle's x, y, z axes [m²].
    drag_coefficient : ndarray (3,)
        ``NacCd``: their drag coefficients [-].
    center : ndarray (3,)
        ``NacDragAC``: the drag's point of action from the yaw bearing, nacelle axes [m].
    """

    area: np.ndarray
    drag_coefficient: np.ndarray
    center: np.ndarray

    def __post_init__(self) -> None:
        for name in ("area", "drag_coefficient", "center"):
            value = np.array(getattr(self, name), dtype=float).reshape(-1)
            if value.size != 3 or not np.all(np.isfinite(value)):
                raise ParameterError(f"NacelleDrag.{name} must hold 3 finite numbers; got {value.tolist()}.")
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        if np.any(self.area < 0) or np.any(self.drag_coefficient < 0):
            raise ParameterError(f"NacelleDrag: NacArea and NacCd must be >= 0; got {self.area.tolist()}, "
                                 f"{self.drag_coefficient.tolist()}.")

    @classmethod
    def from_aerodyn(cls, aerodyn) -> "NacelleDrag | None":
        """The nacelle drag of an AeroDyn input, or None when ``NacelleDrag`` is off (or absent).

        Raises
        ------
        ParameterError
            ``NacelleDrag = True`` with a missing or malformed ``NacArea``, ``NacCd`` or ``NacDragAC``.
        """
        extra = dict(aerodyn.extra or {})
        if str(extra.get("NacelleDrag", "False")).strip().strip("\"'").lower() not in _TRUE:
            return None
        values = {}
        for key in ("NacArea", "NacCd", "NacDragAC"):
            text = str(extra.get(key, "")).replace(",", " ").split()
            try:
                values[key] = [float(v) for v in text[:3]]
            except ValueError:
                values[key] = []
            if len(values[key]) != 3:
                raise ParameterError(f"{aerodyn.source}: NacelleDrag = True needs {key} as 3 numbers; got "
                                     f"{extra.get(key)!r}.")
        return cls(values["NacArea"], values["NacCd"], values["NacDragAC"])

    def loads(self, flow: Any, R: Any, rho: Any) -> tuple[Any, Any]:
        """The drag force [N] and its moment about the yaw bearing [N m], nacelle axes (module docstring).

        Parameters
        ----------
        flow : SX, MX or DM (3, 1)
            The wind at the yaw bearing minus its velocity, ground axes [m/s].
        R : SX, MX or DM (3, 3)
            The nacelle's orientation (columns: its x, y, z axes in ground axes).
        rho : SX or float
            Air density [kg/m³].
        """
        x = R[:, 0]
        heading = ca.sqrt(x[0] ** 2 + x[1] ** 2)
        a = (flow[0] * x[0] + flow[1] * x[1]) / heading                 # |V_h| cos γ
        b = (x[0] * flow[1] - x[1] * flow[0]) / heading                 # |V_h| sin γ
        speed = ca.sqrt(flow[0] ** 2 + flow[1] ** 2 + 1e-12)            # |V_h|
        s = -x[2] / ca.sqrt(x[0] ** 2 + x[2] ** 2)                      # sin τ, τ = −atan2(x_z, x_x)
        ac = self.area * self.drag_coefficient
        k = ac[0] * ca.fabs(a) + ac[1] * ca.fabs(b) + ac[2] * ca.fabs(s) * speed
        force = 0.5 * rho * k * ca.vertcat(a, b, speed * s)
        c = self.center
        moment = ca.vertcat(c[1] * force[2] - c[2] * force[1], c[2] * force[0] - c[0] * force[2],
                            c[0] * force[1] - c[1] * force[0])
        return force, moment
