"""Gauss–Newton SQP and real-time iterations on a :class:`~mbsym.control.stages.StageProblem`.

What acados does, with CasADi pieces:

- one SX *stage QP Function* returns, at a stage's linearization point, the
  dynamics value and Jacobian, the path constraints and their Jacobian, the
  Gauss–Newton Hessian ``2 JᵣᵀJᵣ`` (plus the exact Hessian of general cost terms)
  and the gradient ``2 Jᵣᵀr``;
- it is ``map``-ped over the horizon inside one MX *preparation Function* that
  assembles the sparse QP (variables and constraints in stage order, so ``hpipm``
  sees the OCP structure: ``N``, ``nx``, ``nu``, ``ng``), compiled once through the
  disk cache of :mod:`mbsym.codegen`;
- a CasADi ``conic`` (``hpipm`` by default; ``qrqp``, ``osqp``, ``daqp``,
  ``qpoases``, ``fatrop``) solves the QP for the step ``Δw``.

Both are called through ``Function.buffer()`` on preallocated numpy arrays: the
QP data never leaves C memory layouts between the two calls.

A *real-time iteration* splits a sample into the **preparation** (linearize at the
shifted previous solution; the QP does not depend on the new measurement) and the
**feedback** (fix ``Δx₀ = x_measured − x₀`` in the bounds, solve one QP, update
``w``). :meth:`GaussNewtonSQP.solve` iterates to convergence (``‖Δw‖∞`` below a
tolerance) with full steps.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from ..codegen_async import compile_async
from ..exceptions import ControlDefinitionError
from .nlp import merit_function
from .qp import QP_SOLVERS, QPCall, conic, preparation_function
from .stages import StageProblem

__all__ = ["GaussNewtonSQP", "QP_SOLVERS", "SolveResult"]


@dataclass
class SolveResult:
    """Outcome of one solver call.

    Attributes
    ----------
    w : ndarray
        Primal solution (or the last iterate) in stage order.
    success : bool
    status : str
        ``"success"``, ``"max_iterations"``, ``"qp_failed: <reason>"``, ``"nan"``,
        ``"infeasible"`` or the NLP solver's own return status.
    iterations : int
        SQP (or NLP) iterations.
    cost : float
        Cost at the linearization point of the last iteration (SQP) or at the solution (NLP).
    violation : float
        Largest constraint violation at that point (bounds and constraints).
    qp_iterations : int
        Iterations of the last QP (0 for NLP solvers).
    times : dict
        Wall times [s]: ``"preparation"``, ``"feedback"`` (SQP) or ``"solver"``.
    """

    w: np.ndarray
    success: bool
    status: str
    iterations: int
    cost: float
    violation: float
    qp_iterations: int = 0
    times: dict = field(default_factory=dict)


class GaussNewtonSQP:
    """Gauss–Newton SQP on a stage problem: real-time iterations or iterations to convergence.

    Parameters
    ----------
    problem : StageProblem
    qp_solver : str, keyword-only
        A CasADi conic plugin, one of :data:`QP_SOLVERS` (default ``"hpipm"``).
    qp_options : dict, optional, keyword-only
        Options of the conic (merged over ours; e.g. ``{"hpipm": {"mode": "robust"}}``).
    compile : bool, keyword-only
        Compile the preparation Function (generated C, cached on disk). Default True.

    Attributes
    ----------
    w : ndarray
        The current iterate (stage order).
    build_time : float
        Seconds spent building the Functions and the QP solver, and waiting for their compilation.
    compiled : bool
        Whether the preparation runs compiled code (waits for its compilation).

    Notes
    -----
    With ``compile``, the preparation and merit Functions are compiled in the background
    (:func:`mbsym.codegen_async.compile_async`): the constructor returns at once; the first
    :meth:`prepare` waits for the preparation's library; the line search evaluates the merit
    Function in CasADi's virtual machine until its library is ready (same values).
    """

    #: Smallest step fraction of the line search; below it the search has failed.
    MIN_STEP = 1e-6

    def __init__(self, problem: StageProblem, *, qp_solver: str = "hpipm", qp_options: Mapping[str, Any] | None = None,
                 compile: bool = True) -> None:
        if qp_solver not in QP_SOLVERS:
            raise ControlDefinitionError(f"qp_solver must be one of {list(QP_SOLVERS)}; got {qp_solver!r}.")
        t0 = time.perf_counter()
        self.problem, self.layout = problem, problem.layout
        prep = preparation_function(problem)
        self._compiled = False
        self._prep_job = compile_async(prep) if compile else None
        self._prep = prep
        self._H_sp, self._A_sp = prep.sparsity_out(0), prep.sparsity_out(2)
        self._qp = conic(qp_solver, problem, self._H_sp, self._A_sp, qp_options or {})
        self.qp_solver = qp_solver
        self._alloc()
        self.w = np.zeros(self.layout.n_w)
        self._prepared = False
        self._merit_fn = merit_function(problem)          # virtual machine until compiled
        self._merit_job = compile_async(self._merit_fn) if compile else None
        self.build_time = time.perf_counter() - t0

    @property
    def compiled(self) -> bool:
        self._resolve()
        return self._compiled

    def _resolve(self) -> None:
        """Swap in the compiled preparation Function (waits for its compilation)."""
        if self._prep_job is None:
            return
        t0 = time.perf_counter()
        c = self._prep_job.result()
        self._prep_job = None
        self._prep, self._compiled = c.function, c.compiled
        self._bind_preparation()
        self.build_time += time.perf_counter() - t0

    def _alloc(self) -> None:
        """Preallocated arrays and the two buffers (no conversions in the loop)."""
        f, q = self._prep, self._qp
        self._in = {f.name_in(i): np.zeros(f.nnz_in(i)) for i in range(f.n_in())}
        self._out = {f.name_out(i): np.zeros(f.nnz_out(i)) for i in range(f.n_out())}
        self._bind_preparation()
        self._qp_call = QPCall(q, {"H": self._out["H"], "A": self._out["A"], "g": self._out["g"],
                                   "lba": self._out["lba"], "uba": self._out["uba"], "lbx": self._out["lbdw"],
                                   "ubx": self._out["ubdw"]})
        self._dw = self._qp_call.x

    def _bind_preparation(self) -> None:
        f = self._prep
        self._prep_buf, self._prep_run = f.buffer()
        for i in range(f.n_in()):
            self._prep_buf.set_arg(i, memoryview(self._in[f.name_in(i)]))
        for i in range(f.n_out()):
            self._prep_buf.set_res(i, memoryview(self._out[f.name_out(i)]))

    # ---------------------------------------------------------------- phases
    def set_iterate(self, w: np.ndarray) -> None:
        """Replace the iterate (invalidates a preparation)."""
        self.w = np.array(w, dtype=float).reshape(-1)
        self._prepared = False

    def prepare(self, D: np.ndarray, p: np.ndarray, bounds: tuple[np.ndarray, ...]) -> float:
        """Linearize at the current iterate: build the QP. Returns the wall time [s]."""
        self._resolve()
        t0 = time.perf_counter()
        self._in["w"][:] = self.w
        self._in["D"][:] = np.asarray(D, dtype=float).reshape(-1, order="F")
        self._in["p"][:] = p
        for name, b in zip(("lbw", "ubw", "lbg", "ubg"), bounds):
            self._in[name][:] = b
        self._prep_run()
        self._prepared = True
        return time.perf_counter() - t0

    def feedback(self, x0: np.ndarray | None = None, *, apply: bool = True) -> tuple[bool, str, int, float]:
        """Solve the prepared QP with ``x₀`` fixed to ``x0`` (None: as bounded); update ``w`` if ``apply``.

        Returns ``(success, status, qp_iterations, wall_time)``; on failure ``w`` is unchanged.
        """
        t0 = time.perf_counter()
        if not self._prepared:
            raise RuntimeError("feedback() needs a prepare() first.")
        if x0 is not None:
            sl = self.layout.x_index(0)
            self._out["lbdw"][sl] = self._out["ubdw"][sl] = x0 - self.w[sl]
        self._prepared = False
        o = self._out
        if not (np.all(np.isfinite(o["H"])) and np.all(np.isfinite(o["g"])) and np.all(np.isfinite(o["A"]))
                and not np.any(np.isnan(o["lba"])) and not np.any(np.isnan(o["uba"]))):
            return False, "nan", 0, time.perf_counter() - t0
        ok, status, iters = self._qp_call()
        if not ok:
            return False, status, iters, time.perf_counter() - t0
        if apply:
            self.w += self._dw
        return True, "success", iters, time.perf_counter() - t0

    @property
    def step_norm(self) -> float:
        """``‖Δw‖∞`` of the last feedback."""
        return float(np.max(np.abs(self._dw))) if self._dw.size else 0.0

    @property
    def cost(self) -> float:
        """Cost at the last linearization point."""
        return float(self._out["cost"][0])

    @property
    def violation(self) -> float:
        """Largest constraint violation at the last linearization point."""
        return float(self._out["violation"][0])

    # -------------------------------------------------------------- solving
    def iterate(self, D, p, bounds, x0=None) -> SolveResult:
        """One real-time iteration: prepare (if not done) and feedback."""
        t_prep = 0.0 if self._prepared else self.prepare(D, p, bounds)
        ok, status, qp_it, t_fb = self.feedback(x0)
        return SolveResult(self.w.copy(), ok, status, 1, self.cost, self.violation, qp_it,
                           {"preparation": t_prep, "feedback": t_fb, "qp_solver": self._qp_call.solver_time})

    def solve(self, D, p, bounds, x0=None, *, max_iter: int = 50, tol: float = 1e-8,
              line_search: bool = True) -> SolveResult:
        """Gauss–Newton iterations until ``‖Δw‖∞ ≤ tol (1 + ‖w‖∞)`` at a feasible point.

        With ``line_search`` (default) each step is shortened by backtracking on the
        ℓ₁ merit function ``cost + μ ‖violation‖₁`` (Armijo, μ above the largest QP
        multiplier), which makes the iteration converge from poor initial guesses;
        without it every step is a full step (what a real-time iteration does).
        """
        t_prep = t_fb = 0.0
        status, ok, qp_it, mu = "max_iterations", False, 0, 1.0
        lbw, ubw = (np.array(b, dtype=float) for b in bounds[:2])
        if x0 is not None:
            sl = self.layout.x_index(0)
            lbw[sl] = ubw[sl] = x0
        merit_bounds = (lbw, ubw, bounds[2], bounds[3])
        for it in range(1, max_iter + 1):
            t_prep += self.prepare(D, p, bounds) if not self._prepared else 0.0
            okq, st, qp_it, t = self.feedback(x0, apply=not line_search)
            t_fb += t
            if not okq:
                status = st
                break
            stalled = False
            if line_search:
                mu = max(mu, 1.1 * self._multiplier_norm())
                alpha = self._line_search(D, p, merit_bounds, mu)
                if alpha < self.MIN_STEP and self._multipliers_missing() and self.violation > max(1e-6, 1e3 * tol):
                    # infeasible and the solver gave no multipliers: μ may be below them, find them
                    mu = max(mu, 1.1 * self._multiplier_norm(stationary=True))
                    alpha = self._line_search(D, p, merit_bounds, mu)
                stalled = alpha < self.MIN_STEP        # near a solution: rounding; elsewhere a failure
                self._dw *= alpha
                self.w += self._dw
            if self.step_norm <= tol * (1.0 + np.max(np.abs(self.w))):
                t_prep += self.prepare(D, p, bounds)          # cost and violation at the converged point
                feasible = self.violation <= max(1e-6, 1e3 * tol)
                ok = feasible
                status = "success" if feasible else (
                    "infeasible: line search stalled" if stalled else "infeasible")
                break
        return SolveResult(self.w.copy(), ok, status, it, self.cost, self.violation, qp_it,
                           {"preparation": t_prep, "feedback": t_fb})

    def _multipliers_missing(self) -> bool:
        lam_a = self._qp_call.lam_a
        return bool(lam_a.size) and not np.any(lam_a)

    def _multiplier_norm(self, stationary: bool = False) -> float:
        """Largest multiplier of the last QP: the solver's or (``stationary``) from stationarity.

        CasADi 3.8's hpipm returns ``lam_a = 0`` for every row (measured): the ℓ₁ merit then kept μ = 1 below
        the true multipliers, the Gauss–Newton step stopped being a descent direction of the merit, the
        line search shrank it to nothing and the tiny step passed for convergence at an infeasible point
        (the turbine MHE's first solves, issue 22 item 14). ``H Δw + g + Aᵀλ_a + λ_x = 0`` gives ``λ_a``
        (least squares); :meth:`solve` asks for it when a line search fails with the solver's (zero) ``λ_a``.
        """
        q = self._qp_call
        lam_a, lam_x = q.lam_a, q.lam_x
        if not (np.all(np.isfinite(lam_a)) and np.all(np.isfinite(lam_x))):
            return 0.0
        if stationary and lam_a.size:
            lam_a = self._stationary_multipliers(lam_x)
        lam = np.concatenate([lam_a, lam_x])
        return float(np.max(np.abs(lam))) if lam.size and np.all(np.isfinite(lam)) else 0.0

    def _stationary_multipliers(self, lam_x: np.ndarray) -> np.ndarray:
        """``λ_a`` of the last QP from ``Aᵀλ_a = −(H Δw + g + λ_x)``: least squares by the normal equations
        ``A Aᵀ λ_a = A r`` (``A Aᵀ`` is banded and small; a tiny ridge keeps dependent rows solvable)."""
        H = _dense(self._H_sp, self._out["H"])
        A = _dense(self._A_sp, self._out["A"])
        r = -(H @ self._dw + self._out["g"] + lam_x)
        AAt = A @ A.T
        ridge = 1e-12 * max(float(np.trace(AAt)) / max(AAt.shape[0], 1), 1.0)
        return np.linalg.solve(AAt + ridge * np.eye(AAt.shape[0]), A @ r)

    def _merit(self, w, D, p, bounds, mu: float) -> tuple[float, float]:
        if self._merit_job is not None and self._merit_job.done():
            self._merit_fn = self._merit_job.result().function
            self._merit_job = None
        cost, viol = self._merit_fn(w, np.asarray(D, dtype=float), p, *bounds)
        return float(cost) + mu * float(viol), float(viol)

    def _line_search(self, D, p, bounds, mu: float) -> float:
        """Backtracking (Armijo, factor 1/2) on ``cost + μ ‖violation‖₁`` along the QP step."""
        phi0, viol0 = self._merit(self.w, D, p, bounds, mu)
        slope = float(self._out["g"] @ self._dw) - mu * viol0
        alpha = 1.0
        while alpha >= self.MIN_STEP:
            phi, _ = self._merit(self.w + alpha * self._dw, D, p, bounds, mu)
            if np.isfinite(phi) and phi <= phi0 + 1e-4 * alpha * min(slope, 0.0):
                break
            alpha *= 0.5
        return alpha


def _dense(sp, nonzeros: np.ndarray) -> np.ndarray:
    """A dense matrix of sparsity ``sp`` from its nonzeros (CasADi's column-major order)."""
    rows, cols = sp.get_triplet()
    M = np.zeros((sp.size1(), sp.size2()))
    M[rows, cols] = nonzeros
    return M
