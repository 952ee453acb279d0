"""Methods from ``scipy.integrate``: independent references for the CasADi-backed ones.

``scipy-radau`` (Radau IIA, order 5) and ``scipy-bdf`` (variable-order BDF,
orders 1-5) run scipy's implicit adaptive solvers step by step, with the exact
Jacobian of the rhs from CasADi and the inputs evaluated at every rhs call.
Each accepted step is checked for finiteness; output times come from scipy's
dense output. The rhs and Jacobian are called through ``Function.buffer()``
(compiled C with ``compile=True``); the cost is still dominated by scipy's
Python-side step logic: use them as references, not for long runs.
"""

from __future__ import annotations

import time
from typing import Any, ClassVar

import numpy as np

from ..exceptions import IntegrationError
from .base import BufferedFunction, Method, Trajectory, dense_rhs, jacobian_function, prepared
from .checks import divergence_message, first_bad_column
from .monitor import CHUNK_WALL_S, SimulationInterrupted

__all__ = ["ScipyMethod", "ScipyRadau", "ScipyBDF"]


class ScipyMethod(Method):
    """Base of the scipy solvers: ``solver`` names an ``OdeSolver`` subclass of ``scipy.integrate`` taking ``jac=``.

    scipy is imported when a solver runs, not with :mod:`mbsym` (import time).
    """

    kind: ClassVar[str] = "adaptive"
    implicit: ClassVar[bool] = True
    solver: ClassVar[str] = "Radau"

    def _prepare(self) -> tuple[Any, bool]:
        plant, on = self.problem.plant, self.problem.compile

        def build():
            (rhs, c1), (jac, c2) = self._compile(dense_rhs(plant)), self._compile(jacobian_function(plant))
            return rhs, jac, c1 and c2

        return prepared(self.problem.owner, ("scipy", on, self._compiler), build)

    def _integrate(self, functions) -> Trajectory:
        pr, plant = self.problem, self.problem.plant
        rhs, jac_fn = (BufferedFunction(f, pr.p) for f in functions[:2])
        u_at = pr.inputs.at

        def fun(t, x):
            return rhs(x, u_at(t))

        def jac(t, x):
            return jac_fn(x, u_at(t))

        t_out = pr.t_out
        X = np.empty((t_out.size, plant.n_x))
        done = np.searchsorted(t_out, 0.0, side="right")
        X[:done] = pr.x0
        import scipy.integrate

        solver_class = getattr(scipy.integrate, self.solver)
        solver = (solver_class(fun, 0.0, pr.x0, t_out[-1], rtol=pr.rtol, atol=pr.atol, jac=jac)
                  if t_out[-1] > 0 else None)
        steps = 0
        last_report = time.perf_counter()
        try:
            while solver is not None and solver.status == "running":
                t_old = solver.t
                try:
                    message = solver.step()
                except ValueError as exc:           # scipy's LU refuses a non-finite Jacobian or state
                    self._raise_nonfinite(solver, t_old, exc)
                steps += 1
                self._check(solver, message, t_old)
                upto = np.searchsorted(t_out, solver.t, side="right")
                if upto > done:
                    X[done:upto] = solver.dense_output()(t_out[done:upto]).T
                    done = upto
                if pr.monitor is not None and time.perf_counter() - last_report > CHUNK_WALL_S:
                    pr.monitor.update(float(solver.t))
                    last_report = time.perf_counter()
        except KeyboardInterrupt:
            raise SimulationInterrupted(float(solver.t), (t_out[:done], X[:done].copy())) from None
        if done < t_out.size:     # the last output time exactly at the end
            X[done:] = solver.y
        nfev, njev, nlu = (0, 0, 0) if solver is None else (solver.nfev, solver.njev, solver.nlu)
        success = solver is None or solver.status == "finished"
        message = (f"scipy {self.solver} reached the last output time t = {t_out[-1]:g} s." if success
                   else f"scipy {self.solver} stopped ({solver.status}) at t = {solver.t:g} s.")
        return Trajectory(X, success, message, steps=steps, n_rhs=nfev, n_jac=njev,
                          extra={"n_lu": nlu, "compiled": functions[2]})

    def _raise_nonfinite(self, solver: Any, t_old: float, exc: ValueError) -> None:
        pr, plant = self.problem, self.problem.plant
        y = np.asarray(solver.y, dtype=float)
        with np.errstate(all="ignore"):
            f = np.asarray(solver.fun(solver.t, y), dtype=float)
        if not np.all(np.isfinite(f)):
            i = int(np.flatnonzero(~np.isfinite(f))[0])
            what = f"the rhs is not finite (first non-finite derivative: state {plant.states[i]!r}: {f[i]})"
        else:
            what = f"scipy refused the step ({exc})"
        step = getattr(solver, "h_abs", None)
        step_txt = "unknown step size" if step is None else f"step size dt = {step:.6g} s"
        j = int(np.argmax(np.abs(y) / (1.0 + np.abs(pr.x0))))
        raise IntegrationError(f"method {self.name!r} failed at t = {solver.t:.6g} s ({step_txt}): {what}; "
                               f"state {plant.states[j]!r} = {y[j]:.4g} (largest relative to x0). The rhs may be "
                               "undefined (NaN) just beyond this state.") from exc

    def _check(self, solver: Any, message: str | None, t_old: float) -> None:
        pr, plant = self.problem, self.problem.plant
        y = np.asarray(solver.y)
        if first_bad_column(y[:, None], pr.x0) is not None:
            raise IntegrationError(divergence_message(self.name, float(solver.t), float(solver.t - t_old), y,
                                                      plant.states, pr.x0))
        if solver.status == "failed":
            i = int(np.argmax(np.abs(y) / (1.0 + np.abs(pr.x0))))
            raise IntegrationError(
                f"method {self.name!r} failed at t = {solver.t:.6g} s (step size {solver.h_abs:.3g} s): {message} "
                f"State {plant.states[i]!r} = {y[i]:.4g} (largest relative to x0); the solution may grow without "
                "bound, or the rhs may be undefined (NaN) just beyond this state."
            )


class ScipyRadau(ScipyMethod):
    """scipy's ``Radau`` (implicit Runge-Kutta Radau IIA, order 5) with the CasADi Jacobian."""

    name: ClassVar[str] = "scipy-radau"
    order: ClassVar[int] = 5
    solver: ClassVar[str] = "Radau"


class ScipyBDF(ScipyMethod):
    """scipy's ``BDF`` (variable-order backward differentiation, orders 1-5) with the CasADi Jacobian."""

    name: ClassVar[str] = "scipy-bdf"
    order: ClassVar[int] = 5
    solver: ClassVar[str] = "BDF"
