"""Discrete-time maps of first-order dynamics: RK4 with sub-steps, Radau IIA collocation.

One sample of length ``dt`` (inputs held constant, zero-order hold) becomes a map

    x_next = F(x, v, u, p),        0 = G(x, v, u, p)

where ``v`` are the method's own variables: none for RK4 (``G`` is empty), the
collocation states of every sub-step for Radau collocation (degree 3, order 5,
L-stable). In direct collocation ``v`` are decision variables of the optimal
control problem and ``G`` equality constraints of the same stage, so the OCP keeps
its stage structure.

The maps are built in SX when the model's right-hand side can be expanded to SX
(every model derived by :class:`mbsym.System` up to 8 degrees of freedom), else in
MX (a right-hand side with a numeric linear solve).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ..exceptions import ControlDefinitionError

__all__ = ["Discretization", "discretize", "METHODS", "symbolic_function", "radau_coefficients"]

#: Discretization methods by name.
METHODS = ("rk4", "collocation")


def symbolic_function(f: ca.Function) -> tuple[ca.Function, type]:
    """``f`` as an SX Function when it expands, else ``f`` itself; with the symbol class to call it on."""
    if f.is_a("SXFunction"):
        return f, ca.SX
    try:
        return f.expand(), ca.SX
    except RuntimeError:              # linear solves and other MX-only nodes
        return f, ca.MX


def radau_coefficients(degree: int = 3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Radau IIA collocation: nodes τ (0 first), derivative matrix C and continuity weights D.

    ``C[j, r]`` is the derivative at ``τ_r`` of the Lagrange polynomial of node
    ``j``; ``D[j]`` its value at 1. For Radau nodes the last node is 1, so ``D``
    selects the last collocation state.
    """
    tau = np.concatenate([[0.0], np.asarray(ca.collocation_points(degree, "radau"), dtype=float)])
    n = degree + 1
    C = np.zeros((n, n))
    D = np.zeros(n)
    for j in range(n):
        poly = np.poly1d([1.0])
        for m in range(n):
            if m != j:
                poly *= np.poly1d([1.0, -tau[m]]) / (tau[j] - tau[m])
        D[j] = poly(1.0)
        C[j, :] = np.polyder(poly)(tau)
    return tau, C, D


@dataclass(frozen=True)
class Discretization:
    """A discrete-time map of ``ẋ = f(x, u, p)`` over one sample.

    Attributes
    ----------
    method : str
        ``"rk4"`` or ``"collocation"``.
    dt : float
        Sample time [s].
    substeps : int
        Integration sub-steps per sample.
    n_v : int
        Number of the method's own variables (collocation states).
    step : casadi.Function
        ``(x, v, u, p) -> x_next``.
    equations : casadi.Function
        ``(x, v, u, p) -> G`` (``n_v`` equations, empty for RK4).
    sym : type
        ``casadi.SX`` or ``casadi.MX``: the symbols the maps were built with.
    sensitivity : casadi.Function or None
        RK4 only, when chained: ``(x, u, p) -> (x_next, ∂x_next/∂x, ∂x_next/∂u)`` by
        forward propagation through the RK4 stages with calls to ``rhs`` and its
        Jacobian (MX glue). Its code holds one copy of the rhs Jacobian instead of
        the expanded Jacobian of the whole step (18.7k instead of 144k SX
        instructions for a 7-DOF chain): smaller generated code, shorter builds.
    """

    method: str
    dt: float
    substeps: int
    n_v: int
    step: ca.Function
    equations: ca.Function
    sym: type
    sensitivity: ca.Function | None = None

    def initial_v(self, x: np.ndarray) -> np.ndarray:
        """A guess of the method's variables: every collocation state equal to ``x``."""
        x = np.asarray(x, dtype=float).reshape(-1)
        return np.tile(x, self.n_v // x.size) if self.n_v else np.zeros(0)


#: ``sensitivities="auto"`` chains the RK4 Jacobian when the rhs has more SX instructions than this.
CHAIN_THRESHOLD = 500


def discretize(rhs: ca.Function, dt: float, *, method: str = "rk4", substeps: int = 1,
               degree: int = 3, sensitivities: str = "auto") -> Discretization:
    """Discretize ``rhs (x, u, p) -> xd`` over a sample of ``dt`` seconds.

    Parameters
    ----------
    rhs : casadi.Function
        First-order dynamics ``(x, u, p) -> ẋ``.
    dt : float
        Sample time [s], > 0.
    method : {"rk4", "collocation"}, keyword-only
        Classical Runge-Kutta (explicit), or Radau IIA collocation of ``degree``.
    substeps : int, keyword-only
        Sub-steps per sample (≥ 1).
    degree : int, keyword-only
        Collocation degree (Radau nodes), default 3.
    sensitivities : {"auto", "chained", "inline"}, keyword-only
        RK4: build :attr:`Discretization.sensitivity` (``"chained"``), or let
        automatic differentiation expand the step (``"inline"``); ``"auto"`` chains
        for right-hand sides above :data:`CHAIN_THRESHOLD` instructions or in MX.

    Returns
    -------
    Discretization

    Raises
    ------
    ControlDefinitionError
        Unknown method, non-positive ``dt`` or ``substeps``.

    Examples
    --------
    >>> import casadi as ca
    >>> x, u, p = ca.SX.sym("x"), ca.SX.sym("u"), ca.SX.sym("p", 0)
    >>> d = discretize(ca.Function("f", [x, u, p], [-x]), 0.1)
    >>> round(float(d.step(1.0, [], 0.0, [])), 6)      # exp(-0.1) = 0.904837
    0.904837
    """
    if method not in METHODS:
        raise ControlDefinitionError(f"method must be one of {list(METHODS)}; got {method!r}.")
    if not (isinstance(dt, (int, float, np.floating)) and np.isfinite(dt) and dt > 0):
        raise ControlDefinitionError(f"dt must be a positive number of seconds; got {dt!r}.")
    if not (isinstance(substeps, (int, np.integer)) and substeps >= 1):
        raise ControlDefinitionError(f"substeps must be an integer ≥ 1; got {substeps!r}.")
    f, sym = symbolic_function(rhs)
    nx, nu, np_ = (f.size1_in(i) for i in range(3))
    x, u, p = sym.sym("x", nx), sym.sym("u", nu), sym.sym("p", np_)
    h = float(dt) / substeps
    if method == "rk4":
        v = sym.sym("v", 0)
        xk = x
        for _ in range(substeps):
            xk = _rk4(f, xk, u, p, h)
        eqs = sym(0, 1)
    else:
        v = sym.sym("v", substeps * degree * nx)
        xk, eqs = _collocation(f, x, v, u, p, h, degree, nx, substeps)
    if sensitivities not in ("auto", "chained", "inline"):
        raise ControlDefinitionError(f"sensitivities must be 'auto', 'chained' or 'inline'; got {sensitivities!r}.")
    step = ca.Function("discrete_step", [x, v, u, p], [xk], ["x", "v", "u", "p"], ["x_next"])
    equations = ca.Function("collocation_equations", [x, v, u, p], [eqs], ["x", "v", "u", "p"], ["G"])
    chain = method == "rk4" and (sensitivities == "chained" or (
        sensitivities == "auto" and (sym is ca.MX or f.n_instructions() > CHAIN_THRESHOLD)))
    sens = _rk4_sensitivity(f, h, substeps) if chain else None
    return Discretization(method, float(dt), int(substeps), v.numel(), step, equations, sym, sens)


def _rk4_sensitivity(f: ca.Function, h: float, substeps: int) -> ca.Function:
    """RK4 step and its Jacobian by forward propagation; rhs and rhs Jacobian stay called Functions."""
    nx, nu, np_ = (f.size1_in(i) for i in range(3))
    xs, us, ps = (ca.SX.sym(s, n) for s, n in (("x", nx), ("u", nu), ("p", np_))) if f.is_a("SXFunction") \
        else (ca.MX.sym(s, n) for s, n in (("x", nx), ("u", nu), ("p", np_)))
    fx = f(xs, us, ps)
    jac = ca.Function("rhs_jacobian", [xs, us, ps], [fx, ca.jacobian(fx, xs), ca.jacobian(fx, us)],
                      ["x", "u", "p"], ["f", "fx", "fu"])
    x, u, p = ca.MX.sym("x", nx), ca.MX.sym("u", nu), ca.MX.sym("p", np_)
    X, Sx, Su = x, ca.MX.eye(nx), ca.MX(nx, nu)

    def stage(Xs, Sxs, Sus):
        k, A, B = jac(Xs, u, p)
        return k, ca.mtimes(A, Sxs), ca.mtimes(A, Sus) + B

    for _ in range(substeps):
        k1, a1, b1 = stage(X, Sx, Su)
        k2, a2, b2 = stage(X + h / 2 * k1, Sx + h / 2 * a1, Su + h / 2 * b1)
        k3, a3, b3 = stage(X + h / 2 * k2, Sx + h / 2 * a2, Su + h / 2 * b2)
        k4, a4, b4 = stage(X + h * k3, Sx + h * a3, Su + h * b3)
        X = X + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        Sx = Sx + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
        Su = Su + h / 6 * (b1 + 2 * b2 + 2 * b3 + b4)
    return ca.Function("rk4_sensitivity", [x, u, p], [X, ca.densify(Sx), ca.densify(Su)], ["x", "u", "p"],
                       ["x_next", "dx", "du"])


def _rk4(f: ca.Function, x, u, p, h: float):
    k1 = f(x, u, p)
    k2 = f(x + h / 2 * k1, u, p)
    k3 = f(x + h / 2 * k2, u, p)
    k4 = f(x + h * k3, u, p)
    return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def _collocation(f: ca.Function, x, v, u, p, h: float, degree: int, nx: int, substeps: int):
    """Radau IIA collocation over ``substeps`` intervals; equations scaled to units of ẋ."""
    _, C, _ = radau_coefficients(degree)
    eqs = []
    start = x
    for s in range(substeps):
        z = [start] + [v[(s * degree + r) * nx:(s * degree + r + 1) * nx] for r in range(degree)]
        for r in range(1, degree + 1):
            slope = sum(float(C[j, r]) * z[j] for j in range(degree + 1)) / h
            eqs.append(slope - f(z[r], u, p))
        start = z[degree]                  # Radau: the last node is τ = 1, so D selects it (D = e_d)
    return start, ca.vertcat(*eqs)
