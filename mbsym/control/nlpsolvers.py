"""Converged NLP solvers on a stage problem: CasADi ``nlpsol`` plugins ipopt, fatrop and sqpmethod.

The NLP comes from :func:`mbsym.control.nlp.horizon_nlp` (one mapped stage
Function). ``fatrop`` and ``sqpmethod`` with ``hpipm`` are given the stage structure
(``N``, ``nx``, ``nu``, ``ng``). Hessians: exact (CasADi's automatic
differentiation of the mapped stage) or, for ipopt and sqpmethod, the Gauss–Newton
Hessian of the least-squares cost passed as ``hess_lag``. With ``compile=True`` the
solver's Functions are generated as C and compiled once (:mod:`mbsym.control._compile`).

sqpmethod with hpipm keeps hpipm's default mode (``robust``; iteration limit raised to 100):
sqpmethod's stopping test uses the QP multipliers, and with ``speed_abs`` (what our own
SQP uses) it ran to its iteration limit on 58 of 60 steps although the inputs were right
to 1e-8. Measurements in ``docs/control.md``.
"""

from __future__ import annotations

import time
from typing import Any, Mapping

import casadi as ca
import numpy as np

from ..exceptions import ControlDefinitionError
from ._compile import compiled_nlpsol
from .nlp import horizon_nlp
from .nlpfunctions import nlp_functions
from .qp import QP_SOLVERS, gauss_newton_hessian
from .sqp import SolveResult
from .stages import StageProblem

__all__ = ["NLP_SOLVERS", "NlpSolver"]

#: CasADi nlpsol plugins available by name.
NLP_SOLVERS = ("ipopt", "fatrop", "sqpmethod")

_INFEASIBLE = ("Infeasible_Problem_Detected", "Restoration_Failed", "Error_In_Step_Computation")


class NlpSolver:
    """A converged NLP solver on a stage problem.

    Parameters
    ----------
    problem : StageProblem
    solver : {"ipopt", "fatrop", "sqpmethod"}
    hessian : {"exact", "gauss-newton"}, keyword-only
        Gauss–Newton needs ipopt or sqpmethod.
    qp_solver : str, keyword-only
        QP solver of sqpmethod (default ``"hpipm"``).
    max_iter : int, keyword-only
    tol : float, keyword-only
        Convergence tolerance passed to the solver.
    options : dict, optional, keyword-only
        Extra nlpsol options (merged over ours, dicts one level deep).
    compile : bool, keyword-only
        Compile the NLP Functions (default True).
    """

    def __init__(self, problem: StageProblem, solver: str, *, hessian: str = "exact", qp_solver: str = "hpipm",
                 max_iter: int = 100, tol: float = 1e-8, options: Mapping[str, Any] | None = None,
                 compile: bool = True) -> None:
        if solver not in NLP_SOLVERS:
            raise ControlDefinitionError(f"NLP solver must be one of {list(NLP_SOLVERS)}; got {solver!r}.")
        if hessian not in ("exact", "gauss-newton"):
            raise ControlDefinitionError(f"hessian must be 'exact' or 'gauss-newton'; got {hessian!r}.")
        if hessian == "gauss-newton" and solver == "fatrop":
            raise ControlDefinitionError("fatrop computes its own Hessian: use hessian='exact', or ipopt/sqpmethod "
                                         "for a Gauss-Newton Hessian.")
        if qp_solver not in QP_SOLVERS:
            raise ControlDefinitionError(f"qp_solver must be one of {list(QP_SOLVERS)}; got {qp_solver!r}.")
        t0 = time.perf_counter()
        self.problem, self.solver_name = problem, solver
        self._nlp = horizon_nlp(problem)
        opts = self._options(solver, hessian, qp_solver, int(max_iter), float(tol))
        for key, value in dict(options or {}).items():
            opts[key] = {**opts[key], **value} if isinstance(value, Mapping) and isinstance(opts.get(key), dict) \
                else value
        self._solver, self.compiled, _ = compiled_nlpsol(
            f"mpc_{solver}", solver, self._nlp.as_dict(), opts, compile=compile,
            functions=lambda ref: nlp_functions(problem, self._nlp, ref, hessian=hessian))
        self._lam_g = np.zeros(problem.layout.n_g)
        self._lam_x = np.zeros(problem.layout.n_w)
        self.build_time = time.perf_counter() - t0

    def _options(self, solver: str, hessian: str, qp_solver: str, max_iter: int, tol: float) -> dict:
        P = self.problem
        N = P.N
        structure = {"N": N, "nx": [P.n_x] * (N + 1), "nu": [P.n_u] * N + [0], "ng": [P.n_c] * N + [P.n_cN]}
        opts: dict[str, Any] = {"print_time": False}
        if hessian == "gauss-newton":
            opts["hess_lag"] = self._gauss_newton(triu=solver == "ipopt")
        if solver == "ipopt":
            opts["ipopt"] = {"print_level": 0, "sb": "yes", "max_iter": max_iter, "tol": tol}
        elif solver == "fatrop":
            opts.update(structure, structure_detection="manual",
                        fatrop={"print_level": 0, "max_iter": max_iter, "tol": tol})
        else:
            qp_opts: dict[str, Any] = {"error_on_fail": False}
            if qp_solver == "hpipm":      # hpipm's own default mode: sqpmethod's stopping test needs its multipliers
                qp_opts.update(structure, hpipm={"iter_max": 100})
            if qp_solver == "qrqp":
                qp_opts.update(print_iter=False, print_header=False, print_info=False)
            opts.update(qpsol=qp_solver, qpsol_options=qp_opts, max_iter=max_iter, tol_pr=tol, tol_du=tol,
                        print_header=False, print_iteration=False, print_status=False)
        return opts

    def _gauss_newton(self, triu: bool) -> ca.Function:
        P, nlp = self.problem, self._nlp
        gn = gauss_newton_hessian(P)
        D = ca.reshape(nlp.P[: P.n_d * (P.N + 1)], P.n_d, P.N + 1)
        lam_f, lam_g = ca.MX.sym("lam_f"), ca.MX.sym("lam_g", P.layout.n_g)
        H = lam_f * gn(nlp.w, D, nlp.P[P.n_d * (P.N + 1):])
        return ca.Function("nlp_hess_l", [nlp.w, nlp.P, lam_f, lam_g], [ca.triu(H) if triu else H],
                           ["x", "p", "lam_f", "lam_g"], ["triu_hess_gamma_x_x" if triu else "hess_gamma_x_x"])

    def solve(self, w0: np.ndarray, D: np.ndarray, p: np.ndarray, bounds: tuple[np.ndarray, ...],
              x0: np.ndarray | None = None) -> SolveResult:
        """Solve from ``w0`` (primal warm start; the previous multipliers are reused)."""
        lbw, ubw, lbg, ubg = (np.array(b, dtype=float) for b in bounds)
        if x0 is not None:
            sl = self.problem.layout.x_index(0)
            lbw[sl] = ubw[sl] = x0
        t0 = time.perf_counter()
        try:
            res = self._solver(x0=w0, p=self._nlp.parameters(D, p), lbx=lbw, ubx=ubw, lbg=lbg, ubg=ubg,
                               lam_g0=self._lam_g, lam_x0=self._lam_x)
        except RuntimeError as exc:            # an exception inside the solver (e.g. NaN in a Function)
            return SolveResult(np.array(w0, dtype=float), False, f"error: {str(exc)[-200:]}", 0, np.nan, np.nan,
                               0, {"solver": time.perf_counter() - t0})
        wall = time.perf_counter() - t0
        stats = self._solver.stats()
        w = np.asarray(res["x"], dtype=float).reshape(-1)
        g = np.asarray(res["g"], dtype=float).reshape(-1)
        viol = float(max(0.0, np.max(lbg - g, initial=0.0), np.max(g - ubg, initial=0.0),
                         np.max(lbw - w, initial=0.0), np.max(w - ubw, initial=0.0)))
        status = str(stats.get("return_status", "?"))
        ok = bool(stats.get("success", False)) and bool(np.all(np.isfinite(w)))
        if status == "Search_Direction_Becomes_Too_Small" and viol <= 1e-6 and np.all(np.isfinite(w)):
            # sqpmethod: the primal step vanished at a feasible point (its dual test fails on QP multipliers
            # accurate to ~1e-8): converged in the primal variables
            ok, status = True, "success (search direction too small)"
        if not np.all(np.isfinite(w)):
            status = "nan"
        elif status in _INFEASIBLE:
            status = f"infeasible ({status})"
        if ok:
            self._lam_g = np.asarray(res["lam_g"], dtype=float).reshape(-1)
            self._lam_x = np.asarray(res["lam_x"], dtype=float).reshape(-1)
        return SolveResult(w, ok, status if ok and status.startswith("success") else ("success" if ok else status),
                           int(stats.get("iter_count", 0) or 0),
                           float(res["f"]), viol, 0, {"solver": wall})

    def shift_multipliers(self) -> None:
        """Move the stored multipliers one stage ahead (with the primal shift)."""
        P, L = self.problem, self.problem.layout
        per = P.n_x + P.n_c
        body = self._lam_g[: P.N * per].reshape(P.N, per)
        body = np.concatenate([body[1:], body[-1:]], axis=0)
        self._lam_g = np.concatenate([body.reshape(-1), self._lam_g[P.N * per:]])
        self._lam_x = L.shift(self._lam_x)
