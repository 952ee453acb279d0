"""Physical checks of mass properties: rigid bodies, bound parameter values, the mass matrix.

A rigid body's mass is never negative, and its inertia tensor about the centre of mass is
symmetric positive semi-definite with principal moments that satisfy the triangle
inequality ``J1 <= J2 + J3`` (each moment is an integral of a sum of two squared distances).
Models often use two idealizations, which are accepted:

- a **massless** body (mass 0), e.g. a frame between two joints;
- an inertia about **one axis only** (two principal moments zero), e.g. ElastoDyn's hub and
  generator inertias about the shaft or the nacelle's yaw inertia. It violates the triangle
  inequality, but deliberately;
- an **equivalent** inertia that is not one body's (``RigidBody(..., lumped_inertia=True)``),
  e.g. a generator's inertia times the gear ratio squared lumped into a rotor: the triangle
  inequality is not checked.

The triangle inequality is checked within :data:`TRIANGLE_TOLERANCE` (1 %) of the largest moment.

Numeric properties are checked when a :class:`~mbsym.RigidBody` is built; properties that are
expressions of parameters are checked whenever parameter values are bound
(:meth:`~mbsym.EquationsOfMotion.parameter_vector`, used by every numeric call, ``simulate``,
``linearize``, …). :func:`check_mass_matrix` checks that the mass matrix at a state is
positive definite: ``simulate`` calls it at the initial state before integrating.
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca
import numpy as np

from .exceptions import MassPropertyError, SingularMassMatrixError

__all__ = ["rigid_body_problems", "check_rigid_body", "MassPropertyCheck", "check_mass_matrix", "check_nonsingular",
           "indefinite_problem", "RELATIVE_TOLERANCE", "TRIANGLE_TOLERANCE"]

#: Relative tolerance of the checks (to the largest moment or mass-matrix entry) [-].
RELATIVE_TOLERANCE = 1e-9
#: Relative tolerance of the triangle inequality (to the largest principal moment) [-]: flat bodies
#: (rotors, discs) sit on the bound ``J_axial = 2 J_transverse`` and rounded published data cross it
#: slightly (paper Sect. 4.4: 3.86e7 vs 2 x 1.92e7 kg m^2, 0.5 % over).
TRIANGLE_TOLERANCE = 0.01


def rigid_body_problems(mass: float, inertia: np.ndarray, name: str, *, triangle: bool = True) -> list[str]:
    """Why numeric mass properties are not those of a rigid body (empty list if they are).

    Parameters
    ----------
    mass : float
        [kg].
    inertia : ndarray (3, 3)
        About the centre of mass [kg m^2].
    name : str
        Body name, for the messages.
    triangle : bool, keyword-only
        Check the triangle inequality (not for the lumped, equivalent inertias of
        ``RigidBody(..., lumped_inertia=True)``).
    """
    out = []
    if mass < 0:
        out.append(f"body {name!r}: mass is {mass:g} kg; a mass must not be negative (0 is a massless body)")
    J = np.asarray(inertia, dtype=float).reshape(3, 3)
    scale = float(np.max(np.abs(J)))
    if scale == 0.0:
        return out
    tol = RELATIVE_TOLERANCE * scale
    asym = np.abs(J - J.T)
    if np.max(asym) > tol:
        i, j = np.unravel_index(int(np.argmax(asym)), (3, 3))
        out.append(f"body {name!r}: inertia tensor is not symmetric (J[{i},{j}] = {J[i, j]:g} but "
                   f"J[{j},{i}] = {J[j, i]:g} kg m^2); give a symmetric tensor or 6 values (Jxx, Jyy, Jzz, Jxy, Jyz, Jxz)")
        return out
    w = np.linalg.eigvalsh(0.5 * (J + J.T))
    if w[0] < -tol:
        out.append(f"body {name!r}: inertia tensor is not positive semi-definite (principal moments "
                   f"{_fmt(w)} kg m^2); moments of inertia are never negative: check the signs of the products "
                   "of inertia and the diagonal")
    elif (triangle and w[2] > (w[0] + w[1]) + TRIANGLE_TOLERANCE * w[2]
          and not (w[0] <= tol and w[1] <= tol)):
        out.append(f"body {name!r}: principal moments {_fmt(w)} kg m^2 violate the triangle inequality "
                   f"({w[2]:g} > {w[0]:g} + {w[1]:g}); no rigid body has this inertia. Check the values (about "
                   "the centre of mass, body axes); an inertia about one axis only (two moments 0) is accepted")
    return out


def check_rigid_body(mass: float, inertia: np.ndarray, name: str, *, triangle: bool = True) -> None:
    """Raise :class:`~mbsym.exceptions.MassPropertyError` if :func:`rigid_body_problems` finds any."""
    problems = rigid_body_problems(mass, inertia, name, triangle=triangle)
    if problems:
        raise MassPropertyError("; ".join(problems) + ".")


def _fmt(w) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in w) + ")"


class MassPropertyCheck:
    """Checks the rigid bodies whose mass or inertia are expressions of parameters.

    Parameters
    ----------
    bodies : sequence of RigidBody
        The rigid bodies of a derivation (objects with ``name``, ``mass``, ``inertia``,
        ``lumped_inertia``); only those with symbolic properties are kept.
    p : SX
        The parameter vector the expressions depend on.
    parameters : sequence of str
        Parameter names (to name the culprits).
    """

    def __init__(self, bodies: Sequence, p: ca.SX, parameters: Sequence[str]) -> None:
        self._names: list[str] = []
        self._uses: list[list[str]] = []
        self._triangle: list[bool] = []
        exprs = []
        for body in bodies:
            m, J = body.mass, body.inertia
            if m.is_constant() and J.is_constant():
                continue        # checked when the body was built
            self._names.append(body.name)
            self._triangle.append(not body.lumped_inertia)
            self._uses.append(sorted({s.name() for s in ca.symvar(ca.vertcat(m, ca.vec(J)))}))
            exprs += [m, ca.vec(J)]
        self._f = ca.Function("mass_properties", [p], [ca.vertcat(*exprs)]) if exprs else None
        self._last: bytes | None = None

    def __call__(self, p_values: np.ndarray) -> None:
        """Raise :class:`~mbsym.exceptions.MassPropertyError` for unphysical bound values."""
        if self._f is None:
            return
        key = np.asarray(p_values, dtype=float).tobytes()
        if key == self._last:
            return
        v = np.array(self._f(p_values)).reshape(-1, 10)
        if _all_physical(v, np.array(self._triangle)):
            self._last = key
            return
        problems = []
        for name, uses, triangle, row in zip(self._names, self._uses, self._triangle, v):
            found = rigid_body_problems(float(row[0]), row[1:].reshape(3, 3, order="F"), name, triangle=triangle)
            problems += [f"{msg} (from parameters {uses})" for msg in found]
        if problems:
            raise MassPropertyError("parameter values give unphysical mass properties: " + "; ".join(problems)
                                    + ". Check the values passed in p (and the defaults).")
        self._last = key


def _all_physical(v: np.ndarray, triangle: np.ndarray) -> bool:
    """Vectorized screen of rows ``[mass, vec(J)]`` (the common case: every body is physical)."""
    J = v[:, 1:].reshape(-1, 3, 3).transpose(0, 2, 1)
    scale = np.abs(J).max(axis=(1, 2))
    tol = RELATIVE_TOLERANCE * scale
    if np.any(v[:, 0] < 0) or np.any(np.abs(J - J.transpose(0, 2, 1)).max(axis=(1, 2)) > tol):
        return False
    w = np.linalg.eigvalsh(0.5 * (J + J.transpose(0, 2, 1)))
    one_axis = (w[:, 0] <= tol) & (w[:, 1] <= tol)
    tri = (w[:, 2] <= w[:, 0] + w[:, 1] + TRIANGLE_TOLERANCE * w[:, 2]) | one_axis | ~triangle
    return bool(np.all(w[:, 0] >= -tol) and np.all(tri))


def check_mass_matrix(eom, q, u=None, p=None) -> None:
    """Check that the mass matrix at ``q`` is symmetric positive definite.

    Parameters
    ----------
    eom : EquationsOfMotion
    q : array (n_q)
        Coordinates [m, rad].
    u : array (n_u), optional
        Inputs (needed with prescribed coordinates).
    p : array (n_p) or dict, optional
        Parameter values (a vector in ``eom.parameters`` order, or a dict by name).

    Raises
    ------
    MassPropertyError
        If M has a negative eigenvalue (unphysical parameter values, e.g. a negative mass).
    SingularMassMatrixError
        If M is singular (coordinates that move no mass).
    """
    pv = eom.parameter_vector(p) if (p is None or isinstance(p, dict)) else np.asarray(p, dtype=float)
    uu = np.zeros(eom.n_u) if u is None else np.asarray(u, dtype=float).reshape(-1)
    M = eom._mass(np.asarray(q, dtype=float).reshape(-1), uu, pv)
    check_nonsingular(M, eom.coordinates)


def indefinite_problem(M: np.ndarray, names: Sequence[str], rtol: float = RELATIVE_TOLERANCE) -> str | None:
    """Message if the symmetric matrix ``M`` has a clearly negative eigenvalue, else None."""
    w, vecs = np.linalg.eigh(0.5 * (M + M.T))
    scale = max(float(np.max(np.abs(w))), 1e-300)
    bad = np.flatnonzero(w < -rtol * scale)
    if not bad.size:
        return None
    comp = np.abs(vecs[:, bad]).max(axis=1)
    suspects = [names[i] for i in np.flatnonzero(comp > 0.1)]
    return (f"the mass matrix is not positive definite (eigenvalue {w.min():.4g}); the coordinates {suspects} would "
            "accelerate against the applied forces. Some mass or inertia is negative: check the parameter values "
            "(e.g. p={...} overrides) and the bodies' mass properties.")


def check_nonsingular(M: np.ndarray, names, rtol: float = 1e-12) -> None:
    """Raise SingularMassMatrixError naming the coordinates of M's null space, or
    MassPropertyError if M has a clearly negative eigenvalue (not positive definite)."""
    indefinite = indefinite_problem(M, names)
    if indefinite:
        raise MassPropertyError(indefinite)
    w, vecs = np.linalg.eigh(0.5 * (M + M.T))
    scale = max(float(np.max(np.abs(w))), 1e-300)
    bad = np.flatnonzero(w <= rtol * scale)
    if bad.size:
        comp = np.abs(vecs[:, bad]).max(axis=1)
        suspects = [names[i] for i in np.flatnonzero(comp > 0.1)]
        raise SingularMassMatrixError(
            f"the mass matrix is singular at this state (smallest eigenvalue {w.min():.3g}); the null space "
            f"involves coordinates {suspects}. Check that they move some mass or inertia (a massless body "
            "or a zero parameter value?)."
        )
