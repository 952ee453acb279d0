"""``MHE``: moving-horizon estimation of states, unknown inputs and parameters, with an EKF arrival cost.

Over a window of ``M`` intervals (``M + 1`` measurements) the MHE solves

    min  ‖L₀ (z₀ − z̄₀)‖² + Σₖ ‖ξₖ‖² + Σₖ₌₀ᴹ ‖R^{-1/2} (h(zₖ, uₖ) − yₖ)‖²
    s.t. zₖ₊₁ = f(zₖ, uₖ) + G ξₖ,    G Gᵀ = Q

on the :class:`~mbsym.control.estimation.EstimationModel` (states, random-walk
unknown inputs, estimated parameters). The arrival cost ``(z̄₀, P₀ = (L₀ᵀL₀)⁻¹)`` is
the prior of the window's first node, updated by an EKF as the window slides:
the dropped measurement corrects it and the dropped interval propagates it.
While the window fills, the estimates come from an EKF run on all data.

It is a :class:`~mbsym.control.stages.StageProblem` (noise ``ξ`` as the stage
"controls", inputs and measurements as stage parameters), solved by the same
solvers as :class:`~mbsym.control.nmpc.NMPC`: real-time iterations (default; one
Gauss–Newton QP per sample, warm-started with the shifted window), a converged
Gauss–Newton SQP, or ipopt/fatrop.
"""

from __future__ import annotations

import time
from collections import deque
from typing import Any, Mapping, Sequence

import casadi as ca
import numpy as np

from ..exceptions import ControlDefinitionError
from ._checks import bound_pair, positive_int
from .estimation import EKF, EstimationModel
from .nlpsolvers import NlpSolver
from .nmpc import StepStats, make_solver
from .stages import StageProblem

__all__ = ["MHE"]


def _root(cov: np.ndarray) -> np.ndarray:
    """``G`` with ``G Gᵀ = cov``, zero directions dropped (n × rank)."""
    lam, V = np.linalg.eigh(0.5 * (cov + cov.T))
    keep = lam > 1e-14 * max(1.0, lam.max(initial=0.0))
    return V[:, keep] * np.sqrt(lam[keep])


class MHE:
    """Moving-horizon estimator.

    Parameters
    ----------
    model : model or EstimationModel
        Anything :func:`mbsym.as_dynamics` accepts (then ``dt``, ``measurements``,
        ``unknown_inputs``, ``parameters``, ``p``, ``substeps`` build the
        :class:`EstimationModel`).
    window : int, keyword-only
        Number of intervals M (≥ 1); the window holds M + 1 measurements.
    process_noise, measurement_noise : dict or array, keyword-only
        Standard deviations by name or covariance matrices (see :class:`EKF`).
        Process noise per sample; entries without noise are exactly propagated.
    x0, P0 : optional, keyword-only
        Prior mean and standard deviations/covariance at the first sample.
    bounds : dict, optional, keyword-only
        ``{name: (lower, upper)}`` on estimated entries (e.g. a non-negative wind speed).
    solver, qp_solver, max_iter, compile, solver_options
        As for :class:`~mbsym.control.nmpc.NMPC` (default real-time iterations with hpipm).

    Attributes
    ----------
    names : tuple of str
        Names of the estimate.
    stats : list of StepStats

    Examples
    --------
    >>> import casadi as ca, mbsym as mb
    >>> x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    >>> dyn = mb.Dynamics(ca.Function("f", [x, u, p], [ca.vertcat(x[1], u)]), states=["pos", "vel"], inputs=["a"])
    >>> mhe = MHE(dyn, dt=0.1, window=5, measurements=["pos"], process_noise={"vel": 0.01},
    ...           measurement_noise={"pos": 0.01}, compile=False)
    >>> for k in range(8):
    ...     z = mhe.step([0.1 * k], [0.0])
    >>> round(float(z[1]), 2)            # constant speed 1 m/s
    1.0
    """

    def __init__(self, model: Any, *, window: int, process_noise: Any, measurement_noise: Any,
                 dt: float | None = None, measurements: Sequence[str] = (), unknown_inputs: Sequence[str] = (),
                 parameters: Sequence[str] = (), p: Mapping[str, float] | None = None, substeps: int = 1,
                 x0=None, P0=None, bounds: Mapping[str, tuple] | None = None, solver: str = "rti",
                 qp_solver: str = "hpipm", max_iter: int | None = None, solver_options: Mapping[str, Any] | None = None,
                 compile: bool = True) -> None:
        if isinstance(model, EstimationModel):
            self.model = model
        else:
            if dt is None:
                raise ControlDefinitionError("dt [s] is required to build the estimation model.")
            self.model = EstimationModel(model, dt=dt, measurements=measurements, unknown_inputs=unknown_inputs,
                                         parameters=parameters, p=p, substeps=substeps)
        m = self.model
        self.window = positive_int(window, "window")
        self._ekf = EKF(m, dt=m.dt, measurements=m.measurements, process_noise=process_noise,
                        measurement_noise=measurement_noise, x0=x0, P0=P0)
        self._arrival = (self._ekf.x.copy(), self._ekf.P.copy())          # prior of the window's first node
        self._lag = EKF(m, dt=m.dt, measurements=m.measurements, process_noise=self._ekf.Q,
                        measurement_noise=self._ekf.R)                    # propagates the arrival cost
        self._G = _root(self._ekf.Q)
        self._Rinv_root = np.linalg.inv(np.linalg.cholesky(self._ekf.R))   # ‖R^{-1/2} e‖
        self._lb, self._ub = self._bounds(bounds)
        self._P = self._problem()
        self.solver = solver
        self._max_iter = max_iter
        self._engine = make_solver(self._P, solver, qp_solver=qp_solver, hessian="exact", max_iter=max_iter,
                                   tol=1e-8, options=solver_options, compile=compile)
        self._data: deque = deque(maxlen=self.window + 1)        # (u given with y, y)
        self._history: deque = deque(maxlen=self.window + 1)     # EKF estimates (window initialization)
        self._w: np.ndarray | None = None
        self.stats: list[StepStats] = []
        self.failures = 0
        self.x = self._ekf.x.copy()

    names = property(lambda self: self.model.names, doc="Names of the estimate.")
    build_time = property(lambda self: self._engine.build_time, doc="Seconds spent building the solver.")

    def _bounds(self, bounds) -> tuple[np.ndarray, np.ndarray]:
        lb, ub = np.full(self.model.n_z, -np.inf), np.full(self.model.n_z, np.inf)
        for name, pair in dict(bounds or {}).items():
            if name not in self.model.names:
                raise ControlDefinitionError(f"bounds name unknown entry {name!r}; entries are "
                                             f"{list(self.model.names)}.")
            if not isinstance(pair, (tuple, list)) or len(pair) != 2:
                raise ControlDefinitionError(f"bounds[{name!r}] must be (lower, upper); got {pair!r}.")
            lo, hi = bound_pair(pair[0], pair[1], 1, f"bounds of {name!r}")
            i = self.model.names.index(name)
            lb[i], ub[i] = lo[0], hi[0]
        return lb, ub

    def _problem(self) -> StageProblem:
        m = self.model
        nz, nk, ny, nr = m.n_z, len(m.known_inputs), m.n_y, len(m.p_rest)
        sym = ca.SX if m.step_function.is_a("SXFunction") and m.measurement_function.is_a("SXFunction") else ca.MX
        z, xi = sym.sym("z", nz), sym.sym("xi", self._G.shape[1])
        d, p = sym.sym("d", 2 * nk + ny), sym.sym("p", nr + nz + nz * nz)
        u_dyn, u_meas, y = d[:nk], d[nk:2 * nk], d[2 * nk:]
        pr, zbar, L0 = p[:nr], p[nr:nr + nz], ca.reshape(p[nr + nz:], nz, nz)
        e = ca.mtimes(ca.DM(self._Rinv_root), m.measurement_function(z, u_meas, pr) - y)
        f = m.step_function(z, u_dyn, pr) + ca.mtimes(ca.DM(self._G), xi)
        empty = sym(0, 1)
        path = ca.Function("mhe_stage", [z, xi, d, p], [f, empty, ca.vertcat(xi, e), sym.zeros(1, 1)],
                           ["x", "u", "d", "p"], ["f", "c", "r", "l"])
        term = ca.Function("mhe_terminal", [z, d, p], [empty, e, sym.zeros(1, 1)], ["x", "d", "p"], ["c", "r", "l"])
        init = ca.Function("mhe_arrival", [z, p], [ca.mtimes(L0, z - zbar)], ["x", "p"], ["r0"])
        n_xi = self._G.shape[1]
        return StageProblem(self.window, path, term, init, self._lb, self._ub, np.full(n_xi, -np.inf),
                            np.full(n_xi, np.inf), np.zeros(0), np.zeros(0), np.zeros(0, dtype=bool), np.zeros(0),
                            np.zeros(0), names={"x": list(m.names), "u": [f"noise_{i}" for i in range(n_xi)],
                                                "d": [f"u_dyn:{n}" for n in m.known_inputs] +
                                                [f"u_meas:{n}" for n in m.known_inputs] + list(m.measurements),
                                                "p": list(m.fixed_parameters) + [f"prior:{n}" for n in m.names] +
                                                [f"L0_{i}" for i in range(nz * nz)]},
                            dynamics_jacobian=self._dynamics_jacobian(d.numel(), p.numel()))

    def _dynamics_jacobian(self, n_d: int, n_p: int) -> ca.Function | None:
        """``(z, ξ, d, p) -> (f, ∂f/∂[z; ξ])`` from the model's chained step Jacobian (None without one)."""
        m = self.model
        if m.step_jacobian is None:
            return None
        nk, nr = len(m.known_inputs), len(m.p_rest)
        z, xi = ca.MX.sym("z", m.n_z), ca.MX.sym("xi", self._G.shape[1])
        d, p = ca.MX.sym("d", n_d), ca.MX.sym("p", n_p)
        zn, F = m.step_jacobian(z, d[:nk], p[:nr])
        G = ca.DM(self._G)
        return ca.Function("mhe_dynamics_jacobian", [z, xi, d, p], [zn + ca.mtimes(G, xi), ca.horzcat(F, G)],
                           ["x", "u", "d", "p"], ["f", "J"])

    # ------------------------------------------------------------------ step
    def step(self, y, u=None) -> np.ndarray:
        """Add the measurement ``y`` (and the known inputs ``u`` of the last interval); the current estimate.

        Returns
        -------
        ndarray (n_z)
            Estimate at the current sample, in the order of :attr:`names`.
        """
        t0 = time.perf_counter()
        m = self.model
        yv, uv = m.measurement_vector(y), m.known_input_vector(u)
        x_ekf = self._ekf.step(yv, uv)
        if len(self._data) == self._data.maxlen:        # the window slides: update the arrival cost
            self._slide_arrival()
        self._data.append((uv, yv))
        self._history.append(x_ekf)
        if len(self._data) < self.window + 1:
            self.x = x_ekf
            self.stats.append(StepStats(time.perf_counter() - t0, 0.0, 0.0, 0, 0, "ekf (window filling)", True,
                                        np.nan, 0.0, False))
            return self.x.copy()
        result = self._solve()
        fallback = not result.success
        if result.success:
            X, _ = self._P.layout.split(result.w)
            self.x = X[:, -1].copy()
            self._w = result.w
        else:
            self.failures += 1
            self.x = x_ekf
            self._w = None                               # next solve starts again from the EKF history
        times = result.times
        self.stats.append(StepStats(time.perf_counter() - t0, times.get("preparation", 0.0),
                                    times.get("feedback", times.get("solver", 0.0)), result.iterations,
                                    result.qp_iterations, result.status if result.success else
                                    f"fallback to EKF ({result.status})", result.success, result.cost,
                                    result.violation, fallback))
        return self.x.copy()

    def _slide_arrival(self) -> None:
        """The first node leaves the window: correct its prior with its measurement, propagate one interval."""
        u0, y0 = self._data[0]
        u1 = self._data[1][0]                            # inputs held over the dropped interval
        self._lag.x, self._lag.P = self._arrival
        self._lag.correct(y0, u0)
        self._lag.predict(u1)
        self._arrival = (self._lag.x.copy(), self._lag.P.copy())

    def _parameters(self) -> tuple[np.ndarray, np.ndarray]:
        m = self.model
        data = list(self._data)
        us = np.array([d[0] for d in data]).T.reshape(len(m.known_inputs), -1)
        ys = np.array([d[1] for d in data]).T
        u_dyn = np.concatenate([us[:, 1:], us[:, -1:]], axis=1)      # interval k: inputs given with y_{k+1}
        D = np.concatenate([u_dyn, us, ys], axis=0)
        zbar, P = self._arrival
        info = np.linalg.inv(0.5 * (P + P.T))
        L0 = np.linalg.cholesky(0.5 * (info + info.T) + 1e-12 * np.eye(m.n_z)).T      # L0ᵀL0 = P⁻¹
        return D, np.concatenate([m.p_rest, zbar, L0.reshape(-1, order="F")])

    def _initial_window(self) -> np.ndarray:
        """The window from the EKF estimates, noise fitted to their differences."""
        L = self._P.layout
        Z = np.array(self._history).T
        D, _ = self._parameters()
        n_u = len(self.model.known_inputs)
        pred = np.column_stack([np.asarray(self.model.step_function(Z[:, k], D[:n_u, k], self.model.p_rest)).ravel()
                                for k in range(self.window)])
        Xi = np.linalg.lstsq(self._G, Z[:, 1:] - pred, rcond=None)[0] if self._G.shape[1] else \
            np.zeros((0, self.window))
        return L.join(Z, Xi)

    def _shifted_window(self) -> np.ndarray:
        L = self._P.layout
        X, U = L.split(self._w)
        D, _ = self._parameters()
        n_u = len(self.model.known_inputs)
        x_new = np.asarray(self.model.step_function(X[:, -1], D[:n_u, -2], self.model.p_rest)).ravel()
        X = np.concatenate([X[:, 1:], x_new[:, None]], axis=1)
        U = np.concatenate([U[:, 1:], np.zeros((U.shape[0], 1))], axis=1)
        return L.join(X, U)

    def _solve(self):
        D, p = self._parameters()
        bounds = self._P.bounds()
        first = self._w is None
        w = self._initial_window() if first else self._shifted_window()
        if isinstance(self._engine, NlpSolver):
            return self._engine.solve(w, D, p, bounds)
        self._engine.set_iterate(w)
        if self.solver == "sqp" or first:
            r = self._engine.solve(D, p, bounds, None, max_iter=self._max_iter or 50, tol=1e-8)
            if first and self.solver == "rti" and r.status == "max_iterations":
                r.success, r.status = True, "warm-up: max_iterations"
            return r
        return self._engine.iterate(D, p, bounds)

    def estimate(self) -> dict:
        """The current estimate by name."""
        return dict(zip(self.model.names, self.x.tolist()))

    def summary(self) -> dict:
        """Step-time median/max [s] of the MHE solves after the first one (window full), the first solve, failures."""
        solves = [s.wall_s for s in self.stats if s.iterations > 0]
        walls = np.array(solves[1:]) if len(solves) > 1 else np.zeros(1)
        return {"steps": len(self.stats), "failures": self.failures, "step_median_s": float(np.median(walls)),
                "step_max_s": float(np.max(walls)), "first_solve_s": float(solves[0]) if solves else 0.0,
                "solver": self.solver}
