"""Methods from ``scipy.integrate``: independent references for the CasADi-backed ones.

``scipy-radau`` runs scipy's Radau IIA (order 5, implicit, adaptive) step by
step, with the exact Jacobian of the rhs from CasADi and the inputs evaluated at
every rhs call. Each accepted step is checked for finiteness; output times come
from scipy's dense output. Its cost is dominated by the Python call per rhs
evaluation (~20-30 us): use it as a reference, not for long runs.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from scipy.integrate import Radau

from ..exceptions import IntegrationError
from .base import BufferedFunction, Method, Trajectory, dense_rhs, jacobian_function, prepared
from .checks import divergence_message, first_bad_column

__all__ = ["ScipyRadau"]


class ScipyRadau(Method):
    """scipy's ``Radau`` (implicit Runge-Kutta Radau IIA, order 5) with the CasADi Jacobian."""

    name: ClassVar[str] = "scipy-radau"
    order: ClassVar[int] = 5
    kind: ClassVar[str] = "adaptive"
    implicit: ClassVar[bool] = True

    def _prepare(self) -> tuple[Any, bool]:
        eom = self.problem.eom
        return prepared(eom, (self.name,), lambda: (dense_rhs(eom), jacobian_function(eom)))

    def _integrate(self, functions) -> Trajectory:
        pr, eom = self.problem, self.problem.eom
        rhs, jac_fn = (BufferedFunction(f, pr.p) for f in functions)
        u_at = pr.inputs.at

        def fun(t, x):
            return rhs(x, u_at(t))

        def jac(t, x):
            return jac_fn(x, u_at(t))

        t_out = pr.t_out
        X = np.empty((t_out.size, eom.n_x))
        done = np.searchsorted(t_out, 0.0, side="right")
        X[:done] = pr.x0
        solver = Radau(fun, 0.0, pr.x0, t_out[-1], rtol=pr.rtol, atol=pr.atol, jac=jac) if t_out[-1] > 0 else None
        steps = 0
        while solver is not None and solver.status == "running":
            t_old = solver.t
            message = solver.step()
            steps += 1
            self._check(solver, message, t_old)
            upto = np.searchsorted(t_out, solver.t, side="right")
            if upto > done:
                X[done:upto] = solver.dense_output()(t_out[done:upto]).T
                done = upto
        if done < t_out.size:     # the last output time exactly at the end
            X[done:] = solver.y
        nfev, njev, nlu = (0, 0, 0) if solver is None else (solver.nfev, solver.njev, solver.nlu)
        return Trajectory(X, steps=steps, n_rhs=nfev, n_jac=njev, extra={"n_lu": nlu})

    def _check(self, solver: Radau, message: str | None, t_old: float) -> None:
        pr, eom = self.problem, self.problem.eom
        y = np.asarray(solver.y)
        if first_bad_column(y[:, None], pr.x0) is not None:
            raise IntegrationError(divergence_message(self.name, float(solver.t), float(solver.t - t_old), y,
                                                      eom.states, pr.x0))
        if solver.status == "failed":
            i = int(np.argmax(np.abs(y) / (1.0 + np.abs(pr.x0))))
            raise IntegrationError(
                f"method {self.name!r} failed at t = {solver.t:.6g} s (step size {solver.h_abs:.3g} s): {message} "
                f"State {eom.states[i]!r} = {y[i]:.4g} (largest relative to x0); the solution may grow without "
                "bound, or the rhs may be undefined (NaN) just beyond this state."
            )
