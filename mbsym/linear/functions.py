"""The CasADi Functions of the linearization: residual Jacobians and the exact first-order A, B.

One ``casadi.cse`` pass over the residual's Jacobians is the only derivation the
linearization pays; everything is built once per model (:func:`._cache.cached`).
"""

from __future__ import annotations

import casadi as ca

from ..equations import SYMBOLIC_SOLVE_MAX_DOF, EquationsOfMotion
from ._cache import cached

__all__ = ["jacobian_function", "linear_function", "residual_parts"]


def residual_parts(eom: EquationsOfMotion) -> dict[str, ca.Function]:
    """The residual's Jacobians from one ``casadi.cse`` pass, the only derivation the linearization pays.

    ``"parts"``: ``(q, qd, u, p) -> (M, C0, K0, Q0, F)`` at zero acceleration;
    ``"inertia"``: ``(q, u, p, a) -> (∂(M a)/∂q, ∂(M a)/∂u)``; ``"jacobians"``:
    ``(q, qd, qdd, u, p) -> (M, C, K, Q)`` at any acceleration, ``K = K0 + ∂(M qdd)/∂q``,
    ``Q = Q0 - ∂(M qdd)/∂u`` (the Jacobians of ``e = F - M qdd``).
    """
    def build():
        d = eom.symbolic
        a = ca.SX.sym("qdd", eom.n_q)
        Ma = d.M @ a
        M, C, K, Q, F, Hq, Hu = ca.cse([ca.densify(v) for v in (
            d.M, -ca.jacobian(d.F, d.qd), -ca.jacobian(d.F, d.q), ca.jacobian(d.F, d.u), d.F,
            ca.jacobian(Ma, d.q), ca.jacobian(Ma, d.u))])
        return {"parts": ca.Function(f"{eom.name}_residual_parts", [d.q, d.qd, d.u, d.p], [M, C, K, Q, F],
                                     ["q", "qd", "u", "p"], ["M", "C", "K", "Q", "F"]),
                "inertia": ca.Function(f"{eom.name}_inertia_gradient", [d.q, d.u, d.p, a], [Hq, Hu],
                                       ["q", "u", "p", "a"], ["Hq", "Hu"]),
                "jacobians": ca.Function(f"{eom.name}_linearization", [d.q, d.qd, a, d.u, d.p],
                                         [M, C, K + Hq, Q - Hu], ["q", "qd", "qdd", "u", "p"],
                                         ["M", "C", "K", "Q"])}

    return cached(eom, "residual_parts", build)


def jacobian_function(eom: EquationsOfMotion) -> ca.Function:
    """``(q, qd, qdd, u, p) -> (M0, C0, K0, Q0)``: the residual's Jacobians, built once per model."""
    return residual_parts(eom)["jacobians"]


def linear_function(eom: EquationsOfMotion) -> ca.Function:
    """``(q, qd, u, p) -> (M, C, K, Q, A, B, xd)``, all dense, built once per model.

    M, C, K, Q at zero acceleration (``K = -∂F/∂q``, ``Q = ∂F/∂u`` when nothing but
    F depends on q, u); A, B the exact Jacobians of the rhs, at ``q̈_op = M⁻¹F``
    (``K(q̈_op) = K + ∂(M a)/∂q`` at ``a = q̈_op``, see the module docstring);
    ``xd = [qd; q̈_op]``. SX with a symbolic solve of the small M up to 8 DOF, MX
    with a numeric QR beyond.
    """
    return cached(eom, "linear_function", lambda: _build_linear_function(eom))


def _build_linear_function(eom: EquationsOfMotion) -> ca.Function:
    n, nu = eom.n_q, eom.n_u
    built = residual_parts(eom)
    first, second = built["parts"], built["inertia"]
    sym = ca.SX.sym if n <= SYMBOLIC_SOLVE_MAX_DOF else ca.MX.sym
    args = [sym(s, k) for s, k in (("q", n), ("qd", n), ("u", nu), ("p", eom.n_p))]
    M, C, K, Q, F = first(*args)
    if n <= SYMBOLIC_SOLVE_MAX_DOF:                # symbolic QR of the small M
        qdd_op = ca.solve(M, F)
        Hq, Hu = second(args[0], args[2], args[3], qdd_op)
        sol = ca.solve(M, ca.horzcat(K + Hq, C, Q - Hu))
        opts = {"cse": True}
    else:
        qdd_op = ca.solve(M, F, "qr")
        Hq, Hu = second(args[0], args[2], args[3], qdd_op)
        sol = ca.solve(M, ca.horzcat(K + Hq, C, Q - Hu), "qr")
        opts = {}
    A = ca.vertcat(ca.horzcat(ca.DM.zeros(n, n), ca.DM.eye(n)), -sol[:, : 2 * n])
    B = ca.vertcat(ca.DM.zeros(n, nu), sol[:, 2 * n:])
    outs = [ca.densify(v) for v in (M, C, K, Q, A, B, ca.vertcat(args[1], qdd_op))]
    return ca.Function(f"{eom.name}_linear", args, outs, ["q", "qd", "u", "p"],
                       ["M", "C", "K", "Q", "A", "B", "xd"], opts)
