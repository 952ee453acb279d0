"""The QP of a stage problem at a linearization point, assembled from one mapped stage Function.

One SX *stage QP Function* returns, at a stage's linearization point, the dynamics
value and Jacobian, the path constraints and their Jacobian, the Gauss–Newton
Hessian ``2 JᵣᵀJᵣ`` (plus the exact Hessian of general cost terms) and the
gradient ``2 Jᵣᵀr``. It is ``map``-ped over the horizon inside one MX *preparation
Function* that assembles the sparse QP with variables and constraints in stage
order, so structure-exploiting QP solvers (``hpipm``, ``fatrop``) see ``N``,
``nx``, ``nu``, ``ng``. :func:`conic` creates the QP solver with those options.
"""

from __future__ import annotations

from typing import Any, Mapping

import casadi as ca
import numpy as np

from ..exceptions import ControlDefinitionError
from .nlp import split_w
from .stages import StageProblem

__all__ = ["QP_SOLVERS", "preparation_function", "gauss_newton_hessian", "conic", "QPCall"]

#: CasADi conic plugins usable for the QPs; ``hpipm`` exploits the stage structure. (CasADi's ``fatrop`` conic
#: aborts with an internal assertion, ``objective_scale==1``, in casadi 3.8.2: not offered.)
QP_SOLVERS = ("hpipm", "qrqp", "osqp", "daqp", "qpoases")


def _stage_qp(P: StageProblem, hessian_only: bool = False) -> tuple[ca.Function, ca.Function, ca.Function | None]:
    """SX (or MX) Functions of the stage, terminal and initial QP data (or only their Hessians)."""
    sym = ca.SX if P.path.is_a("SXFunction") and P.terminal.is_a("SXFunction") else ca.MX
    x, u, d, p = sym.sym("x", P.n_x), sym.sym("u", P.n_u), sym.sym("d", P.n_d), sym.sym("p", P.n_p)
    f, c, r, l_ = P.path(x, u, d, p)
    v = ca.vertcat(x, u)
    Jr = ca.jacobian(r, v)
    H = 2 * ca.mtimes(Jr.T, Jr) + ca.hessian(l_, v)[0]
    grad = 2 * ca.mtimes(Jr.T, r) + ca.gradient(l_, v)
    outs = [f, None, c, ca.jacobian(c, v), H, grad, ca.sumsqr(r) + l_]
    if P.dynamics_jacobian is None:
        outs[1] = ca.jacobian(f, v)
    else:       # the stage map's Jacobian from chained sensitivities; the rest by AD of the small parts
        rest = ca.Function("stage_rest", [x, u, d, p], [ca.densify(o) for o in outs[2:]])
        x, u, d, p = (ca.MX.sym(s, n) for s, n in (("x", P.n_x), ("u", P.n_u), ("d", P.n_d), ("p", P.n_p)))
        outs = [*P.dynamics_jacobian(x, u, d, p), *rest(x, u, d, p)]
    names = ["f", "Jf", "c", "Jc", "H", "g", "cost"]
    keep = [4] if hessian_only else range(len(outs))
    stage = ca.Function("stage_qp", [x, u, d, p], [ca.densify(outs[i]) for i in keep],
                        ["x", "u", "d", "p"], [names[i] for i in keep])
    x, d, p = (sym.sym(s, n) for s, n in (("x", P.n_x), ("d", P.n_d), ("p", P.n_p)))
    cN, rN, lN = P.terminal(x, d, p)
    JrN = ca.jacobian(rN, x)
    outs = [cN, ca.jacobian(cN, x), 2 * ca.mtimes(JrN.T, JrN) + ca.hessian(lN, x)[0],
            2 * ca.mtimes(JrN.T, rN) + ca.gradient(lN, x), ca.sumsqr(rN) + lN]
    names = ["c", "Jc", "H", "g", "cost"]
    keep = [2] if hessian_only else range(len(outs))
    term = ca.Function("terminal_qp", [x, d, p], [ca.densify(outs[i]) for i in keep], ["x", "d", "p"],
                       [names[i] for i in keep])
    init = None
    if P.initial is not None:
        r0 = P.initial(x, p)
        J0 = ca.jacobian(r0, x)
        outs = [2 * ca.mtimes(J0.T, J0), 2 * ca.mtimes(J0.T, r0), ca.sumsqr(r0)]
        keep = [0] if hessian_only else range(3)
        init = ca.Function("initial_qp", [x, p], [ca.densify(outs[i]) for i in keep], ["x", "p"],
                           [["H", "g", "cost"][i] for i in keep])
    return stage, term, init


def preparation_function(P: StageProblem) -> ca.Function:
    """``(w, D, p, lbw, ubw, lbg, ubg) -> (H, g, A, lba, uba, lbdw, ubdw, cost, violation)``: the QP at ``w``."""
    stage, term, init = _stage_qp(P)
    N, nx, nu = P.N, P.n_x, P.n_u
    nv, n_w = nx + nu, P.layout.n_w
    w, D, p = ca.MX.sym("w", n_w), ca.MX.sym("D", P.n_d, N + 1), ca.MX.sym("p", P.n_p)
    bounds = [ca.MX.sym(s, n) for s, n in (("lbw", n_w), ("ubw", n_w), ("lbg", P.layout.n_g), ("ubg", P.layout.n_g))]
    X, U, xN = split_w(P, w)
    F, JF, C, JC, H, G, COST = stage.map(N, "serial")(X, U, D[:, :N], ca.repmat(p, 1, N))
    cN, JcN, HN, gN, costN = term(xN, D[:, N], p)
    hess = [H[:, k * nv:(k + 1) * nv] for k in range(N)] + [HN]
    grad, cost = ca.vertcat(ca.vec(G), gN), ca.sum2(COST) + costN
    if init is not None:
        H0, g0, cost0 = init(X[:, 0], p)
        hess[0] = hess[0] + ca.diagcat(H0, ca.MX(nu, nu))
        grad = grad + ca.vertcat(g0, ca.MX(n_w - nx, 1))
        cost = cost + cost0
    rows = []
    for k in range(N):
        left, right = ca.MX(nx, k * nv), ca.MX(nx, n_w - (k + 1) * nv - nx)
        rows.append(ca.horzcat(left, -JF[:, k * nv:(k + 1) * nv], ca.MX.eye(nx), right))
        rows.append(ca.horzcat(ca.MX(P.n_c, k * nv), JC[:, k * nv:(k + 1) * nv], ca.MX(P.n_c, n_w - (k + 1) * nv)))
    rows.append(ca.horzcat(ca.MX(P.n_cN, N * nv), JcN))
    X_next = ca.horzcat(X[:, 1:], xN) if N > 1 else xN
    gval = ca.vertcat(ca.vec(ca.vertcat(X_next - F, C)), cN)
    lbw, ubw, lbg, ubg = bounds
    viol = ca.mmax(ca.vertcat(0, lbg - gval, gval - ubg, lbw - w, w - ubw))
    return ca.Function("sqp_preparation", [w, D, p, *bounds],
                       [ca.diagcat(*hess), ca.densify(grad), ca.vertcat(*rows), ca.densify(lbg - gval),
                        ca.densify(ubg - gval), ca.densify(lbw - w), ca.densify(ubw - w), cost, viol],
                       ["w", "D", "p", "lbw", "ubw", "lbg", "ubg"],
                       ["H", "g", "A", "lba", "uba", "lbdw", "ubdw", "cost", "violation"])


def gauss_newton_hessian(P: StageProblem) -> ca.Function:
    """``(w, D, p) -> H``: the block-diagonal Gauss–Newton Hessian of the whole cost (plus general-cost Hessians)."""
    stage, term, init = _stage_qp(P, hessian_only=True)
    N, nx, nu = P.N, P.n_x, P.n_u
    w, D, p = ca.MX.sym("w", P.layout.n_w), ca.MX.sym("D", P.n_d, N + 1), ca.MX.sym("p", P.n_p)
    X, U, xN = split_w(P, w)
    H = stage.map(N, "serial")(X, U, D[:, :N], ca.repmat(p, 1, N))
    blocks = [H[:, k * (nx + nu):(k + 1) * (nx + nu)] for k in range(N)] + [term(xN, D[:, N], p)]
    if init is not None:
        blocks[0] = blocks[0] + ca.diagcat(init(X[:, 0], p), ca.MX(nu, nu))
    return ca.Function("gauss_newton_hessian", [w, D, p], [ca.diagcat(*blocks)], ["w", "D", "p"], ["H"])


def conic(name: str, P: StageProblem, H: ca.Sparsity, A: ca.Sparsity, options: Mapping[str, Any], *,
          label: str | None = None) -> ca.Function:
    opts: dict[str, Any] = {"error_on_fail": False}
    N = P.N
    structure = {"N": N, "nx": [P.n_x] * (N + 1), "nu": [P.n_u] * N + [0], "ng": [P.n_c] * N + [P.n_cN]}
    if name == "hpipm":
        # speed_abs: the other modes stall on the ±1e8 bounds CasADi puts on unbounded variables (see docs)
        opts.update(structure, hpipm={"mode": "speed_abs", "iter_max": 50})
    elif name == "qrqp":
        opts.update(print_iter=False, print_header=False, print_info=False, max_iter=200)
    elif name == "osqp":
        opts.update(osqp={"verbose": False, "eps_abs": 1e-8, "eps_rel": 1e-8, "max_iter": 10000, "polish": True},
                    warm_start_primal=True)
    elif name == "qpoases":
        opts.update(printLevel="none", sparse=True)
    elif name != "daqp":
        raise ControlDefinitionError(f"qp_solver must be one of {list(QP_SOLVERS)}; got {name!r}.")
    for key, value in dict(options).items():       # user options override ours (dicts merged one level)
        opts[key] = {**opts[key], **value} if isinstance(value, Mapping) and isinstance(opts.get(key), dict) \
            else value
    return ca.conic(label or f"qp_{name}", name, {"h": H, "a": A}, opts)


class QPCall:
    """A conic called on preallocated numpy arrays: an MX wrapper run through ``Function.buffer()``.

    The wrapper takes ``H`` and ``A`` by their nonzeros (their fixed sparsity), so no
    ``DM`` is built per call (building a 1600-nonzero DM from numpy takes ~2 ms).
    Calling the conic's own buffer is not an option: CasADi 3.8's hpipm interface
    stops writing its results from the second buffered call on (measured).

    The result is accepted only if the solver reports success *and* the step is
    finite and satisfies the QP's bounds and constraints (qrqp was seen reporting
    success on a solution violating a bound by 4.3).

    Parameters
    ----------
    qp : casadi.Function
        The conic.
    data : dict of ndarray
        ``"H"``, ``"A"`` (nonzeros), ``"g"``, ``"lba"``, ``"uba"``, ``"lbx"``, ``"ubx"``; read at every call.
    """

    FEAS_TOL = 1e-6

    def __init__(self, qp: ca.Function, data: dict) -> None:
        H, A = ca.MX.sym("H", qp.sparsity_in("h")), ca.MX.sym("A", qp.sparsity_in("a"))
        n, m = qp.sparsity_in("h").size1(), qp.sparsity_in("a").size1()
        vecs = [ca.MX.sym(s, k) for s, k in (("g", n), ("lba", m), ("uba", m), ("lbx", n), ("ubx", n))]
        g, lba, uba, lbx, ubx = vecs
        res = qp(h=H, g=g, a=A, lba=lba, uba=uba, lbx=lbx, ubx=ubx)
        x = res["x"]
        Ax = ca.mtimes(A, x)
        viol = ca.mmax(ca.vertcat(0, lbx - x, x - ubx, lba - Ax, Ax - uba))       # checked in C, not numpy
        self._wrapper = ca.Function(f"{qp.name()}_call", [H, A, *vecs],
                                    [x, res["cost"], res["lam_a"], res["lam_x"], viol])
        self.qp, self.data = qp, data
        self.x, self.cost, self.lam_a, self.lam_x = np.zeros(n), np.zeros(1), np.zeros(m), np.zeros(n)
        self._viol = np.zeros(1)
        self._buf, self._run = self._wrapper.buffer()
        for i, key in enumerate(("H", "A", "g", "lba", "uba", "lbx", "ubx")):
            self._buf.set_arg(i, memoryview(data[key]))
        for i, arr in enumerate((self.x, self.cost, self.lam_a, self.lam_x, self._viol)):
            self._buf.set_res(i, memoryview(arr))
        self._mem: int | None = None
        self.solver_time = 0.0

    def __call__(self) -> tuple[bool, str, int]:
        """Solve into :attr:`x`; ``(accepted, status, iterations)``."""
        self.x[:] = 0.0
        self._run()
        stats = self._stats()
        iters = int(stats.get("iter_count", -1) or 0)
        self.solver_time = float(stats.get("t_wall_solver", 0.0) or 0.0)
        if not bool(stats.get("success", False)):
            return False, f"qp_failed: {stats.get('return_status', stats.get('unified_return_status', '?'))}", iters
        if not np.all(np.isfinite(self.x)):
            return False, "nan", iters
        viol = float(self._viol[0])
        if not viol <= self.FEAS_TOL * (1.0 + np.max(np.abs(self.x))):
            return False, f"qp_failed: reported success, but the step violates the QP constraints by {viol:.2g}", iters
        return True, "success", iters

    def violation(self) -> float:
        """Largest violation of the QP's bounds and linear constraints by :attr:`x` (last call)."""
        return float(self._viol[0])

    def _stats(self) -> dict:
        """The conic's statistics of the wrapper's call (its memory is found once, then reused)."""
        if self._mem is None:
            found = []
            for k in range(64):
                try:
                    self.qp.stats(k)
                    found.append(k)
                except RuntimeError:
                    continue
            self._mem = max(found) if found else -1
        if self._mem < 0:
            return {"success": True, "iter_count": -1}
        return self.qp.stats(self._mem)
