"""Methods backed by CasADi's SUNDIALS interfaces.

``cvodes``: variable-order BDF (orders 1-5) with Newton iterations on the exact
Jacobian (CasADi's algorithmic differentiation of the rhs); ``adams``: CVODES
Adams-Moulton (orders 1-5) with functional iteration (explicit, non-stiff);
``idas``: IDAS BDF on the residual form ``e(q, qd, qdd) = 0`` (no M^-1). Each
runs as one call of ``casadi.integrator(name, plugin, dae, t0, tgrid, opts)``
over the whole integration grid, keeping step size and order across grid
points. With ``compile=True`` the rhs (residual for IDAS) and its Jacobian are
compiled into one library (:func:`mbsym.codegen.compile_function` with
``jacobian=True``) and the DAE calls it; otherwise CasADi's virtual machine
evaluates them.

Inputs: constant inputs are passed as extra parameters. Otherwise the
integration grid is the output grid ``t_out`` plus the grid points of table
inputs (and t = 0); on each grid interval ``[t_k, t_k+1]`` a table input is the
straight line between ``u(t_k)`` and ``u(t_k+1)``, evaluated inside the ODE
with its explicit time (CasADi's per-interval controls carry ``u(t_k)``, the
slope and ``t_k``): constant and table inputs are exact. CasADi restarts
CVODES at every grid point where controls are given (about 1.5-2x the steps of
an input-free run); a piecewise-linear interpolant inside the ODE avoided the
restarts but lost accuracy at the kinks (measured: 1e-5 vs 1e-8 error at rtol
1e-6 with 60 000 grid points), hence this choice for tables.

Callable inputs are known only through samples, taken independently of how
coarse ``t_out`` is: each is sampled on a uniform grid of spacing
``min(smallest output spacing, tmax / CALLABLE_INTERVALS)`` (at most
``MAX_CALLABLE_INTERVALS`` intervals) and replaced by the cubic interpolating
spline through the samples (``scipy.interpolate.make_interp_spline``,
not-a-knot), evaluated inside the ODE by ``casadi.bspline`` with the
coefficients passed as parameters (no restarts). Its error is about
``h^4 max|d^4u/dt^4| / 384`` (F = 10 sin 3t over 10 s: h = 5 ms, 1.3e-9 N), and
it is smooth, so CVODES keeps its order. A callable that jumps (a step) rings
over a few samples around the jump: give such an input as a table. The number
of samples is reported as ``statistics["input_samples"]``.
"""

from __future__ import annotations

from typing import Any, ClassVar

import casadi as ca
import numpy as np

from ..exceptions import IntegrationError
from .base import Method, Trajectory, prepared, symbolic_rhs
from .checks import divergence_message, first_bad_column, raise_diverged
from .monitor import SimulationInterrupted, sigint_seen

__all__ = ["SundialsMethod", "Cvodes", "Adams", "Idas", "CALLABLE_INTERVALS", "MAX_CALLABLE_INTERVALS"]

#: Callable inputs are sampled on at least this many intervals over ``[0, tmax]`` [-] ...
CALLABLE_INTERVALS = 2000
#: ... and at most this many (an output grid finer than ``tmax / CALLABLE_INTERVALS`` refines them) [-].
MAX_CALLABLE_INTERVALS = 100_000


class SundialsMethod(Method):
    """Base of the methods backed by ``casadi.integrator`` (CVODES, IDAS) over the whole grid.

    Subclasses set ``plugin`` and ``solver_options`` and may override ``_dae``
    (the DAE dict and the extra call arguments, e.g. ``z0``).
    """

    kind: ClassVar[str] = "adaptive"
    plugin: ClassVar[str] = "cvodes"
    solver_options: ClassVar[dict] = {}
    #: Maximum number of internal steps per grid interval (SUNDIALS ``mxstep``).
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

    def _model_function(self) -> ca.Function:
        """The model Function inside the DAE (the rhs; the residual for IDAS)."""
        return self.problem.plant.rhs

    @classmethod
    def settings(cls) -> tuple:
        return cls.plugin, tuple(sorted(cls.solver_options.items())), cls.max_num_steps

    def _spline_knots(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Sample times of the callable inputs and the knots of their cubic splines (not-a-knot), or None."""
        pr = self.problem
        if not (pr.plant.n_u and pr.inputs.callables):
            return None
        spacing = float(np.min(np.diff(pr.t_out))) if pr.t_out.size > 1 else pr.tmax
        n = int(np.ceil(pr.tmax / min(spacing, pr.tmax / CALLABLE_INTERVALS) - 1e-9))
        t = np.linspace(0.0, pr.tmax, min(max(n, CALLABLE_INTERVALS), MAX_CALLABLE_INTERVALS) + 1)
        return t, np.concatenate([np.zeros(4), t[2:-2], np.full(4, pr.tmax)])

    def _spline_coefficients(self) -> np.ndarray:
        """B-spline coefficients of the callable inputs, row-major ``(n_coef, n_callable)`` as casadi.bspline."""
        if self._splines is None:
            return np.zeros(0)
        from scipy.interpolate import make_interp_spline   # only with callable inputs (import time of mbsym)

        t, knots = self._splines
        values = self.problem.inputs(t)[:, list(self.problem.inputs.callables)]
        return make_interp_spline(t, values, k=3, t=knots).c.reshape(-1)

    def _prepare(self) -> tuple[Any, bool]:
        pr = self.problem
        grid, self._out_index = self._grid()
        self._tgrid = grid
        self._varying = pr.plant.n_u > 0 and not pr.inputs.constant
        self._splines = self._spline_knots()
        f = self._model_function()
        (self._fn, self._compiled), _ = prepared(pr.owner, ("sundials", f.name(), pr.compile, self._compiler),
                                                 lambda: self._compile(f, jacobian=True))
        samples = None if self._splines is None else (pr.inputs.callables, self._splines[0].size, pr.tmax)
        import hashlib

        key = self.cache_key(pr.rtol, pr.atol, self._varying, grid.size, hashlib.sha1(grid.tobytes()).hexdigest(),
                             samples)
        return prepared(pr.owner, key, lambda: self._build(grid))

    def _build(self, grid: np.ndarray) -> ca.Function:
        plant, pr = self.problem.plant, self.problem
        sym, _ = symbolic_rhs(plant)
        # a compiled (external) Function and casadi.bspline take MX only
        sym = ca.MX if self._compiled or self._splines is not None else sym
        if self._varying:
            idx = pr.inputs.callables
            n_coef = 0 if self._splines is None else self._splines[0].size * len(idx)
            pc, t, c = sym.sym("p", plant.n_p + n_coef), sym.sym("t"), sym.sym("c", 2 * plant.n_u + 1)
            p = pc[: plant.n_p]
            u = c[: plant.n_u] + c[plant.n_u: 2 * plant.n_u] * (t - c[-1])   # c = [u(t_k); slope; t_k] (tables)
            if idx:                                                     # callables: splines of t
                knots = self._splines[1]
                s = ca.bspline(ca.fmin(ca.fmax(t, knots[0]), knots[-1]), pc[plant.n_p:], [knots.tolist()], [3],
                               len(idx), {})
                u = ca.vertcat(*[s[idx.index(j)] if j in idx else u[j] for j in range(plant.n_u)])
            dae = {"p": pc, "t": t, "u": c, **self._dae(sym, u, p)}
        else:                                   # constant inputs: extra parameters [p; u]
            pu = sym.sym("p", plant.n_p + plant.n_u)
            dae = {"p": pu, **self._dae(sym, pu[plant.n_p:], pu[: plant.n_p])}
        opts = {"abstol": pr.atol, "reltol": pr.rtol, "max_num_steps": self.max_num_steps,
                "disable_internal_warnings": True, "show_eval_warnings": False,   # failures raise instead
                **self.solver_options}
        return ca.integrator(f"{plant.name}_{self.name}", self.plugin, dae, 0.0, grid, opts)

    def _dae(self, sym, u, p) -> dict:
        """``x``, ``ode`` (and ``z``, ``alg``) of the DAE, given the input and parameter expressions."""
        x = sym.sym("x", self.problem.plant.n_x)
        return {"x": x, "ode": self._fn(x, u, p)}

    def _call_args(self) -> dict:
        """Extra arguments of the integrator call (e.g. an initial guess ``z0``)."""
        return {}

    def _controls(self, grid: np.ndarray) -> np.ndarray:
        """Per-interval input line ``[u(t_k); slope; t_k]``; column j drives (grid[j-1], grid[j]]."""
        n_u = self.problem.plant.n_u
        u = self.problem.inputs(grid)                                  # (n_grid, n_u)
        u[:, list(self.problem.inputs.callables)] = 0.0                # callables: splines (see _build)
        C = np.zeros((2 * n_u + 1, grid.size))
        if grid.size > 1:
            C[:n_u, 1:] = u[:-1].T
            C[n_u: 2 * n_u, 1:] = (np.diff(u, axis=0) / np.diff(grid)[:, None]).T
            C[-1, 1:] = grid[:-1]
        C[:n_u, 0] = u[0]
        return C

    def _integrate(self, integ: ca.Function) -> Trajectory:
        pr, plant = self.problem, self.problem.plant
        if self._varying:
            args = {"x0": pr.x0, "p": np.concatenate([pr.p, self._spline_coefficients()]),
                    "u": self._controls(self._tgrid),
                    **self._call_args()}
        else:
            args = {"x0": pr.x0, "p": np.concatenate([pr.p, pr.inputs.at(0.0)]), **self._call_args()}
        try:
            with sigint_seen() as interrupted:
                X = np.array(integ(**args)["xf"])
        except (RuntimeError, KeyboardInterrupt) as exc:
            if interrupted or isinstance(exc, KeyboardInterrupt):
                raise SimulationInterrupted(float(integ.stats().get("tcur", 0.0))) from None
            raise IntegrationError(self._failure(integ, args, exc)) from exc
        stats = integ.stats()
        bad = first_bad_column(X, pr.x0)
        if bad is not None:
            raise_diverged(self.name, float(self._tgrid[bad]), float(stats.get("hlast", np.nan)), X[:, bad],
                           plant.states, pr.x0)
        extra = {"n_lu": int(stats.get("nlinsetups", 0)), "n_error_test_failures": int(stats.get("netfails", 0)),
                 "compiled": self._compiled,
                 "input_samples": 0 if self._splines is None else self._splines[0].size}
        t_end = float(stats.get("tcur", np.nan))
        success = bool(t_end >= self._tgrid[-1] * (1 - 1e-12)) or self._tgrid.size == 1
        message = (f"{self.plugin.upper()} reached the last output time t = {self._tgrid[-1]:g} s." if success else
                   f"{self.plugin.upper()} stopped at t = {t_end:g} s before the last output time "
                   f"{self._tgrid[-1]:g} s.")
        return Trajectory(X[:, self._out_index].T.copy(), success, message, steps=int(stats["nsteps"]),
                          n_rhs=int(stats["nfevals"]), n_jac=int(stats.get("n_call_jacF", 0)), extra=extra)

    def _failure(self, integ: ca.Function, args: dict, exc: RuntimeError) -> str:
        """Explain a CVODES failure: its flag, where it stopped, and the last state it reached."""
        pr, plant = self.problem, self.problem.plant
        stats = integ.stats()
        t_fail, h = float(stats.get("tcur", np.nan)), float(stats.get("hcur", np.nan))
        text = str(exc)
        marker = next((m for m in ("CVode returned", "IDASolve returned", "returned") if m in text), None)
        flag = (text.rsplit(marker, 1)[-1].split(".")[0].strip(' "') if marker else "") or "an error"
        head = (f"method {self.name!r} failed near t = {t_fail:.6g} s (step size {h:.3g} s; "
                f"{self.plugin.upper()} returned {flag}).")
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
            return divergence_message(self.name, float(before[bad]), h, X[:, bad], plant.states, pr.x0)
        i = int(np.argmax(np.abs(x_last) / (1.0 + np.abs(pr.x0))))
        rhs = np.array(plant.rhs(x_last, pr.inputs.at(float(before[-1])), pr.p)).reshape(-1)
        nonfinite = [plant.states[j] for j in np.flatnonzero(~np.isfinite(rhs))]
        tail = (f" The rhs is not finite for {nonfinite} there." if nonfinite
                else " The solution may grow without bound, or the rhs may be undefined (NaN) just beyond this state.")
        return (f"{head} Last output at t = {before[-1]:.6g} s: state {plant.states[i]!r} = {x_last[i]:.4g} "
                f"(largest relative to x0).{tail}")


class Cvodes(SundialsMethod):
    """CVODES (SUNDIALS) BDF, adaptive step and order (1-5), Newton on the exact Jacobian."""

    name: ClassVar[str] = "cvodes"
    order: ClassVar[int] = 5
    implicit: ClassVar[bool] = True
    solver_options: ClassVar[dict] = {"linear_multistep_method": "bdf"}


class Adams(SundialsMethod):
    """CVODES Adams-Moulton, adaptive step and order 1-5, functional iteration: explicit, non-stiff.

    No Jacobian and no linear solves: cheap steps, but the step is limited by
    stability on stiff problems (many steps, or a failure near the step limit).
    The order is capped at 5 (CVODES allows 12): with the cap the order is
    measurable (fitted 5.0 +- 0.1 on the oscillator; uncapped, 5 to 15
    depending on the tolerance window) and equals BDF's.
    """

    name: ClassVar[str] = "adams"
    order: ClassVar[int] = 5
    implicit: ClassVar[bool] = False
    solver_options: ClassVar[dict] = {"linear_multistep_method": "adams", "nonlinear_solver_iteration": "functional",
                                      "max_order": 5}


class Idas(SundialsMethod):
    """IDAS (SUNDIALS) BDF on the residual form: ``x = [q; qd]``, algebraic ``qdd`` with ``e(q, qd, qdd) = 0``.

    Integrates ``M(q) qdd = F`` without forming M^-1 F (the exact Jacobian of
    the residual drives Newton); consistent initial accelerations from the rhs.
    The accelerations are left out of the error test (``suppress_algebraic``):
    they follow from ``q, qd`` and the inputs, and IDAS cannot estimate their
    first-step error (it has no ``d qdd/dt``; from rest under a ramp force
    the error test failed at ``h ~ 1e-10`` s). First-order dynamics that are more
    than ``[q; qd]`` (an :class:`mbsym.Dynamics` with extra states) are integrated
    as the implicit ODE ``xd - f(x, u, p) = 0`` by the same BDF.
    """

    name: ClassVar[str] = "idas"
    order: ClassVar[int] = 5
    implicit: ClassVar[bool] = True
    plugin: ClassVar[str] = "idas"
    solver_options: ClassVar[dict] = {"calc_ic": True, "suppress_algebraic": True}

    @property
    def _residual_form(self) -> bool:
        return self.problem.eom is not None

    def _dae(self, sym, u, p) -> dict:
        if not self._residual_form:
            return super()._dae(sym, u, p)
        eom = self.problem.eom
        n = eom.n_q
        x, z = sym.sym("x", eom.n_x), sym.sym("qdd", n)
        return {"x": x, "z": z, "ode": ca.vertcat(x[n:], z), "alg": self._fn(x[:n], x[n:], z, u, p)}

    def _model_function(self) -> ca.Function:
        return self.problem.eom.functions.residual if self._residual_form else self.problem.plant.rhs

    def _call_args(self) -> dict:
        pr = self.problem
        if not self._residual_form:
            return {}
        xd = np.array(pr.plant.rhs(pr.x0, pr.inputs.at(0.0), pr.p)).reshape(-1)
        return {"z0": xd[pr.eom.n_q:]}
