"""Derivatives of a linear model with respect to named parameters.

:func:`sensitivities` differentiates the Functions of :func:`mbsym.linear.linearize`
(automatic differentiation) and returns a :class:`Sensitivity`. Both names are
re-exported by :mod:`mbsym.linear`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from ..equations import EquationsOfMotion
from ..exceptions import DimensionError
from ._cache import cached
from .fd import fd_rhs
from .functions import jacobian_function, linear_function
from .linearize import linearize, resolve_steps
from .model import LinearModel
from .target import Target

__all__ = ["Sensitivity", "sensitivities"]


@dataclass(frozen=True)
class Sensitivity:
    """Derivatives of a linear model with respect to named parameters.

    Attributes
    ----------
    parameters : tuple of str
        The parameters, in the order of the first axis of every array.
    linear : LinearModel
        The model at the nominal parameters.
    dM, dC, dK : ndarray (n_s, n_q, n_q); dQ : (n_s, n_q, n_u); dA : (n_s, n_x, n_x); dB : (n_s, n_x, n_u)
    modes : list of Mode
        The nominal modes (:meth:`LinearModel.modes`).
    dfreq : ndarray (n_s, n_modes)
        ∂(natural frequency [Hz]) / ∂parameter, per mode (0 for rigid-body modes).
    dzeta : ndarray (n_s, n_modes)
        ∂(damping ratio) / ∂parameter.
    """

    parameters: tuple[str, ...]
    linear: LinearModel
    dM: np.ndarray
    dC: np.ndarray
    dK: np.ndarray
    dQ: np.ndarray
    dA: np.ndarray
    dB: np.ndarray
    modes: list
    dfreq: np.ndarray
    dzeta: np.ndarray

    def of(self, parameter: str) -> dict[str, np.ndarray]:
        """All derivatives with respect to one parameter, by name (``"M"``, ``"A"``, ``"freq"`` …)."""
        if parameter not in self.parameters:
            raise KeyError(f"no sensitivity for {parameter!r}; computed for {list(self.parameters)}.")
        i = self.parameters.index(parameter)
        return {"M": self.dM[i], "C": self.dC[i], "K": self.dK[i], "Q": self.dQ[i], "A": self.dA[i],
                "B": self.dB[i], "freq": self.dfreq[i], "zeta": self.dzeta[i]}


def _sensitivity_function(eom: EquationsOfMotion, fd: bool) -> ca.Function:
    """``(q, qd, qdd, u, p, h) -> ∂vec(M, C, K, Q)/∂p`` at qdd, ∂vec(A, B)/∂p (and ∂vec(A_fd)/∂p)."""
    key = "sensitivity_fd" if fd else "sensitivity"
    return cached(eom, key, lambda: _build_sensitivity_function(eom, fd, key))


def _build_sensitivity_function(eom: EquationsOfMotion, fd: bool, name: str) -> ca.Function:
    n, nu = eom.n_q, eom.n_u
    q, qd, qdd, u, p, h = (ca.MX.sym(s, k) for s, k in (("q", n), ("qd", n), ("qdd", n), ("u", nu),
                                                          ("p", eom.n_p), ("h", 2 * n)))
    mats = list(jacobian_function(eom)(q, qd, qdd, u, p)) + list(linear_function(eom)(q, qd, u, p)[4:6])
    if fd:
        mats.append(fd_rhs(eom)(ca.vertcat(q, qd), u, p, h))
    outs = [ca.densify(ca.jacobian(ca.vec(m), p)) for m in mats]
    return ca.Function(f"{eom.name}_{name}", [q, qd, qdd, u, p, h], outs)


def sensitivities(model, parameters: Sequence[str] | str, q0=None, qd0=None, u0=None,
                  p: Mapping[str, float] | None = None, *, qdd0=None, method: str = "exact",
                  steps=None) -> Sensitivity:
    """∂M, ∂C, ∂K, ∂Q, ∂A, ∂B and ∂(frequency), ∂(damping) with respect to named parameters.

    By automatic differentiation of the same Functions :func:`linearize` uses (with
    ``method="fd"``/``"elastodyn-fd"``: the exact derivative of the finite-difference A).
    Arguments as for :func:`linearize`; ``parameters`` names model parameters, e.g.
    ``["tower_stiffness_scale", "nacelle_mass"]``. Mode sensitivities use
    ∂λ = wᴴ ∂A v / (wᴴ v) with the left and right eigenvectors of A.

    Examples
    --------
    >>> import mbsym as mb
    >>> from mbsym.linear import sensitivities
    >>> sys = mb.System()
    >>> x = sys.coordinates("x")
    >>> m, k = sys.parameters("m k", values={"m": 2.0, "k": 8.0})
    >>> sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("b", m), axis=[1, 0, 0], coordinate=x))
    >>> sys.add_spring(x, k)
    >>> s = sensitivities(sys.equations(), ["k"], [0.0])
    >>> float(s.of("k")["K"][0, 0]), round(float(s.of("k")["freq"][-1]), 5)   # 1, 1/(4π sqrt(k m))
    (1.0, 0.01989)
    """
    from ..modal import mode_sensitivities

    target = Target(model)
    eom, n = target.eom, target.eom.n_q
    names = [parameters] if isinstance(parameters, str) else list(parameters)
    unknown = [s for s in names if s not in eom.parameters]
    if unknown or not names:
        raise DimensionError(f"unknown parameters {unknown or '(none given)'}; this model's parameters are "
                             f"{list(eom.parameters)}.")
    lin = linearize(model, q0, qd0, u0, p, qdd0=qdd0, method=method, steps=steps)
    op = lin.operating_point
    pp = eom.parameter_vector(op["p"])
    h = resolve_steps(target, method, steps)
    qdd = np.zeros(n) if qdd0 is None or isinstance(qdd0, str) else op["qdd"]
    jac = [np.array(j) for j in _sensitivity_function(eom, h is not None)(op["q"], op["qd"], qdd, op["u"], pp,
                                                                            np.ones(2 * n) if h is None else h)]
    cols = [eom.parameters.index(s) for s in names]
    shapes = [(n, n), (n, n), (n, n), (n, eom.n_u), (2 * n, 2 * n), (2 * n, eom.n_u), (2 * n, 2 * n)]
    d = [np.stack([j[:, c].reshape(s, order="F") for c in cols]) for j, s in zip(jac, shapes)]
    dM, dC, dK, dQ, dA, dB = d[:6]
    if isinstance(qdd0, str):                 # exact K = -M A21, Q = M B2 (product rule)
        A21 = -np.linalg.solve(lin.M, lin.K)
        dK = -(dM @ A21 + lin.M @ dA[:, n:, :n])
        dQ = dM @ lin.B[n:] + lin.M @ dB[:, n:]
    if h is not None:
        dA = d[6]                             # the derivative of the finite-difference A
    modes = lin.modes()
    dfreq, dzeta = mode_sensitivities(lin.A, dA, modes)
    return Sensitivity(tuple(names), lin, dM, dC, dK, dQ, dA, dB, modes, dfreq, dzeta)
