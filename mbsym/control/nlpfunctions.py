"""The Functions an NLP solver evaluates, assembled from stage-level derivatives.

CasADi's ``nlpsol`` differentiates the whole-horizon MX graph itself; for a mapped
stage that costs many sweeps through the map (4–6 ms per Jacobian or Hessian of a
6-state, 40-stage problem, measured). Here the stage Jacobians and the stage
Hessian of the Lagrangian are differentiated once, at stage level, in SX, then
``map``-ped and assembled into the sparse horizon matrices, exactly like the QP of
:mod:`mbsym.control.qp`. :func:`nlp_functions` returns them under the names and
signatures a given solver expects (``nlp_f``, ``nlp_g``, ``nlp_grad_f``,
``nlp_jac_g``, ``nlp_hess_l``, ``nlp_grad``, ``nlp_fg``, ``nlp_jac_fg``), read from
the solver CasADi builds, so that a compiled library of them can replace CasADi's
own (:func:`mbsym.control._compile.compiled_nlpsol`).
"""

from __future__ import annotations

import casadi as ca

from .nlp import HorizonNLP, split_w
from .stages import StageProblem

__all__ = ["nlp_functions"]


def _stage_functions(P: StageProblem, hessian: str):
    """SX Functions of a path stage, the terminal stage and the initial term: values, gradients, Jacobians, Hessians."""
    sym = ca.SX if P.path.is_a("SXFunction") and P.terminal.is_a("SXFunction") else ca.MX
    x, u, d, p = sym.sym("x", P.n_x), sym.sym("u", P.n_u), sym.sym("d", P.n_d), sym.sym("p", P.n_p)
    sigma, lf, lc = sym.sym("sigma"), sym.sym("lf", P.n_x), sym.sym("lc", P.n_c)
    f, c, r, l_ = P.path(x, u, d, p)
    v = ca.vertcat(x, u)
    cost = ca.sumsqr(r) + l_
    if hessian == "exact":
        H = ca.hessian(sigma * cost - ca.dot(lf, f) + ca.dot(lc, c), v)[0]
    else:
        Jr = ca.jacobian(r, v)
        H = sigma * (2 * ca.mtimes(Jr.T, Jr) + ca.hessian(l_, v)[0])
    if P.dynamics_jacobian is not None and hessian == "gauss-newton":   # no second derivatives of the map:
        rest = ca.Function("nlp_stage_rest", [x, u, d, p],                # its Jacobian from chained sensitivities
                           [ca.densify(o) for o in (c, cost, ca.gradient(cost, v), ca.jacobian(c, v))])
        xm, um, dm, pm = (ca.MX.sym(s, n) for s, n in (("x", P.n_x), ("u", P.n_u), ("d", P.n_d), ("p", P.n_p)))
        fm, Jfm = P.dynamics_jacobian(xm, um, dm, pm)
        cm, costm, gm, Jcm = rest(xm, um, dm, pm)
        values = ca.Function("nlp_stage", [xm, um, dm, pm], [fm, cm, costm, gm, Jfm, Jcm])
    else:
        values = ca.Function("nlp_stage", [x, u, d, p],
                             [ca.densify(o) for o in (f, c, cost, ca.gradient(cost, v), ca.jacobian(f, v),
                                                      ca.jacobian(c, v))])
    stage = (values, ca.Function("nlp_stage_hessian", [x, u, d, p, sigma, lf, lc], [ca.densify(H)]))
    lN = sym.sym("lN", P.n_cN)
    cN, rN, lNc = P.terminal(x, d, p)
    costN = ca.sumsqr(rN) + lNc
    if hessian == "exact":
        HN = ca.hessian(sigma * costN + ca.dot(lN, cN), x)[0]
    else:
        JN = ca.jacobian(rN, x)
        HN = sigma * (2 * ca.mtimes(JN.T, JN) + ca.hessian(lNc, x)[0])
    term = (ca.Function("nlp_terminal", [x, d, p],
                        [ca.densify(o) for o in (cN, costN, ca.gradient(costN, x), ca.jacobian(cN, x))]),
            ca.Function("nlp_terminal_hessian", [x, d, p, sigma, lN], [ca.densify(HN)]))
    init = None
    if P.initial is not None:
        r0 = P.initial(x, p)
        cost0 = ca.sumsqr(r0)
        init = (ca.Function("nlp_initial", [x, p], [ca.densify(o) for o in (cost0, ca.gradient(cost0, x))]),
                ca.Function("nlp_initial_hessian", [x, p, sigma], [ca.densify(sigma * ca.hessian(cost0, x)[0])]))
    return stage, term, init


def _assemble(P: StageProblem, nlp: HorizonNLP, hessian: str) -> dict:
    """MX expressions of f, g, ∇f, J_g, ∇²L (σ, λ symbolic) over the horizon."""
    stage, term, init = _stage_functions(P, hessian)
    N, nx, nu, nc = P.N, P.n_x, P.n_u, P.n_c
    nv, n_w = nx + nu, P.layout.n_w
    w = nlp.w
    D = ca.reshape(nlp.P[: P.n_d * (N + 1)], P.n_d, N + 1)
    p = nlp.P[P.n_d * (N + 1):]
    sigma, lam = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", P.layout.n_g)
    L = ca.reshape(lam[: N * (nx + nc)], nx + nc, N)
    X, U, xN = split_w(P, w)
    F, C, COST, G, JF, JC = stage[0].map(N, "serial")(X, U, D[:, :N], ca.repmat(p, 1, N))
    H = stage[1].map(N, "serial")(X, U, D[:, :N], ca.repmat(p, 1, N), ca.repmat(sigma, 1, N), L[:nx, :], L[nx:, :])
    cN, costN, gN, JcN = term[0](xN, D[:, N], p)
    HN = term[1](xN, D[:, N], p, sigma, lam[N * (nx + nc):])
    hess = [H[:, k * nv:(k + 1) * nv] for k in range(N)] + [HN]
    grad, cost = ca.vertcat(ca.vec(G), gN), ca.sum2(COST) + costN
    if init is not None:
        cost0, g0 = init[0](X[:, 0], p)
        hess[0] = hess[0] + ca.diagcat(init[1](X[:, 0], p, sigma), ca.MX(nu, nu))
        grad = grad + ca.vertcat(g0, ca.MX(n_w - nx, 1))
        cost = cost + cost0
    rows = []
    for k in range(N):
        rows.append(ca.horzcat(ca.MX(nx, k * nv), -JF[:, k * nv:(k + 1) * nv], ca.MX.eye(nx),
                               ca.MX(nx, n_w - (k + 1) * nv - nx)))
        rows.append(ca.horzcat(ca.MX(nc, k * nv), JC[:, k * nv:(k + 1) * nv], ca.MX(nc, n_w - (k + 1) * nv)))
    rows.append(ca.horzcat(ca.MX(P.n_cN, N * nv), JcN))
    jac = ca.vertcat(*rows)
    X_next = ca.horzcat(X[:, 1:], xN) if N > 1 else xN
    g = ca.vertcat(ca.vec(ca.vertcat(X_next - F, C)), cN)
    H_all = ca.diagcat(*hess)
    grad_f = ca.densify(grad)
    lag_x = ca.densify(grad_f * sigma + ca.mtimes(jac.T, lam))
    lag_p = ca.densify(ca.gradient(sigma * nlp.f + ca.dot(lam, nlp.g), nlp.P))    # rare: reverse AD is fine
    return {"x": w, "p": nlp.P, "lam_f": sigma, "lam_g": lam, "f": cost, "g": g, "grad_f_x": grad_f,
            "jac_g_x": jac, "hess_gamma_x_x": H_all, "triu_hess_gamma_x_x": ca.triu(H_all), "grad_gamma_x": lag_x,
            "grad_gamma_p": lag_p}


def nlp_functions(P: StageProblem, nlp: HorizonNLP, reference: ca.Function, *, hessian: str = "exact") -> list:
    """Replacements of the solver ``reference``'s Functions (same names, inputs and outputs), plus its oracle."""
    exprs = _assemble(P, nlp, hessian)
    out = [ca.Function("nlp", [exprs["x"], exprs["p"]], [exprs["f"], exprs["g"]], ["x", "p"], ["f", "g"])]
    for name in reference.get_function():
        ref = reference.get_function(name)
        ins = [ref.name_in(i) for i in range(ref.n_in())]
        outs = [ref.name_out(i) for i in range(ref.n_out())]
        missing = [n for n in ins + outs if n not in exprs]
        if missing:
            raise KeyError(f"{name}: no expression for {missing}")
        out.append(ca.Function(name, [exprs[n] for n in ins], [exprs[n] for n in outs], ins, outs))
    return out
