"""Linearized equations of motion (paper Sect. 2.5, Eqs. 24-26).

About an operating point ``(q0, qd0, qdd0, u0)`` the residual ``e = F - M qdd``
gives ``M0 δq̈ + C0 δq̇ + K0 δq = Q0 δu`` with

``M0 = -∂e/∂q̈``, ``C0 = -∂e/∂q̇``, ``K0 = -∂e/∂q``, ``Q0 = ∂e/∂u``,

all from one CasADi Function of the residual's Jacobians (automatic
differentiation, no symbolic inverse). The first-order form uses a numeric
factorization of M0: ``A = [[0, I], [-M0⁻¹K0, -M0⁻¹C0]]``, ``B = [[0], [M0⁻¹Q0]]``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

import casadi as ca
import numpy as np
import scipy.linalg

from .equations import EquationsOfMotion, check_nonsingular

__all__ = ["LinearModel", "linearize", "jacobian_function"]


@dataclass(frozen=True)
class LinearModel:
    """Linear model ``M δq̈ + C δq̇ + K δq = Q δu`` and its first-order form.

    Attributes
    ----------
    M, C, K : ndarray (n_q, n_q)
        Mass, damping and stiffness matrices at the operating point.
    Q : ndarray (n_q, n_u)
        Input matrix.
    A : ndarray (2 n_q, 2 n_q), B : ndarray (2 n_q, n_u)
        First-order state-space matrices for ``x = [q; qd]``.
    states, inputs : tuple of str
        Names of the state and input vectors.
    operating_point : dict
        ``q``, ``qd``, ``qdd``, ``u`` (arrays) and ``p`` (dict by name).
    """

    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    Q: np.ndarray
    A: np.ndarray
    B: np.ndarray
    coordinates: tuple[str, ...]
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    operating_point: dict = field(default_factory=dict)

    def frequencies(self) -> tuple[np.ndarray, np.ndarray]:
        """Natural frequencies [Hz] and damping ratios [-] of the oscillatory modes of A.

        One entry per complex-conjugate pair (and per real eigenvalue), sorted by
        frequency; rigid-body (zero) eigenvalues give frequency 0.
        """
        lam = np.linalg.eigvals(self.A)
        lam = lam[np.imag(lam) >= 0]
        wn = np.abs(lam)
        zeta = np.where(wn > 0, -np.real(lam) / np.where(wn > 0, wn, 1.0), 1.0)
        order = np.argsort(wn)
        return wn[order] / (2 * np.pi), zeta[order]


def jacobian_function(eom: EquationsOfMotion) -> ca.Function:
    """``(q, qd, qdd, u, p) -> (M0, C0, K0, Q0)``: the residual's Jacobians, built once per model."""
    cached = getattr(eom, "_jacobian_function", None)
    if cached is not None:
        return cached
    d = eom.symbolic
    e = d.F - d.M @ d.qdd
    outs = [-ca.jacobian(e, d.qdd), -ca.jacobian(e, d.qd), -ca.jacobian(e, d.q), ca.jacobian(e, d.u)]
    outs = ca.cse(outs)
    f = ca.Function(f"{eom.name}_linearization", [d.q, d.qd, d.qdd, d.u, d.p], outs,
                    ["q", "qd", "qdd", "u", "p"], ["M", "C", "K", "Q"])
    eom._jacobian_function = f     # private cache: the model itself stays unchanged
    return f


def linearize(eom: EquationsOfMotion, q0, qd0=None, u0=None, p: Mapping[str, float] | None = None, *,
              qdd0=None) -> LinearModel:
    """Linearize the equations of motion about an operating point.

    Parameters
    ----------
    eom : EquationsOfMotion
    q0 : sequence of n_q
        Coordinates at the operating point [m, rad].
    qd0, qdd0 : sequence of n_q, optional
        Speeds and accelerations at the operating point (default zero).
    u0 : sequence of n_u or dict, optional
        Inputs at the operating point (default zero).
    p : dict, optional
        Parameter values by name (defaults fill the gaps).

    Returns
    -------
    LinearModel

    Raises
    ------
    SingularMassMatrixError
        If M0 is singular (naming the coordinates involved).

    Examples
    --------
    >>> import mbsym as mb
    >>> sys = mb.System(gravity=[0, 0, -9.81])
    >>> th = sys.coordinates("th")
    >>> sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[0, 0, -1.0]),
    ...                           axis=[0, 1, 0], coordinate=th))
    >>> lin = mb.linearize(sys.equations(), [0.0])
    >>> round(float(lin.K[0, 0]), 2)    # m g l
    9.81
    """
    n = eom.n_q
    q = eom._vec(q0, n, "q0", eom.coordinates)
    qd = np.zeros(n) if qd0 is None else eom._vec(qd0, n, "qd0", eom.speeds)
    qdd = np.zeros(n) if qdd0 is None else eom._vec(qdd0, n, "qdd0", eom.coordinates)
    if u0 is None and eom.n_u:
        u0 = np.zeros(eom.n_u)
    uu, pp = eom._args(u0, p)
    M, C, K, Q = (np.array(m) for m in jacobian_function(eom)(q, qd, qdd, uu, pp))
    check_nonsingular(M, eom.coordinates)
    lu = scipy.linalg.lu_factor(M)
    Z, I = np.zeros((n, n)), np.eye(n)
    A = np.block([[Z, I], [-scipy.linalg.lu_solve(lu, K), -scipy.linalg.lu_solve(lu, C)]])
    B = np.vstack([np.zeros((n, eom.n_u)), scipy.linalg.lu_solve(lu, Q) if eom.n_u else np.zeros((n, 0))])
    op = {"q": q, "qd": qd, "qdd": qdd, "u": uu, "p": dict(zip(eom.parameters, pp.tolist()))}
    return LinearModel(M, C, K, Q.reshape(n, eom.n_u), A, B.reshape(2 * n, eom.n_u),
                       eom.coordinates, eom.states, eom.inputs, op)
