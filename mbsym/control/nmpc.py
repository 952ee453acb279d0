"""``NMPC``: receding-horizon control with warm start, shift, statistics and a documented fallback.

Solvers (``solver=``):

- ``"rti"`` (default): real-time iterations of a Gauss–Newton SQP (one QP per
  sample, structure-exploiting ``hpipm`` by default). The first step converges
  a globalized SQP from the initial guess (``warmup_iterations``); later steps
  do one iteration from the shifted previous solution. :meth:`NMPC.prepare`
  linearizes ahead of the measurement, :meth:`NMPC.step` then only solves the QP
  (the *feedback*).
- ``"sqp"``: the same Gauss–Newton SQP iterated to convergence (line search) every step.
- ``"ipopt"``, ``"fatrop"``, ``"sqpmethod"``: CasADi NLP solvers, converged.

Failures (QP or NLP failure, maximum iterations, NaN) are reported in the step's
:class:`StepStats` and counted; the input applied is then the **previous
solution shifted** (its next planned input), and the next step starts from that
shifted plan. Before any successful step the fallback is the last applied input
(or ``hold``).

**Deadline** (``deadline=`` seconds of wall time per step): a step whose solution took longer is
a *miss*: it arrived too late to be applied, so the step applies the previous plan's next input
(``hold`` or the last input when there is no plan) and counts the miss
(:attr:`NMPC.deadline_misses`, ``status`` ``"fallback (deadline missed ...)"``); the late
solution becomes the plan and warm start of the next step (by then it has arrived), so the next
step is again one bounded real-time iteration. The first step, the start-up (a converged,
globalized SQP from the initial guess), is not held to it. The work of a real-time iteration is
bounded: one linearization and one QP of at most 50 interior-point iterations (hpipm
``iter_max``).
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass
from typing import Any, Mapping

import numpy as np

from ..exceptions import ControlDefinitionError
from ._checks import finite_number, positive_int, vector
from .nlpsolvers import NLP_SOLVERS, NlpSolver
from .ocp import OCP
from .qp import QP_SOLVERS
from .sqp import GaussNewtonSQP, SolveResult

__all__ = ["NMPC", "StepStats", "SOLVERS"]

#: Solver names accepted by :class:`NMPC` (and :class:`~mbsym.control.mhe.MHE`).
SOLVERS = ("rti", "sqp") + NLP_SOLVERS


@dataclass(frozen=True)
class StepStats:
    """Statistics of one controller (or estimator) step.

    Attributes
    ----------
    wall_s : float
        Wall time of the whole step [s] (preparation included when it ran inside the step).
    preparation_s, feedback_s : float
        Real-time iterations: linearization and QP solve [s] (NLP solvers: 0 and the solver time).
    iterations : int
        SQP or NLP iterations.
    qp_iterations : int
        Iterations of the last QP.
    status : str
        ``"success"`` or what failed (``"qp_failed: ..."``, ``"max_iterations"``, ``"nan"``, ``"infeasible ..."``).
    success : bool
    cost : float
        Cost at the (last) linearization point or at the NLP solution.
    violation : float
        Largest constraint violation there.
    fallback : bool
        True when the applied input came from the previous shifted solution.
    qp_solver_s : float
        Time inside the QP solver as it reports it (``t_wall_solver``) [s]; 0 when unknown.
    """

    wall_s: float
    preparation_s: float
    feedback_s: float
    iterations: int
    qp_iterations: int
    status: str
    success: bool
    cost: float
    violation: float
    fallback: bool
    qp_solver_s: float = 0.0

    def as_dict(self) -> dict:
        return asdict(self)


def make_solver(problem, solver: str, *, qp_solver: str, hessian: str, max_iter: int | None, tol: float,
                options: Mapping[str, Any] | None, compile: bool):
    """A Gauss–Newton SQP engine or an :class:`NlpSolver` for ``solver``."""
    if solver not in SOLVERS:
        raise ControlDefinitionError(f"solver must be one of {list(SOLVERS)}; got {solver!r}.")
    if qp_solver not in QP_SOLVERS:
        raise ControlDefinitionError(f"qp_solver must be one of {list(QP_SOLVERS)}; got {qp_solver!r}.")
    if solver in ("rti", "sqp"):
        if hessian != "gauss-newton" and hessian != "exact":
            raise ControlDefinitionError(f"hessian must be 'exact' or 'gauss-newton'; got {hessian!r}.")
        return GaussNewtonSQP(problem, qp_solver=qp_solver, qp_options=options, compile=compile)
    return NlpSolver(problem, solver, hessian=hessian, qp_solver=qp_solver, max_iter=max_iter or 100, tol=tol,
                     options=options, compile=compile)


class NMPC:
    """Nonlinear model-predictive controller on an :class:`~mbsym.control.ocp.OCP`.

    On a failed step the next input of the previous plan is applied; after
    :attr:`MAX_FALLBACKS` failures in a row (or before any success) the last input
    is held and the next step starts again from a fresh initial guess (for
    ``"rti"``: with the globalized warm-up).

    Parameters
    ----------
    ocp : OCP
    solver : str, keyword-only
        One of :data:`SOLVERS` (default ``"rti"``).
    qp_solver : str, keyword-only
        QP solver of ``"rti"``/``"sqp"``/``"sqpmethod"`` (default ``"hpipm"``).
    hessian : {"exact", "gauss-newton"}, keyword-only
        NLP solvers only (RTI/SQP are always Gauss–Newton).
    max_iter : int, optional, keyword-only
        Iterations per step of the converged solvers (default 50 for ``"sqp"``, 100 otherwise).
    tol : float, keyword-only
        Convergence tolerance of the converged solvers.
    warmup_iterations : int, keyword-only
        ``"rti"``: iterations of the globalized SQP at the first step (default 200).
    p : dict, optional, keyword-only
        Model parameter values by name (the model's defaults fill the gaps).
    u_prev : array, optional, keyword-only
        Input applied before the first step (rate terms; fallback); default: the model's nominal inputs.
    solver_options : dict, optional, keyword-only
        Options of the QP solver (``"rti"``, ``"sqp"``) or of the nlpsol.
    compile : bool, keyword-only
        Compile the solver Functions (generated C, disk cache). Default True.
    deadline : float, optional, keyword-only
        Wall time allowed per step [s] (after the first); a later result is not applied (see the module
        docstring). Default None: no deadline.
    hold : array, optional, keyword-only
        Input applied when no plan is left to fall back on (before any success, or after
        :attr:`MAX_FALLBACKS` failures in a row); default the last applied input. A controller of
        rates holds zero, for example.

    Attributes
    ----------
    stats : list of StepStats
        One per call of :meth:`step`.
    failures : int
        Steps whose solve failed (they fell back to the previous shifted solution).
    deadline_misses : int
        Steps whose solution came after the deadline (they fell back too; not counted in ``failures``).

    Examples
    --------
    >>> import casadi as ca, mbsym as mb
    >>> x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    >>> dyn = mb.Dynamics(ca.Function("f", [x, u, p], [ca.vertcat(x[1], u)]), states=["pos", "vel"], inputs=["force"])
    >>> ocp = OCP(dyn, horizon=20, dt=0.1).track({"pos": 1.0, "vel": 0.1, "force": 0.01}).bound("force", -1, 1)
    >>> mpc = NMPC(ocp, compile=False)
    >>> u = mpc.step([1.0, 0.0])
    >>> bool(-1.0 <= u[0] < 0.0), mpc.stats[-1].status
    (True, 'success')
    """

    #: Consecutive failed steps served from the previous plan before starting over.
    MAX_FALLBACKS = 5

    def __init__(self, ocp: OCP, *, solver: str = "rti", qp_solver: str = "hpipm", hessian: str = "exact",
                 max_iter: int | None = None, tol: float = 1e-8, warmup_iterations: int = 200,
                 p: Mapping[str, float] | None = None, u_prev=None, solver_options: Mapping[str, Any] | None = None,
                 compile: bool = True, deadline: float | None = None, hold=None) -> None:
        if not isinstance(ocp, OCP):
            raise TypeError(f"ocp must be an mbsym.control.OCP; got {type(ocp).__name__}.")
        self._ocp = ocp
        self._tr = ocp.transcribe()
        self._P = self._tr.problem
        dyn = self._tr.dynamics
        self._p = dyn.parameter_vector(p)
        u_nom = dyn.u0[[dyn.inputs.index(n) for n in self._tr.controls]]
        self._u_prev = u_nom if u_prev is None else vector(u_prev, len(self._tr.controls), "u_prev",
                                                           self._tr.controls)
        self._D = self._tr.stage_parameters()
        self._bounds = self._P.bounds()
        self.solver = solver
        self._max_iter = positive_int(max_iter, "max_iter") if max_iter is not None else (50 if solver == "sqp"
                                                                                           else 100)
        self._tol = float(tol)
        self._warmup = positive_int(warmup_iterations, "warmup_iterations")
        self._engine = make_solver(self._P, solver, qp_solver=qp_solver, hessian=hessian, max_iter=self._max_iter,
                                   tol=self._tol, options=solver_options, compile=compile)
        self._w: np.ndarray | None = None          # warm start (NLP solvers) / iterate
        self._plan: np.ndarray | None = None       # last successful solution
        self._since = 0                            # steps since that solution
        self._prepared_for: tuple | None = None
        self.deadline = None if deadline is None else finite_number(deadline, "deadline [s]", nonnegative=True)
        self._hold = None if hold is None else vector(hold, len(self._tr.controls), "hold", self._tr.controls)
        self.stats: list[StepStats] = []
        self.failures = 0
        self.deadline_misses = 0
        self._streak = 0                           # consecutive failures

    # ------------------------------------------------------------ description
    ocp = property(lambda self: self._ocp, doc="The optimal control problem.")
    transcription = property(lambda self: self._tr, doc="Its discrete form.")
    inputs = property(lambda self: self._tr.controls, doc="Names of the inputs this controller sets.")
    sample_time = property(lambda self: self._tr.dt, doc="Sample time [s] (zero-order hold).")
    build_time = property(lambda self: self._engine.build_time, doc="Seconds spent building the solver.")
    compiled = property(lambda self: self._engine.compiled, doc="Whether the solver runs compiled code.")

    def __repr__(self) -> str:
        return f"NMPC({self._ocp!r}, solver={self.solver!r}, steps={len(self.stats)}, failures={self.failures})"

    # ------------------------------------------------------------ parameters
    def _update(self, p, preview, reference) -> bool:
        """Take new parameters/previews/references (all checked before any is stored); True if anything changed."""
        new_p = self._tr.dynamics.parameter_vector(p) if p is not None else self._p
        new_D = self._D
        if preview is not None or reference is not None:
            new_D = self._tr.stage_parameters(preview, reference)
            nd = len(self._tr.disturbances)
            if preview is None:        # keep the previous disturbance rows
                new_D[:nd] = self._D[:nd]
            if reference is None:      # keep the previous references
                new_D[nd:] = self._D[nd:]
        changed = not (np.array_equal(new_p, self._p) and np.array_equal(new_D, self._D))
        self._p, self._D = new_p, new_D
        return changed

    def prepare(self, *, p: Mapping[str, float] | None = None, preview: Mapping[str, Any] | None = None,
                reference: Mapping[str, Any] | None = None) -> float:
        """RTI preparation before the next measurement (linearize at the shifted solution); returns seconds.

        Values given here (parameters, previews, references) persist for the next
        steps. Other solvers: only stores the values (returns 0).
        """
        self._update(p, preview, reference)
        if self.solver != "rti" or self._w is None:
            return 0.0
        self._engine.set_iterate(self._w)
        seconds = self._engine.prepare(self._D, self._p, self._bounds)
        self._prepared_for = (self._D.copy(), self._p.copy())
        return seconds

    # ------------------------------------------------------------------ step
    def step(self, x, *, p: Mapping[str, float] | None = None, preview: Mapping[str, Any] | None = None,
             reference: Mapping[str, Any] | None = None) -> np.ndarray:
        """Controls for the measured state ``x`` (model state order); warm start, shift and statistics.

        Parameters
        ----------
        x : array (n_x) or dict
            Measured (or estimated) state.
        p : dict, optional
            Parameter values by name (persist).
        preview : dict, optional
            Disturbance inputs by name: one value or N+1 values (stages 0..N); persist.
        reference : dict, optional
            References of tracked signals by name: one value or N+1 values; persist.

        Returns
        -------
        ndarray (n_controls)
            In the order of :attr:`inputs`.
        """
        t0 = time.perf_counter()
        x = self._tr.dynamics.state_vector(x) if isinstance(x, Mapping) else \
            vector(x, self._tr.dynamics.n_x, "x", self._tr.dynamics.states)
        self._update(p, preview, reference)
        xa = self._tr.augmented_state(x, self._u_prev)
        result = self._solve(xa)
        elapsed = time.perf_counter() - t0
        if self.deadline is not None and self.stats and elapsed > self.deadline and result.success:
            u, fallback = self._late(result)
            result.status = f"deadline missed ({elapsed * 1e3:.3g} ms > {self.deadline * 1e3:.3g} ms)"
        else:
            u, fallback = self._apply(result)
        times = result.times
        prep = times.get("preparation", 0.0)
        fb = times.get("feedback", times.get("solver", 0.0))
        st = StepStats(time.perf_counter() - t0, prep, fb, result.iterations, result.qp_iterations,
                       result.status if not fallback else f"fallback ({result.status})", not fallback,
                       result.cost, result.violation, fallback, times.get("qp_solver", 0.0))
        self.stats.append(st)
        return u

    def __call__(self, t: float, y) -> np.ndarray:
        """Controller protocol of a simulation loop: ``controller(t, y) -> u`` with ``y`` the measured state.

        ``t`` [s] is not used (the controller is time-invariant); the returned
        values are the inputs :attr:`inputs`, to be held for :attr:`sample_time`.
        """
        return self.step(y)

    def _solve(self, xa: np.ndarray) -> SolveResult:
        if self._w is None:
            self._w = self._tr.initial_guess(xa, self._u_prev)
            if self.solver == "rti":           # first step: a globalized SQP from the initial guess
                self._engine.set_iterate(self._w)
                r = self._engine.solve(self._D, self._p, self._bounds, xa, max_iter=self._warmup, tol=1e-6)
                if r.status == "max_iterations":    # not converged, but every QP solved: RTI continues from it
                    r.success, r.status = True, "warm-up: max_iterations"
                return r
        if self.solver in ("rti", "sqp"):
            prepared = self._prepared_for is not None and np.array_equal(self._prepared_for[0], self._D) \
                and np.array_equal(self._prepared_for[1], self._p)
            if not prepared:
                self._engine.set_iterate(self._w)
            self._prepared_for = None
            if self.solver == "rti":
                return self._engine.iterate(self._D, self._p, self._bounds, xa)
            return self._engine.solve(self._D, self._p, self._bounds, xa, max_iter=self._max_iter, tol=self._tol)
        return self._engine.solve(self._w, self._D, self._p, self._bounds, xa)

    def _late(self, result: SolveResult) -> tuple[np.ndarray, bool]:
        """A solution that came after the deadline: apply the previous plan's next input (``hold`` or the last input
        without a plan); the late solution is the plan and warm start from the next step on (it will have arrived)."""
        L, nc = self._P.layout, len(self._tr.controls)
        self.deadline_misses += 1
        if self._plan is None:
            u = self._hold.copy() if self._hold is not None else self._u_prev.copy()
        else:
            u = np.clip(L.split(L.shift(self._plan))[1][:nc, 0], self._P.lbu[:nc], self._P.ubu[:nc])
        self._plan, self._streak = result.w.copy(), 0
        self._w = L.shift(self._plan)
        if isinstance(self._engine, NlpSolver):
            self._engine.shift_multipliers()
        self._u_prev = u
        return u.copy(), True

    def _apply(self, result: SolveResult) -> tuple[np.ndarray, bool]:
        """The input to apply and the next warm start; on failure the previous plan, shifted."""
        L, nc = self._P.layout, len(self._tr.controls)
        ok = result.success and bool(np.all(np.isfinite(result.w)))
        fallback = not ok
        if ok:
            self._plan, self._streak = result.w.copy(), 0
        else:
            self.failures += 1
            self._streak += 1
            if self._plan is None or self._streak > self.MAX_FALLBACKS:
                # nothing (left) to fall back on: hold; the next step initializes again
                self._w = self._plan = None
                if self._hold is not None:
                    self._u_prev = self._hold.copy()
                return self._u_prev.copy(), True
            self._plan = L.shift(self._plan)        # its next planned input is the fallback
        u = np.clip(L.split(self._plan)[1][:nc, 0], self._P.lbu[:nc], self._P.ubu[:nc])   # QP tolerance
        self._w = L.shift(self._plan)
        if isinstance(self._engine, NlpSolver) and result.success:
            self._engine.shift_multipliers()
        self._u_prev = u
        return u.copy(), fallback

    # -------------------------------------------------------------- results
    def prediction(self) -> dict:
        """The last solution: ``t`` (N+1) [s], ``x`` (n_x, N+1) and ``u`` (n_controls, N) by name lists."""
        if self._plan is None:
            raise RuntimeError("no successful step yet: call step() first.")
        X, U = self._P.layout.split(self._plan)
        nx, nc = self._tr.dynamics.n_x, len(self._tr.controls)
        return {"t": np.arange(self._P.N + 1) * self._tr.dt, "x": X[:nx].copy(), "u": U[:nc].copy(),
                "states": self._tr.dynamics.states, "inputs": self._tr.controls}

    def summary(self) -> dict:
        """Step-time median/max [s], failures and steps (JSON-friendly)."""
        walls = np.array([s.wall_s for s in self.stats]) if self.stats else np.zeros(1)
        return {"steps": len(self.stats), "failures": self.failures, "step_median_s": float(np.median(walls)),
                "step_max_s": float(np.max(walls)), "solver": self.solver, "deadline_s": self.deadline,
                "deadline_misses": self.deadline_misses}

    def as_controller(self, *, estimator=None, name: str = "nmpc"):
        """This NMPC (with ``estimator``) as a :class:`mbsym.simulate.DiscreteController`
        (:func:`~mbsym.control.in_loop.nmpc_controller`); ``mb.simulate(..., controller=mpc)`` and
        ``controller=(estimator, mpc)`` call it."""
        from .in_loop import nmpc_controller

        return nmpc_controller(self, estimator=estimator, name=name)

    def reset(self, *, u_prev=None) -> None:
        """Forget the warm start, the plan and the statistics (next step initializes again)."""
        if u_prev is not None:
            self._u_prev = vector(u_prev, len(self._tr.controls), "u_prev", self._tr.controls)
        self._w = self._plan = None
        self._prepared_for = None
        self.stats, self.failures, self._streak, self.deadline_misses = [], 0, 0, 0
