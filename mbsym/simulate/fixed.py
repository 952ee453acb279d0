"""Fixed-step methods, with the whole time loop inside CasADi.

A fixed-step method builds one step ``(z, U, p, h) -> (z_next, aux)`` as a
CasADi Function (SX when the model's Functions are SX, MX glue otherwise) and
``Function.mapaccum`` repeats it ``n_steps`` times. The step size ``h`` is an
input, so one step Function, compiled or not, serves every ``dt`` and every
number of steps. ``z`` is the method's state (``x = [q; qd]`` for explicit
Runge-Kutta methods; more for methods that carry accelerations); ``aux`` holds
per-step by-products (the rhs at the start of the step for RK4). Inputs are
sampled beforehand at every stage time (``t_k + c_i h``) and passed as one
``(n_u, n_c * n_steps)`` array; parameters are passed once.

With ``compile=True`` the step is generated as C, compiled and cached on disk
(:mod:`mbsym.codegen`); ``mapaccum`` then loops over the compiled step. States
between steps (an output time off the step grid) come from cubic Hermite
interpolation with the time derivatives at both ends (error O(h^4)).
"""

from __future__ import annotations

import time
from typing import Any, ClassVar

import casadi as ca
import numpy as np

from .base import Method, Trajectory, prepared, run_buffered, stability_hint, symbolic_rhs
from .checks import first_bad_column, raise_diverged
from .monitor import CHUNK_WALL_S

#: Chunks of a long run have between MIN_CHUNK and MAX_CHUNK steps (powers of two, plus one remainder):
#: CasADi's mapaccum takes time to build in proportion to its length (~15 ms per 1000 steps), once per length.
MIN_CHUNK, MAX_CHUNK = 64, 4096

__all__ = ["FixedStepMethod", "RK4", "PreparedLoop"]


class PreparedLoop:
    """A step Function and its ``mapaccum`` loop over ``n`` steps; ``compiled`` says whether the step is C.

    :meth:`run` calls the loop through ``Function.buffer()`` on numpy arrays (no
    DM conversions: ~0.3 ms saved per 600 steps of a 6-state model).
    """

    def __init__(self, step: ca.Function, n: int, compiled: bool) -> None:
        self.step, self.compiled, self.n = step, compiled, n
        loop = step.mapaccum(f"{step.name()}_loop", n, [0], [0])
        z, U, p, h = (ca.MX.sym(s, step.size_in(i)[0], step.size_in(i)[1] * (n if s == "U" else 1))
                      for i, s in enumerate(("z", "U", "p", "h")))
        self.loop = ca.Function(f"{step.name()}_loop", [z, U, p, h], loop(z, U, ca.repmat(p, 1, n), ca.repmat(h, 1, n)),
                                ["z0", "U", "p", "h"], ["Z", "aux"])

    def run(self, z0: np.ndarray, U: np.ndarray, p: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
        """States after each step ``(n_z, n)`` and by-products ``(n_aux, n)``; ``U`` is ``(n_u, n_c n)``."""
        args = [np.ascontiguousarray(z0, dtype=float), np.asfortranarray(U, dtype=float).reshape(-1, order="F"),
                np.ascontiguousarray(p, dtype=float), np.array([h], dtype=float)]
        return run_buffered(self.loop, args, self.n)      # column-major (n_x, n) as a view

    def runner(self, p: np.ndarray):
        """A fast ``run(z0, U, h) -> (Z, aux)`` for many calls with the same ``p`` (one buffer, reused arrays;
        the returned arrays are overwritten by the next call: copy what you keep)."""
        z = np.zeros(self.step.size1_in(0))
        U = np.zeros(self.step.size1_in(1) * self.step.size2_in(1) * self.n)
        P, H = np.ascontiguousarray(p, dtype=float).copy(), np.zeros(1)
        outs = [np.empty(self.n * self.step.numel_out(i)) for i in range(2)]
        buf, trigger = self.loop.buffer()
        for i, a in enumerate((z, U, P, H)):
            buf.set_arg(i, memoryview(a))
        for i, o in enumerate(outs):
            buf.set_res(i, memoryview(o))
        views = tuple(o.reshape(self.n, -1).T for o in outs)
        n_u = self.step.size1_in(1)

        def run(z0: np.ndarray, Uc: np.ndarray, h: float, _keep=(buf, outs, P)):   # buffer and p must stay alive
            z[:] = z0
            U.reshape(-1, n_u).T[:] = Uc                       # (n_u, n_c n) column-major into the buffer
            H[0] = h
            trigger()
            return views

        return run


class FixedStepMethod(Method):
    """Base of one-step methods with a constant step.

    Subclasses give the distinct stage-time fractions ``nodes`` (in [0, 1]) and
    implement ``_step(z, U, p, h)`` (symbolic: one step from ``z`` with the
    inputs ``U[:, i]`` at ``t + nodes[i] h``; returns ``(z_next, aux)``). A
    method whose state ``z`` is more than ``x`` overrides ``_state_size``,
    ``_initial`` and ``_derivatives``.
    """

    kind: ClassVar[str] = "fixed-step"
    implicit: ClassVar[bool] = False
    nodes: ClassVar[tuple[float, ...]] = (0.0,)
    #: Right-hand-side (or residual) evaluations per step.
    rhs_per_step: ClassVar[int] = 1
    #: Jacobian evaluations per step.
    jac_per_step: ClassVar[int] = 0
    #: Stability limit ``|lambda| h`` of the method (imaginary and negative real axes) [-]; inf: A-stable.
    stability_radius: ClassVar[float] = 2.0

    @classmethod
    def settings(cls) -> tuple:
        return (cls.nodes,)

    # ------------------------------------------------------------------ hooks
    def _state_size(self) -> int:
        return self.problem.plant.n_x

    def _step(self, z, U, p, h):
        raise NotImplementedError

    def _initial(self) -> np.ndarray:
        return self.problem.x0

    def _derivatives(self, Zr: np.ndarray, Ar: np.ndarray, t_grid: np.ndarray,
                     need_end: bool) -> tuple[np.ndarray, int]:
        """Time derivatives of x at every grid point, rows ``(n + 1, n_x)``, and the extra rhs evaluations.

        Default: ``aux`` holds the rhs at every step start; the end point is
        evaluated only if ``need_end`` (an output time in the last step).
        """
        pr = self.problem
        F = np.empty((Zr.shape[0], pr.plant.n_x))
        F[:-1] = Ar
        F[-1] = 0.0                              # weight zero in the interpolation unless needed
        if need_end:
            F[-1] = np.asarray(pr.plant.rhs(Zr[-1, : pr.plant.n_x], pr.inputs.at(float(t_grid[-1])),
                                                    pr.p)).reshape(-1)
        return F, int(need_end)

    def _symbol_class(self) -> type:
        """SX or MX for the step (default: as the model's rhs)."""
        return symbolic_rhs(self.problem.plant)[0]

    def _counts(self, A: np.ndarray) -> tuple[int, int]:
        """(rhs or residual evaluations, Jacobian evaluations) of the loop, from the by-products."""
        n = A.shape[1]
        return self.rhs_per_step * n, self.jac_per_step * n

    def _aux_failure(self, A: np.ndarray) -> int | None:
        """Index of the first step whose by-products reveal a failure (e.g. Newton), or None."""
        return None

    def _raise_aux_failure(self, k: int, A: np.ndarray, Z: np.ndarray, t_grid: np.ndarray, offset: int) -> None:
        """Raise for the failure at step ``k`` of a chunk starting at global step ``offset``."""
        raise NotImplementedError

    # ------------------------------------------------------------------ machinery
    def _prepare(self) -> tuple[Any, bool]:
        """The step, the seconds one step takes (long runs only) and the loop of the first chunk."""
        pr = self.problem
        step, _ = prepared(pr.owner, self.cache_key("step"), self._build_step)
        z0 = self._initial()
        per_step = self._step_seconds(step[0], z0) if pr.n_steps > MIN_CHUNK else 0.0
        m = self._chunk_length(pr.n_steps, per_step) if per_step else pr.n_steps
        loop, hit = self._loop(step, m)
        return (step, per_step, z0, loop), hit

    def _loop(self, step: tuple[ca.Function, bool], n: int) -> tuple[PreparedLoop, bool]:
        """The ``mapaccum`` loop over ``n`` steps (cached per length: whole runs, chunks, remainders)."""
        return prepared(self.problem.owner, self.cache_key("loop", n), lambda: PreparedLoop(step[0], n, step[1]))

    def symbolic_step(self) -> ca.Function:
        """The step Function before compilation (cached per model and method settings)."""
        step, _ = prepared(self.problem.owner, (type(self), self.settings(), "symbolic-step"), self._symbolic_step)
        return step

    def _build_step(self) -> tuple[ca.Function, bool]:
        return self._compile(self.symbolic_step())

    def _symbolic_step(self) -> ca.Function:
        plant = self.problem.plant
        sym = self._symbol_class()
        z = sym.sym("z", self._state_size())
        U = sym.sym("U", plant.n_u, len(self.nodes))
        p = sym.sym("p", plant.n_p)
        h = sym.sym("h")
        z_next, aux = self._step(z, U, p, h)
        opts = {"cse": True} if sym is ca.SX else {}
        return ca.Function(f"{plant.name}_{self.name.replace('-', '_')}_step", [z, U, p, h], [z_next, aux],
                           ["z", "U", "p", "h"], ["z_next", "aux"], opts)

    def _step_seconds(self, step: ca.Function, z0: np.ndarray) -> float:
        """Wall time of one step [s], timed on the first step (to size the chunks of long runs)."""
        pr = self.problem
        U = pr.inputs(np.asarray(self.nodes) * pr.dt).T
        buf, trigger = step.buffer()
        args = [np.ascontiguousarray(z0, dtype=float), np.asfortranarray(U, dtype=float).reshape(-1, order="F"),
                np.ascontiguousarray(pr.p, dtype=float), np.array([pr.dt])]
        outs = [np.empty(step.numel_out(i)) for i in range(step.n_out())]
        for i, a in enumerate(args):
            buf.set_arg(i, memoryview(a))
        for i, o in enumerate(outs):
            buf.set_res(i, memoryview(o))
        t0 = time.perf_counter()
        trigger()
        return max(time.perf_counter() - t0, 1e-7)

    def _chunk_length(self, remaining: int, seconds_per_step: float) -> int:
        """Steps of the next chunk: all that remain if they take about a chunk's time, else a power of two."""
        fit = CHUNK_WALL_S / seconds_per_step
        if remaining <= max(1.5 * fit, MIN_CHUNK):
            return remaining
        return int(min(max(2 ** int(np.log2(max(fit, 1.0))), MIN_CHUNK), MAX_CHUNK, remaining))

    def _integrate(self, prep: tuple) -> Trajectory:
        pr, plant = self.problem, self.problem.plant
        step, per_step, z, loop = prep
        h, n = pr.dt, pr.n_steps
        x_out = np.empty((pr.t_out.size, plant.n_x))
        done, k0, n_rhs, n_jac, n_extra = 0, 0, 0, 0, 0
        c = np.asarray(self.nodes)
        try:
            while k0 < n:
                if k0 > 0:
                    m = self._chunk_length(n - k0, per_step)
                    loop = loop if loop.n == m else self._loop(step, m)[0]
                m = loop.n
                t_grid = (k0 + np.arange(m + 1)) * h
                if k0 + m == n:
                    t_grid[-1] = pr.tmax
                t_stage = (t_grid[:-1, None] + c[None, :] * h).reshape(-1)
                U = pr.inputs(t_stage).T                                # (n_u, n_c * m)
                t0 = time.perf_counter()
                Zn, A = loop.run(z, U, pr.p, h)                         # (n_z, m), (n_aux, m)
                per_step = max((time.perf_counter() - t0) / m, 1e-8)
                Zr = np.vstack([z[None, :], Zn.T])                      # (m + 1, n_z) rows at t_grid
                self._check_chunk(Zn, A, Zr, t_grid, k0)
                hi = int(np.searchsorted(pr.t_out, t_grid[-1] * (1 + 1e-12) + 1e-12, side="right"))
                if k0 + m == n:
                    hi = pr.t_out.size
                if hi > done:
                    x_out[done:hi], extra = self._output(Zr, A.T, t_grid, pr.t_out[done:hi])
                    n_extra += extra
                    done = hi
                r, j = self._counts(A)
                n_rhs, n_jac = n_rhs + r, n_jac + j
                z = Zn[:, -1].copy()
                k0 += m
                if pr.monitor is not None:
                    pr.monitor.update(float(t_grid[-1]))
        except KeyboardInterrupt:
            from .monitor import SimulationInterrupted

            t_reached = float(min(k0 * h, pr.tmax))
            raise SimulationInterrupted(t_reached, (pr.t_out[:done], x_out[:done].copy())) from None
        return Trajectory(x_out, True, f"{n} of {n} steps of dt = {h:.6g} s taken up to t = {pr.tmax:g} s.",
                          steps=n, n_rhs=n_rhs + n_extra, n_jac=n_jac, extra={"compiled": step[1]})

    def _check_chunk(self, Zn: np.ndarray, A: np.ndarray, Zr: np.ndarray, t_grid: np.ndarray, k0: int) -> None:
        """Raise IntegrationError at the first diverged step or failed by-product of a chunk."""
        pr, plant = self.problem, self.problem.plant
        bad, bad_aux = first_bad_column(Zn[: plant.n_x], pr.x0), self._aux_failure(A)
        if bad_aux is not None and (bad is None or bad_aux <= bad):
            self._raise_aux_failure(bad_aux, A, Zr.T, t_grid, k0)
        if bad is not None:
            hint = "" if self.implicit else stability_hint(plant, pr, self.name, self.stability_radius)
            raise_diverged(self.name, float(t_grid[bad + 1]), pr.dt, Zn[: plant.n_x, bad], plant.states, pr.x0,
                           where=f"step {k0 + bad + 1} of {pr.n_steps}", hint=hint)

    def _output(self, Zr: np.ndarray, Ar: np.ndarray, t_grid: np.ndarray,
                t_out: np.ndarray) -> tuple[np.ndarray, int]:
        """States at ``t_out`` (rows, within ``t_grid``): exact on the step grid, cubic Hermite in between."""
        h, n_x = self.problem.dt, self.problem.plant.n_x
        m = t_grid.size - 1
        k = np.clip(np.floor((t_out - t_grid[0]) / h + 1e-9).astype(int), 0, m)
        s = (t_out - t_grid[k]) / h
        if np.all(np.abs(s) <= 1e-9):
            return Zr[k, :n_x].copy(), 0
        k = np.minimum(k, m - 1)
        s = ((t_out - t_grid[k]) / h)[:, None]
        last = (k == m - 1) & (s[:, 0] > 1e-9) & (s[:, 0] < 1 - 1e-9)
        F, n_extra = self._derivatives(Zr, Ar, t_grid, bool(np.any(last)))
        s2, s3 = s * s, s * s * s
        x = ((2 * s3 - 3 * s2 + 1) * Zr[k, :n_x] + (s3 - 2 * s2 + s) * h * F[k]
             + (3 * s2 - 2 * s3) * Zr[k + 1, :n_x] + (s3 - s2) * h * F[k + 1])
        return x, n_extra


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

    def _symbol_class(self) -> type:
        """MX: four calls of the rhs Function. Measured on paper45 against the step expanded in SX
        (with CSE): built in 3.5 instead of 44 ms, serialized (the disk-cache key) in 3.7 instead of
        7.6 ms, compiled ~2.7x faster (the rhs is generated once), and as fast to run (VM 30 vs 26 ms,
        compiled 2.1 vs 2.4 ms for 480 steps)."""
        return ca.MX

    def _step(self, x, U, p, h):
        rhs = self.problem.plant.rhs
        k1 = rhs(x, U[:, 0], p)
        k2 = rhs(x + (h / 2) * k1, U[:, 1], p)
        k3 = rhs(x + (h / 2) * k2, U[:, 1], p)
        k4 = rhs(x + h * k3, U[:, 2], p)
        return x + (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4), k1
