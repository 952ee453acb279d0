"""The whole-horizon NLP of a :class:`~mbsym.control.stages.StageProblem`, from mapped stage Functions.

The stage Function is evaluated for all N stages by one ``Function.map`` (a loop in
the generated code, never an inlined horizon), the terminal Function once. The NLP
has the variables ``w`` in stage order, the parameters ``[vec(D); p]`` (stage
parameters column by column, then the global parameters) and the constraints in
the order fatrop and hpipm expect (see :mod:`mbsym.control.stages`).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from .stages import StageProblem

__all__ = ["HorizonNLP", "horizon_nlp"]


@dataclass(frozen=True)
class HorizonNLP:
    """The NLP as MX expressions: ``{"x": w, "p": P, "f": cost, "g": g}`` and its sizes."""

    w: ca.MX
    P: ca.MX
    f: ca.MX
    g: ca.MX
    problem: StageProblem

    def as_dict(self) -> dict:
        return {"x": self.w, "p": self.P, "f": self.f, "g": self.g}

    def parameters(self, D: np.ndarray, p: np.ndarray) -> np.ndarray:
        """The NLP parameter vector from stage parameters ``(n_d, N+1)`` and global parameters."""
        return np.concatenate([np.asarray(D, dtype=float).reshape(-1, order="F"), np.asarray(p, dtype=float)])


def split_w(P: StageProblem, w):
    """``X (nx, N)``, ``U (nu, N)``, ``x_N`` of a symbolic ``w``."""
    nx, nu, N = P.n_x, P.n_u, P.N
    body = ca.reshape(w[: N * (nx + nu)], nx + nu, N)
    return body[:nx, :], body[nx:, :], w[N * (nx + nu):]


def horizon_nlp(P: StageProblem) -> HorizonNLP:
    """Build the NLP of ``P`` (MX glue around the mapped stage Function)."""
    N = P.N
    w = ca.MX.sym("w", P.layout.n_w)
    D = ca.MX.sym("D", P.n_d, N + 1)
    p = ca.MX.sym("p", P.n_p)
    X, U, xN = split_w(P, w)
    stage = P.path.map(N, "serial")
    f, c, r, l_ = stage(X, U, D[:, :N], ca.repmat(p, 1, N))
    X_next = ca.horzcat(X[:, 1:], xN) if N > 1 else xN
    gaps = X_next - f                    # fatrop requires x_{k+1} - F(x_k, u_k)
    cN, rN, lN = P.terminal(xN, D[:, N], p)
    cost = ca.sumsqr(r) + ca.sum2(l_) + ca.sumsqr(rN) + lN
    if P.initial is not None:
        cost = cost + ca.sumsqr(P.initial(X[:, 0], p))
    g = ca.vertcat(ca.vec(ca.vertcat(gaps, c)), cN)
    return HorizonNLP(w, ca.vertcat(ca.vec(D), p), cost, g, P)


def merit_function(P: StageProblem) -> ca.Function:
    """``(w, D, p, lbw, ubw, lbg, ubg) -> (cost, l1 violation)`` of the whole NLP (line searches)."""
    nlp = horizon_nlp(P)
    n_w, n_g = P.layout.n_w, P.layout.n_g
    bounds = [ca.MX.sym(s, n) for s, n in (("lbw", n_w), ("ubw", n_w), ("lbg", n_g), ("ubg", n_g))]
    lbw, ubw, lbg, ubg = bounds
    w, g = nlp.w, nlp.g
    viol = ca.sum1(ca.fmax(0, lbg - g) + ca.fmax(0, g - ubg)) + ca.sum1(ca.fmax(0, lbw - w) + ca.fmax(0, w - ubw))
    D = ca.MX.sym("D", P.n_d, P.N + 1)
    p = ca.MX.sym("p", P.n_p)
    f = ca.Function("nlp_merit_parts", [w, nlp.P, *bounds], [nlp.f, viol])
    cost, v = f(w, ca.vertcat(ca.vec(D), p), *bounds)
    return ca.Function("nlp_merit", [w, D, p, *bounds], [cost, v], ["w", "D", "p", "lbw", "ubw", "lbg", "ubg"],
                       ["cost", "violation"])
