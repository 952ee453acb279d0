"""Methods backed by CasADi's SUNDIALS interfaces.

``cvodes``: variable-order BDF (orders 1-5) with Newton iterations on the exact
Jacobian (CasADi's algorithmic differentiation of the rhs), in one call of
``casadi.integrator(name, "cvodes", dae, t0, tgrid, opts)`` over the whole
integration grid. CVODES keeps its step size and order across grid points.

Inputs: constant inputs are passed as extra parameters. Otherwise the
integration grid is the output grid ``t_out`` plus the grid points of table
inputs (and t = 0); on each grid interval ``[t_k, t_k+1]`` the input is the
straight line between ``u(t_k)`` and ``u(t_k+1)``, evaluated inside the ODE
with its explicit time (CasADi's per-interval controls carry ``u(t_k)``, the
slope and ``t_k``). Constant and table inputs are thus exact; callables are
interpolated linearly between grid points (error ~ dt_out^2 |u''| / 8), so
pass a finer ``t_out`` for inputs that vary within an output interval. CasADi
restarts CVODES at every grid point where controls are given (about 1.5-2x
the steps of an input-free run); a piecewise-linear interpolant inside the
ODE avoided the restarts but lost accuracy at the kinks (measured: 1e-5 vs
1e-8 error at rtol 1e-6 with 60 000 grid points), hence this choice.
"""

from __future__ import annotations

import hashlib
from typing import Any, ClassVar

import casadi as ca
import numpy as np

from ..exceptions import IntegrationError
from .base import Method, Trajectory, prepared, symbolic_rhs
from .checks import divergence_message, first_bad_column, raise_diverged

__all__ = ["Cvodes"]


class Cvodes(Method):
    """CVODES (SUNDIALS) BDF, adaptive step and order, tolerances ``rtol``/``atol``."""

    name: ClassVar[str] = "cvodes"
    order: ClassVar[int] = 5
    kind: ClassVar[str] = "adaptive"
    implicit: ClassVar[bool] = True
    #: Maximum number of internal steps per grid interval (CVODES ``mxstep``).
    max_num_steps: ClassVar[int] = 100_000

    def _grid(self) -> tuple[np.ndarray, np.ndarray]:
        """Integration grid (t = 0, output times, table knots) and the indices of ``t_out`` in it."""
        pr = self.problem
        tol = 1e-10 * pr.tmax
        base = np.unique(np.concatenate([[0.0], pr.t_out]))
        knots = pr.inputs.knots[pr.inputs.knots < pr.t_out[-1] - tol]
        if knots.size:
            near = np.abs(knots[:, None] - base[None, :]).min(axis=1) <= tol
            knots = knots[~near]
            knots = knots[np.concatenate([[True], np.diff(knots) > tol])] if knots.size else knots
        grid = np.unique(np.concatenate([base, knots]))
        return grid, np.searchsorted(grid, pr.t_out)

    def _prepare(self) -> tuple[Any, bool]:
        pr = self.problem
        grid, self._out_index = self._grid()
        self._tgrid = grid
        self._varying = pr.eom.n_u > 0 and not pr.inputs.constant
        key = (self.name, pr.rtol, pr.atol, self._varying, grid.size, hashlib.sha1(grid.tobytes()).hexdigest())
        return prepared(pr.eom, key, lambda: self._build(grid))

    def _build(self, grid: np.ndarray) -> ca.Function:
        eom, pr = self.problem.eom, self.problem
        sym, rhs = symbolic_rhs(eom)
        x = sym.sym("x", eom.n_x)
        if self._varying:
            p, t, c = sym.sym("p", eom.n_p), sym.sym("t"), sym.sym("c", 2 * eom.n_u + 1)  # c = [u(t_k); slope; t_k]
            u = c[: eom.n_u] + c[eom.n_u: 2 * eom.n_u] * (t - c[-1])
            dae = {"x": x, "p": p, "t": t, "u": c, "ode": rhs(x, u, p)}
        else:                                   # constant inputs: extra parameters [p; u]
            pu = sym.sym("p", eom.n_p + eom.n_u)
            dae = {"x": x, "p": pu, "ode": rhs(x, pu[eom.n_p:], pu[: eom.n_p])}
        opts = {"abstol": pr.atol, "reltol": pr.rtol, "linear_multistep_method": "bdf",
                "max_num_steps": self.max_num_steps, "disable_internal_warnings": True,
                "show_eval_warnings": False}     # failures raise IntegrationError instead
        return ca.integrator(f"{eom.name}_cvodes", "cvodes", dae, 0.0, grid, opts)

    def _controls(self, grid: np.ndarray) -> np.ndarray:
        """Per-interval input line ``[u(t_k); slope; t_k]``; column j drives (grid[j-1], grid[j]]."""
        n_u = self.problem.eom.n_u
        u = self.problem.inputs(grid)                                  # (n_grid, n_u)
        C = np.zeros((2 * n_u + 1, grid.size))
        if grid.size > 1:
            C[:n_u, 1:] = u[:-1].T
            C[n_u: 2 * n_u, 1:] = (np.diff(u, axis=0) / np.diff(grid)[:, None]).T
            C[-1, 1:] = grid[:-1]
        C[:n_u, 0] = u[0]
        return C

    def _integrate(self, integ: ca.Function) -> Trajectory:
        pr, eom = self.problem, self.problem.eom
        if self._varying:
            args = {"x0": pr.x0, "p": pr.p, "u": self._controls(self._tgrid)}
        else:
            args = {"x0": pr.x0, "p": np.concatenate([pr.p, pr.inputs.at(0.0)])}
        try:
            X = np.array(integ(**args)["xf"])
        except RuntimeError as exc:
            raise IntegrationError(self._failure(integ, args, exc)) from exc
        stats = integ.stats()
        bad = first_bad_column(X, pr.x0)
        if bad is not None:
            raise_diverged(self.name, float(self._tgrid[bad]), float(stats.get("hlast", np.nan)), X[:, bad],
                           eom.states, pr.x0)
        extra = {"n_lu": int(stats.get("nlinsetups", 0)), "n_error_test_failures": int(stats.get("netfails", 0))}
        return Trajectory(X[:, self._out_index].T.copy(), steps=int(stats["nsteps"]), n_rhs=int(stats["nfevals"]),
                          n_jac=int(stats.get("n_call_jacF", 0)), extra=extra)

    def _failure(self, integ: ca.Function, args: dict, exc: RuntimeError) -> str:
        """Explain a CVODES failure: its flag, where it stopped, and the last state it reached."""
        pr, eom = self.problem, self.problem.eom
        stats = integ.stats()
        t_fail, h = float(stats.get("tcur", np.nan)), float(stats.get("hcur", np.nan))
        flag = str(exc).rsplit("CVode returned", 1)[-1].split(".")[0].strip(' "') or "an error"
        head = f"method 'cvodes' failed near t = {t_fail:.6g} s (step size {h:.3g} s; CVODES returned {flag})."
        before = self._tgrid[self._tgrid < t_fail]
        if before.size < 2:
            return f"{head} It failed right after t = 0; check the initial state and the parameters."
        partial = self._build(before)
        part_args = dict(args)
        if "u" in part_args:
            part_args["u"] = part_args["u"][:, : before.size]
        try:
            X = np.array(partial(**part_args)["xf"])
        except RuntimeError:
            return head
        x_last = X[:, -1]
        bad = first_bad_column(X, pr.x0)
        if bad is not None:
            return divergence_message(self.name, float(before[bad]), h, X[:, bad], eom.states, pr.x0)
        i = int(np.argmax(np.abs(x_last) / (1.0 + np.abs(pr.x0))))
        rhs = np.array(eom.functions.rhs(x_last, pr.inputs.at(float(before[-1])), pr.p)).reshape(-1)
        nonfinite = [eom.states[j] for j in np.flatnonzero(~np.isfinite(rhs))]
        tail = (f" The rhs is not finite for {nonfinite} there." if nonfinite
                else " The solution may grow without bound, or the rhs may be undefined (NaN) just beyond this state.")
        return (f"{head} Last output at t = {before[-1]:.6g} s: state {eom.states[i]!r} = {x_last[i]:.4g} "
                f"(largest relative to x0).{tail}")
