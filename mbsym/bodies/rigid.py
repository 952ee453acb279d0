"""Rigid bodies: mass, centre of mass and inertia tensor."""

from __future__ import annotations

import casadi as ca
import numpy as np

from ..exceptions import DimensionError
from ..kinematics import _scalar, as_matrix3, as_vector3
from .base import Body

__all__ = ["RigidBody"]


class RigidBody(Body):
    """A rigid body.

    Parameters
    ----------
    name : str
        Unique name of the body in its system.
    mass : float or SX
        Mass [kg]; a number or an expression of the system's parameters.
    com : sequence of 3, optional
        Centre of mass in the body frame, relative to the body origin (the
        joint frame that places the body) [m]. Default: the origin.
    inertia : optional
        Inertia tensor about the centre of mass in body axes [kg m^2]: a 3x3
        array, 3 principal values ``(Jxx, Jyy, Jzz)``, or 6 values
        ``(Jxx, Jyy, Jzz, Jxy, Jyz, Jxz)``. Default: zero (a point mass).
    lumped_inertia : bool, optional, keyword-only
        ``True`` for an *equivalent* inertia that is not one rigid body's, e.g. a geared
        generator's inertia times the gear ratio squared added about a rotor's shaft: the
        triangle inequality is then not checked (symmetry and positive semi-definiteness are).

    Raises
    ------
    MassPropertyError
        A negative mass, or an inertia that is not symmetric positive semi-definite or whose
        principal moments violate the triangle inequality (an inertia about one axis only is
        accepted). Expressions of parameters are checked when values are bound
        (:mod:`mbsym.mass_properties`).

    Examples
    --------
    >>> import mbsym as mb
    >>> b = mb.RigidBody("nacelle", mass=2.4e5, com=[1.9, 0, 1.75], inertia=[0, 1.01e6, 0])
    >>> b.name
    'nacelle'
    """

    def __init__(self, name: str, mass, com=(0.0, 0.0, 0.0), inertia=None, *, lumped_inertia: bool = False) -> None:
        super().__init__(name)
        if not isinstance(lumped_inertia, bool):
            from ..exceptions import ArgumentTypeError

            raise ArgumentTypeError(f"lumped_inertia must be True or False; got {lumped_inertia!r}.")
        self.lumped_inertia = lumped_inertia
        self._mass = _scalar(mass, f"mass of body {name!r}")
        self._com = as_vector3(com, f"com of body {name!r}")
        self._inertia = _inertia_matrix(inertia, name)
        self._check_numeric_parts()

    @property
    def mass(self) -> ca.SX:
        """Mass [kg] (SX scalar)."""
        return self._mass

    @property
    def com(self) -> ca.SX:
        """Centre of mass in body coordinates [m] (3x1 SX)."""
        return self._com

    @property
    def inertia(self) -> ca.SX:
        """Inertia tensor about the centre of mass, body axes [kg m^2] (3x3 SX)."""
        return self._inertia

    def symbolic_values(self) -> list[ca.SX]:
        return [self._mass, self._com, self._inertia]

    def _check_numeric_parts(self) -> None:
        """Refuse numeric mass properties no rigid body has (symbolic ones: when parameters are bound)."""
        from ..mass_properties import check_rigid_body

        mass = float(ca.evalf(self._mass)) if self._mass.is_constant() else 0.0
        inertia = np.array(ca.evalf(self._inertia)) if self._inertia.is_constant() else np.zeros((3, 3))
        check_rigid_body(mass, inertia, self.name, triangle=not self.lumped_inertia)


def _inertia_matrix(inertia, name: str) -> ca.SX:
    what = f"inertia of body {name!r}"
    if inertia is None:
        return ca.SX.zeros(3, 3)
    if isinstance(inertia, (ca.SX, ca.DM)) and ca.SX(inertia).shape == (3, 3):
        return as_matrix3(inertia, what)
    try:
        n = len(inertia)
    except TypeError as exc:
        raise DimensionError(f"{what} must be a 3x3 array, 3 or 6 values; got {inertia!r}.") from exc
    if n == 3 and all(not hasattr(e, "__len__") or isinstance(e, (ca.SX, ca.DM)) for e in inertia):
        jxx, jyy, jzz = (_scalar(e, what) for e in inertia)
        return ca.diag(ca.vertcat(jxx, jyy, jzz))
    if n == 6:
        jxx, jyy, jzz, jxy, jyz, jxz = (_scalar(e, what) for e in inertia)
        return ca.vertcat(
            ca.horzcat(jxx, jxy, jxz), ca.horzcat(jxy, jyy, jyz), ca.horzcat(jxz, jyz, jzz)
        )
    if n == 3:
        return as_matrix3(inertia, what)
    raise DimensionError(
        f"{what} has {n} entries; expected a 3x3 array, 3 principal values or "
        "6 values (Jxx, Jyy, Jzz, Jxy, Jyz, Jxz)."
    )
