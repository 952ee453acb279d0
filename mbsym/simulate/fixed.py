"""Fixed-step explicit methods, with the whole time loop inside CasADi.

One step is built in MX from ``eom.functions.rhs`` (expanded to SX when the
rhs is an SX Function, so the CasADi virtual machine runs it without call
overhead), and ``Function.mapaccum`` repeats it ``n_steps`` times. Inputs are
sampled beforehand at every stage time (``t_k + c_i h``) and passed as one
``(n_u, n_c * n_steps)`` array; parameters are passed once. States between
steps (an output time off the step grid) come from cubic Hermite interpolation
with the rhs at both ends (error O(h^4), the order of RK4).
"""

from __future__ import annotations

from typing import Any, ClassVar

import casadi as ca
import numpy as np

from .base import Method, Trajectory, prepared, stability_hint, symbolic_rhs
from .checks import first_bad_column, raise_diverged

__all__ = ["FixedStepMethod", "RK4"]


class FixedStepMethod(Method):
    """Base of explicit one-step methods with a constant step.

    Subclasses give the distinct stage-time fractions ``nodes`` (in [0, 1])
    and implement ``_step(x, U, p, h, rhs)``: one step from ``x`` with the
    inputs ``U[:, i]`` at ``t + nodes[i] h``.
    """

    kind: ClassVar[str] = "fixed-step"
    implicit: ClassVar[bool] = False
    nodes: ClassVar[tuple[float, ...]] = (0.0,)
    #: Right-hand-side evaluations per step.
    rhs_per_step: ClassVar[int] = 1
    #: Stability limit ``|lambda| h`` of the method (imaginary and negative real axes) [-].
    stability_radius: ClassVar[float] = 2.0

    def _step(self, x, U, p, h: float, rhs: ca.Function):
        raise NotImplementedError

    def _prepare(self) -> tuple[Any, bool]:
        pr = self.problem
        return prepared(pr.eom, (self.name, pr.dt, pr.n_steps), self._build_loop)

    def _build_loop(self) -> ca.Function:
        pr, eom = self.problem, self.problem.eom
        sym, rhs = symbolic_rhs(eom)
        x = ca.MX.sym("x", eom.n_x)
        U = ca.MX.sym("U", eom.n_u, len(self.nodes))
        p = ca.MX.sym("p", eom.n_p)
        step = ca.Function(f"{self.name}_step", [x, U, p], [self._step(x, U, p, pr.dt, rhs)],
                           ["x", "U", "p"], ["x_next"])
        if sym is ca.SX:
            step = step.expand()
        return step.mapaccum(f"{self.name}_loop", pr.n_steps)

    def _integrate(self, loop: ca.Function) -> Trajectory:
        pr, eom = self.problem, self.problem.eom
        h, n = pr.dt, pr.n_steps
        t_grid = h * np.arange(n + 1)
        t_grid[-1] = pr.tmax
        c = np.asarray(self.nodes)
        t_stage = (t_grid[:-1, None] + c[None, :] * h).reshape(-1)
        U = pr.inputs(t_stage).T                                   # (n_u, n_c * n)
        X = np.array(loop(pr.x0, U, pr.p))                         # (n_x, n)
        bad = first_bad_column(X, pr.x0)
        if bad is not None:
            hint = stability_hint(eom, pr, self.name, self.stability_radius)
            raise_diverged(self.name, float(t_grid[bad + 1]), h, X[:, bad], eom.states, pr.x0,
                           where=f"step {bad + 1} of {n}", hint=hint)
        X = np.hstack([pr.x0[:, None], X])                         # (n_x, n + 1) at t_grid
        x_out, n_extra = self._output(X, t_grid)
        return Trajectory(x_out, steps=n, n_rhs=self.rhs_per_step * n + n_extra, n_jac=0)

    def _output(self, X: np.ndarray, t_grid: np.ndarray) -> tuple[np.ndarray, int]:
        """States at ``t_out``: exact on the step grid, cubic Hermite in between."""
        pr = self.problem
        h = pr.dt
        k = np.clip(np.floor(pr.t_out / h + 1e-9).astype(int), 0, pr.n_steps)
        s = (pr.t_out - t_grid[k]) / h
        on_grid = np.abs(s) <= 1e-9
        if np.all(on_grid):
            return X[:, k].T.copy(), 0
        k = np.minimum(k, pr.n_steps - 1)
        s = (pr.t_out - t_grid[k]) / h
        need = np.unique(np.concatenate([k, k + 1]))
        F = np.zeros_like(X)
        F[:, need] = np.array(pr.eom.functions.rhs(X[:, need], pr.inputs(t_grid[need]).T, pr.p))
        h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
        h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
        x = h00 * X[:, k] + h10 * h * F[:, k] + h01 * X[:, k + 1] + h11 * h * F[:, k + 1]
        return x.T, int(need.size)


class RK4(FixedStepMethod):
    """The classical fourth-order Runge-Kutta method, fixed step ``dt``.

    Inputs are evaluated at the stage times ``t``, ``t + h/2``, ``t + h``.
    Stable for ``|lambda| h`` below about 2.78 (negative real axis; 2.83 on the
    imaginary axis), ``lambda`` the eigenvalues of the linearized system.
    """

    name: ClassVar[str] = "rk4"
    order: ClassVar[int] = 4
    nodes: ClassVar[tuple[float, ...]] = (0.0, 0.5, 1.0)
    rhs_per_step: ClassVar[int] = 4
    stability_radius: ClassVar[float] = 2.78

    def _step(self, x, U, p, h: float, rhs: ca.Function):
        k1 = rhs(x, U[:, 0], p)
        k2 = rhs(x + (h / 2) * k1, U[:, 1], p)
        k3 = rhs(x + (h / 2) * k2, U[:, 1], p)
        k4 = rhs(x + h * k3, U[:, 2], p)
        return x + (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4)
