"""Platform hydrostatics and HydroDyn's additional loads, as numbers or CasADi expressions.

Hydrostatics (HydroDyn ``WAMIT.f90``, ``WAMIT_CalcOutput``) at the platform reference point
(PRP), for the platform DOFs ``q = (surge, sway, heave, roll, pitch, yaw)`` [m, rad]:

* HydroDyn uses only the heave–roll–pitch block of the WAMIT restoring matrix C (rows and
  columns 3-5, 1-based): ``f_h = −C[3:5, 3:5] q[3:5]`` in the heading frame, plus the constant
  buoyancy of the undisplaced body: ``F_z = ρ g V0``, ``M_x = ρ g V0 (y_COB − y_ref)``,
  ``M_y = −ρ g V0 (x_COB − x_ref)``; the force and the moment are then turned from the heading
  frame to the inertial frame by the yaw angle (a rotation about z by ``q[5]``).
* The rotations are ZYX Euler angles of the platform orientation (HydroDyn's
  ``EulerExtractZYX``): mbsym's platform joint uses the same sequence (R = Rz(Y) Ry(P) Rx(R),
  ElastoDyn v4+/v5), so the platform DOFs enter directly. The restoring is *linear* in those
  angles (HydroDyn has no large-angle hydrostatics for potential-flow bodies; it warns beyond
  its small-angle limit): only the yaw rotation of the load is exact.

**What ElastoDyn's gravity already holds.** The WAMIT ``.hst`` matrix of this deck is
computed with the centre of gravity at the origin (the deck's HydroData README), so it holds
only the water's part: ``C33 = ρ g A_wp``, ``C44, C55 = ρ g (I_wp + V0 z_COB)`` and their
couplings. The weight of every mass (platform ``PtfmMass`` at ``PtfmCMzt``, tower, nacelle,
rotor) and its overturning moment ``−m g z_G θ`` come from ElastoDyn's gravity, which mbsym's
structural model applies. Adding ``−m g z_G`` here would count it twice.

Additional loads (HydroDyn ``HydroDyn.f90``): ``AddF0 − AddCLin q`` in the inertial frame and
``−R AddBLin Rᵀ q̇ − R AddBQuad (|Rᵀq̇| ∘ Rᵀq̇)`` with the damping matrices in body axes (R the
body-to-inertial rotation of the six-vector: the same 3×3 on forces and moments).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import DimensionError, ParameterError
from ._casadi import _in, _out, euler_zyx

__all__ = ["PlatformHydrostatics", "AdditionalLoads"]


def _matrix(value, name: str, shape=(6, 6)) -> np.ndarray:
    arr = np.array(value, dtype=float)
    if arr.shape != shape:
        raise DimensionError(f"{name} has shape {arr.shape}; expected {shape}.")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"All entries of {name} must be finite numbers.")
    arr.setflags(write=False)
    return arr


def _yaw_turn(vector, yaw):
    """Turn a 3-vector from the heading frame to the inertial frame (rotation about z by ``yaw``)."""
    c, s = ca.cos(yaw), ca.sin(yaw)
    return ca.vertcat(c * vector[0] - s * vector[1], s * vector[0] + c * vector[1], vector[2])


@dataclass(frozen=True, eq=False)
class PlatformHydrostatics:
    """HydroDyn's hydrostatic load on a potential-flow platform (see the module docstring).

    Parameters
    ----------
    restoring : (6, 6) array_like
        Dimensional WAMIT restoring matrix C [N/m, N/rad, N m/m, N m/rad] (only its
        heave–roll–pitch block acts, as in HydroDyn).
    water_density, gravity : float
        ρ [kg/m³], g [m/s²].
    displaced_volume : float
        ``PtfmVol0`` V0 [m³], the displaced volume of the undisplaced platform.
    buoyancy_center : (float, float)
        ``(PtfmCOBxt, PtfmCOByt)`` [m].
    reference : (float, float, float)
        ``(PtfmRefxt, PtfmRefyt, PtfmRefzt)`` [m], the WAMIT body reference point.

    Examples
    --------
    >>> import numpy as np
    >>> C = np.zeros((6, 6)); C[2, 2] = 1025 * 9.81 * 100.0   # a 10 m x 10 m waterplane
    >>> hs = PlatformHydrostatics(C, 1025.0, 9.81, 1000.0)
    >>> bool(np.isclose(hs.load(np.array([0, 0, -0.1, 0, 0, 0]))[2], 1025 * 9.81 * (1000.0 + 10.0), rtol=1e-14))
    True
    """

    restoring: np.ndarray
    water_density: float
    gravity: float
    displaced_volume: float
    buoyancy_center: tuple[float, float] = (0.0, 0.0)
    reference: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "restoring", _matrix(self.restoring, "restoring"))
        for name in ("water_density", "gravity", "displaced_volume"):
            value = float(getattr(self, name))
            if not (math.isfinite(value) and value >= 0):
                raise ParameterError(f"{name} must be a finite number >= 0; got {value}.")
            object.__setattr__(self, name, value)

    @property
    def buoyancy(self) -> float:
        """ρ g V0 [N], the buoyancy of the undisplaced platform."""
        return self.water_density * self.gravity * self.displaced_volume

    @property
    def stiffness(self) -> np.ndarray:
        """The 6×6 stiffness HydroDyn applies: C with all but rows/columns heave, roll, pitch zeroed [SI]."""
        out = np.zeros((6, 6))
        out[2:5, 2:5] = self.restoring[2:5, 2:5]
        return out

    @property
    def offset_load(self) -> np.ndarray:
        """The constant part (HydroDyn's ``F_HS_Moment_Offset``): buoyancy and its moment about the reference [N, N m]."""
        b = self.buoyancy
        return np.array([0.0, 0.0, b, b * (self.buoyancy_center[1] - self.reference[1]),
                         -b * (self.buoyancy_center[0] - self.reference[0]), 0.0])

    def load(self, q):
        """Hydrostatic force and moment at the reference point, inertial axes [N, N m].

        Parameters
        ----------
        q : array_like (6,) or casadi SX/MX
            Platform displacement ``(surge, sway, heave, roll, pitch, yaw)`` [m, rad].

        Returns
        -------
        ndarray (6,) or casadi expression
        """
        x = _in(q, 6, "q")
        heading = -ca.mtimes(ca.DM(self.stiffness), x) + ca.DM(self.offset_load)
        out = ca.vertcat(_yaw_turn(heading[0:3], x[5]), _yaw_turn(heading[3:6], x[5]))
        return _out(out, q)


@dataclass(frozen=True, eq=False)
class AdditionalLoads:
    """HydroDyn's ``AddF0``, ``AddCLin``, ``AddBLin``, ``AddBQuad`` (see the module docstring).

    Parameters
    ----------
    force : (6,) array_like
        Preload ``AddF0`` [N, N m], inertial axes.
    stiffness, damping, quadratic_damping : (6, 6) array_like
        ``AddCLin`` (inertial), ``AddBLin`` and ``AddBQuad`` (body axes) [SI].
    """

    force: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    quadratic_damping: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "force", _matrix(np.ravel(self.force), "force", (6,)))
        for name in ("stiffness", "damping", "quadratic_damping"):
            object.__setattr__(self, name, _matrix(getattr(self, name), name))

    def load(self, q, qd):
        """Force and moment at the reference point, inertial axes [N, N m].

        ``qd`` holds the translational velocity and the angular velocity of the platform in
        inertial axes [m/s, rad/s] (HydroDyn's mesh velocities; the operating turbine passes the
        Euler rates' angular velocity, :func:`~._casadi.body_motion`).
        """
        x, v = _in(q, 6, "q"), _in(qd, 6, "qd")
        rot = euler_zyx(x[3:6])
        body = ca.vertcat(ca.mtimes(rot.T, v[0:3]), ca.mtimes(rot.T, v[3:6]))
        damp = ca.mtimes(ca.DM(self.damping), body) + ca.mtimes(ca.DM(self.quadratic_damping), ca.fabs(body) * body)
        out = (ca.DM(self.force) - ca.mtimes(ca.DM(self.stiffness), x)
               - ca.vertcat(ca.mtimes(rot, damp[0:3]), ca.mtimes(rot, damp[3:6])))
        return _out(out, q, qd)
