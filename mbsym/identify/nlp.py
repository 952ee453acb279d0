"""The same multiple-shooting problem through CasADi's NLP solvers (``sqpmethod`` or ``ipopt``).

The decision vector is ``w = [θ; vec(S_1); …; vec(S_R)]`` (nodes as ``n_x × (N + 1)``
matrices), the objective ``½‖r‖²`` and the constraints the gaps of every interval,
with the mapped (virtual-machine) interval and output Functions, so CasADi
computes exact Jacobians by AD. The Hessian is the Gauss–Newton one,
``Jᵣᵀ Jᵣ`` (option ``hess_lag``), positive semi-definite and free of second
derivatives. ``sqpmethod`` solves its QPs with ``osqp`` (sparse); fixed initial
states and parameter bounds are simple bounds on ``w``.

Slower than :mod:`mbsym.identify.gauss_newton` (a sparse QP over all nodes per
iteration instead of a condensed dense one); kept as an independent check and for
users who want CasADi's solvers.
"""

from __future__ import annotations

import time

import casadi as ca
import numpy as np

from .gauss_newton import GaussNewtonResult, ShootingRecord, condensed, linearize, stack

__all__ = ["solve_nlp"]


def _wrap_mx(e, period: np.ndarray):
    if not np.any(period):
        return e
    P = ca.DM(np.where(period > 0, period, 1.0))
    mask = ca.DM((period > 0).astype(float))
    return e - mask * P * ca.floor(e / P + 0.5)


def solve_nlp(fun, recs: list[ShootingRecord], p: np.ndarray, theta0: np.ndarray, S0: list, lb: np.ndarray,
              ub: np.ndarray, *, solver: str = "ipopt", tol: float = 1e-8, max_iter: int = 100,
              verbose: bool = False) -> GaussNewtonResult:
    """Solve with ``nlpsol`` (``solver`` = ``"ipopt"`` or ``"sqpmethod"``); same result type as Gauss–Newton."""
    t0 = time.perf_counter()
    n_th, n_x = theta0.size, fun.n_x
    th = ca.MX.sym("theta", n_th)
    parts, res, gaps, lbw, ubw, w0 = [th], [], [], [lb], [ub], [theta0]
    p_fixed = np.array(p, dtype=float)
    p_fixed[fun.theta_index] = 0.0
    pf = ca.DM(p_fixed) + ca.mtimes(ca.DM(fun.E), th)          # the parameter vector with the estimates
    for i, (rec, S) in enumerate(zip(recs, S0)):
        n = rec.H.size
        Sm = ca.MX.sym(f"S{i}", n_x, n + 1)
        parts.append(ca.vec(Sm))
        xn = fun.sym_interval.map(n)(Sm[:, :-1], rec.U[:-1].T, rec.U[1:].T, pf, rec.H[None, :])
        gaps.append(ca.vec(xn - Sm[:, 1:]))
        y = fun.sym_output.map(n + 1)(Sm, rec.U.T, pf)
        e = _wrap_mx(y - ca.DM(rec.Y.T), rec.period)
        res.append(ca.vec(e * ca.DM(rec.w)))
        lo, hi = np.full((n_x, n + 1), -np.inf), np.full((n_x, n + 1), np.inf)
        fixed = np.setdiff1d(np.arange(n_x), rec.free0)
        lo[fixed, 0] = hi[fixed, 0] = rec.x0[fixed]
        S = np.array(S, dtype=float).copy()
        S[0, fixed] = rec.x0[fixed]
        lbw.append(lo.reshape(-1, order="F"))
        ubw.append(hi.reshape(-1, order="F"))
        w0.append(S.T.reshape(-1, order="F"))
    w, r, g = ca.vertcat(*parts), ca.vertcat(*res), ca.vertcat(*gaps)
    lam_f, lam_g, pp = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", g.numel()), ca.MX.sym("p", 0)
    Jr = ca.jacobian(r, w)
    H = lam_f * ca.mtimes(Jr.T, Jr)
    if solver == "ipopt":
        hess = ca.Function("hess_lag", [w, pp, lam_f, lam_g], [ca.triu(H)], ["x", "p", "lam_f", "lam_g"],
                           ["triu_hess_gamma_x_x"])
        opts = {"ipopt.print_level": 5 if verbose else 0, "print_time": verbose, "ipopt.tol": tol,
                "ipopt.max_iter": max_iter, "ipopt.sb": "yes"}
    else:
        hess = ca.Function("hess_lag", [w, pp, lam_f, lam_g], [H], ["x", "p", "lam_f", "lam_g"], ["hess_gamma_x_x"])
        opts = {"qpsol": "osqp", "max_iter": max_iter, "tol_pr": tol, "tol_du": tol, "print_time": verbose,
                "print_iteration": verbose, "print_header": verbose, "print_status": verbose,
                "qpsol_options": {"error_on_fail": False, "osqp": {"verbose": False, "eps_abs": 1e-10,
                                                                    "eps_rel": 1e-10, "max_iter": 20000,
                                                                    "polish": True}}}
    nlp = ca.nlpsol("identify_nlp", solver, {"x": w, "f": 0.5 * ca.sumsqr(r), "g": g}, {**opts, "hess_lag": hess})
    sol = nlp(x0=np.concatenate(w0), lbx=np.concatenate(lbw), ubx=np.concatenate(ubw), lbg=0.0, ubg=0.0)
    stats = nlp.stats()
    wopt = np.array(sol["x"], dtype=float).reshape(-1)
    theta = wopt[:n_th]
    S, off = [], n_th
    for rec in recs:
        k = n_x * (rec.H.size + 1)
        S.append(wopt[off:off + k].reshape(rec.H.size + 1, n_x))
        off += k
    lins = [linearize(fun, rec, s, theta, p) for rec, s in zip(recs, S)]
    J, _ = stack([condensed(fun, rec, *ln)[1:] for rec, ln in zip(recs, lins)], recs, n_th)
    r_opt = np.concatenate([ln[1].reshape(-1) for ln in lins])
    x_scale = np.maximum(np.max(np.abs(np.vstack(S)), axis=0), 1e-6)
    gap = max(float(np.max(np.abs(ln[2]) / x_scale)) for ln in lins)
    return GaussNewtonResult(theta, S, J, r_opt, int(stats.get("iter_count", 0)), bool(stats.get("success", False)),
                             f"{solver}: {stats.get('return_status', '')}", 0.5 * float(r_opt @ r_opt), gap, [],
                             time.perf_counter() - t0)
