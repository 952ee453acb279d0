"""Integration of a plant with a :class:`~mbsym.simulate.controller.DiscreteController` in the loop.

See :mod:`mbsym.simulate.controller` for the conventions (samples, zero-order hold, results).
:func:`run_closed_loop` chooses the RK4 sub-steps per sample (given, or for ``accuracy`` from the
plant's linearized spectrum, checked by step doubling on the sub-steps), then runs either one
generated ``mapaccum`` over samples (CasADi law) or a Python loop over samples around a compiled
plant loop (Python law); long runs are chunked for progress and Ctrl-C.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ..exceptions import DimensionError, IntegrationError, SimulationOptionError
from .base import BufferedFunction, Problem, dense_rhs, maybe_compile, prepared
from .checks import first_bad_column, raise_diverged
from .controller import BoundController, DiscreteController
from .fixed import RK4, PreparedLoop
from .held_carry import HeldCarry
from .held_multistep import HELD_METHODS, MULTISTEP_METHODS, START_STEPS, MultistepHistory
from .held_rk4 import HeldRK4, held_rk4_step
from .monitor import CHUNK_WALL_S, SimulationInterrupted
from .sample_loops import chunk_length, sample_loop

__all__ = ["run_closed_loop", "CALLABLE_BATCH"]

#: Per-sample cost [s] of the generated body from which samples are run one call each rather than in a
#: ``mapaccum`` (:class:`.sample_loops.StepLoop`): the blade-element turbine's ~30-200 µs, not the rotor-effective one's ~6 µs.
STEPWISE_FROM_S = 20e-6
#: Samples per batch of a Python law: inputs sampled and outputs interpolated per batch (Ctrl-C and progress
#: are handled between batches; a Ctrl-C inside the law ends the run at once).
CALLABLE_BATCH = 256


# ------------------------------------------------------------------------------------------- runs
@dataclass
class Extra:
    """Columns the closed loop adds to a result: inputs as applied, controller states."""

    u: np.ndarray
    y: np.ndarray
    names: tuple[str, ...]
    units: tuple[str, ...]
    #: The plant's outputs at the output times the loop evaluated them (sample starts, "rk4-held"), NaN rows
    #: elsewhere; None: none evaluated in the loop.
    plant_y: np.ndarray | None = None


def run_closed_loop(bc: BoundController, plant, x0, p, signal, times, tmax, *, accuracy, dt, compile, monitor):
    """Integrate plant + controller; ``(X on times, statistics, Extra)``."""
    from .auto import BACKGROUND_COMPILE_MIN_S, CHECK_SAMPLES, MAX_REFINEMENTS, epsilon, plant_step
    from .monitor import check_resources

    c = bc.ctrl
    u_init = signal.at(0.0)
    t0 = time.perf_counter()
    if bc.substep_dt is not None:
        m, reason = int(round(c.dt / bc.substep_dt)), f"{bc.method}, dt = {bc.substep_dt:.4g} s (given)"
    elif accuracy is None:
        m = max(1, int(math.ceil(c.dt / RK4.default_dt - 1e-9)))
        reason = f"rk4, {m} sub-step(s) of at most {RK4.default_dt} s per sample"
    else:
        ps = plant_step(plant, x0, u_init, p, tmax, accuracy, h_max=c.dt)
        h = min(ps.h_accuracy, 0.95 * ps.h_stability, c.dt) if math.isfinite(ps.h_accuracy) else c.dt / 4
        m = max(1, int(math.ceil(c.dt / h - 1e-9)))
        reason = (f"rk4, {m} sub-step(s) of {c.dt / m:.4g} s per {c.dt:g} s sample, from the linearized spectrum "
                  f"at t = 0 (|λ|max = {ps.rho:.3g} 1/s)")
    select_s = time.perf_counter() - t0
    loop = _ClosedLoop(bc, plant, x0, p, signal, tmax)
    check_resources(times.size, 1, float(loop.samples) * m, tmax,
                    fewer_steps="use a longer controller sample time or fewer sub-steps")
    on, compile_reason = _compilation(loop, m, compile, accuracy is not None, BACKGROUND_COMPILE_MIN_S)
    res = loop.run(times, m, on, monitor)
    wall = res.stats["integration_wall_s"]
    estimate = None
    repeatable = c.is_function or callable(getattr(c.law, "reset", None))
    checks = MAX_REFINEMENTS + 1 if accuracy is not None and repeatable else 0
    for attempt in range(checks):
        _reset(c)
        # step doubling on the sub-steps (the samples stay): half of them when possible, else twice as many
        if m >= 2 and m % 2 == 0:
            sub = slice(None, None, max(1, int(math.ceil(times.size / CHECK_SAMPLES))))
            chk = loop.run(times[sub], m // 2, on, None)
            estimate = epsilon(res.x[sub], chk.x) / 15.0
        else:                                           # the finer run is the answer
            chk = loop.run(times, 2 * m, on, None)
            estimate = epsilon(chk.x, res.x) / 15.0
            res, m = chk, 2 * m
        wall += chk.stats["integration_wall_s"]
        if estimate <= accuracy or attempt == MAX_REFINEMENTS:
            break
        grow = (estimate / (0.7 * accuracy)) ** 0.25 if math.isfinite(estimate) else 4.0
        m = 2 * int(math.ceil(m * min(max(grow, 1.2), 10.0) / 2))      # even: the next check halves it
        reason += f"; refined to {m} sub-steps after the check estimated ε = {estimate:.2g}"
        _reset(c)
        res = loop.run(times, m, on, monitor)
        wall += res.stats["integration_wall_s"]
    stats = res.stats
    if accuracy is not None and not repeatable:
        stats.update(accuracy=accuracy, check="none: a Python controller without reset() may keep hidden state "
                     "(a DISCON library does), so the loop is not run again; the step is the linear prediction's")
    stats["integration_wall_s"] = wall
    if estimate is not None:
        stats.update(error_estimate=estimate, accuracy=accuracy, check="step doubling (sub-steps per sample)")
        if estimate > accuracy:
            stats["message"] += f" The error estimate {estimate:.2g} is above the requested accuracy {accuracy:g}."
    stats.update(selection=reason, selection_wall_s=select_s, compile_choice=compile_reason,
                 controller_samples=res.samples, substeps=m, dt=res.h)
    stats["prepare_wall_s"] = stats.get("prepare_wall_s", 0.0) + select_s
    return res.x, stats, Extra(res.u, res.xc, c.state_names, tuple(getattr(c, "state_units", ("",) * c.n_shown)), res.y)


def _reset(c) -> None:
    """Before a repeated run: a Python law with ``reset()`` starts again from its initial state."""
    if not c.is_function and callable(getattr(c.law, "reset", None)):
        c.law.reset()


def _compilation(loop: "_ClosedLoop", m: int, compile, auto: bool, threshold: float) -> tuple[bool, str]:
    if compile is not None:
        return bool(compile), f"compile={compile}"
    if not auto:
        return False, "virtual machine (explicit method)"
    from .. import codegen

    if loop.bc.ctrl.is_function:
        f = loop.body(m)
        vm = loop.sample_seconds(f) * loop.samples * 1.5
    else:                                   # a Python law: the plant's RK4 step is what may be compiled
        f = loop.rk4.symbolic_step()
        vm = loop.rk4._step_seconds(f, loop.x0) * loop.samples * m * 1.5
    if vm <= threshold:
        return False, f"virtual machine: ~{1e3 * vm:.3g} ms"
    if codegen.compile_disabled() or codegen.compiler_command() is None:
        return False, "virtual machine: compilation unavailable"
    if codegen.cached_library(f) is not None:
        return True, "compiled: its library is in the disk cache"
    cost = codegen.estimate_compile_seconds(f)
    if vm > cost:
        return True, f"compiled: ~{vm:.2g} s in the virtual machine against ~{cost:.2g} s of compiling"
    codegen.compile_in_background(f)
    return False, f"virtual machine: ~{1e3 * vm:.3g} ms, below ~{cost:.2g} s of compiling; compiling in the background"


@dataclass
class _Run:
    x: np.ndarray
    u: np.ndarray
    xc: np.ndarray
    stats: dict
    samples: int
    h: float
    y: np.ndarray | None = None


class _ClosedLoop:
    """The sampled-data loop of one simulate() call (see the module docstring)."""

    def __init__(self, bc: BoundController, plant, x0, p, signal, tmax) -> None:
        self.bc, self.plant, self.x0, self.p, self.signal, self.tmax = bc, plant, x0, p, signal, tmax
        c = bc.ctrl
        self.samples = max(int(math.ceil(tmax / c.dt - 1e-9)), 1)
        self.u_init = signal.at(0.0)[bc.act]
        dummy = Problem(plant, x0, p, signal, np.array([0.0]), tmax, dt=c.dt, n_steps=1)
        self.rk4 = (HeldRK4 if bc.method in HELD_METHODS else RK4)(dummy)
        self._shares: bool | None = None
        #: Whether the body returns the derivative at each sample's end (the dense output between samples needs
        #: it; when every output time is a sample start it does not, and one right-hand side per sample is saved).
        self.end_derivative = True

    # ---------------------------------------------------------------- the generated body
    def body(self, m: int) -> ca.Function:
        """``(z = [x; xc; u_held], Uexo (n_u, 3m), p, h) -> (z_next, aux)``: law, then m RK4 sub-steps."""
        return self.body_with_hit(m)[0]

    def body_with_hit(self, m: int) -> tuple[ca.Function, bool]:
        """:meth:`body` and whether it came from the in-process cache (:func:`~.base.prepared`)."""
        plant, bc = self.plant, self.bc

        def build():
            n_x, n_u, n_a, n_xc = plant.n_x, plant.n_u, bc.act.size, bc.ctrl.n_xc
            carried = self.carries_held(m)
            hc = self.held_carry() if carried else None
            n_c = hc.n_carry if carried else 0
            ms = self.multistep()
            z, U = ca.MX.sym("z", n_x + n_xc + n_a + n_c + (ms.n_carry if ms else 0)), ca.MX.sym("U", n_u, 3 * m)
            p, hf = ca.MX.sym("p", plant.n_p), ca.MX.sym("h", self.n_h_rows(m))
            h = hf[0]
            x, xc, ua_prev = z[:n_x], z[n_x:n_x + n_xc], z[n_x + n_xc:n_x + n_xc + n_a]
            keep, put = _masks(n_u, bc.act)
            u_meas = ca.mtimes(keep, U[:, 0]) + ca.mtimes(put, ua_prev)
            shared = self._shares_held_part()
            outputs = self.outputs_in_loop(m)
            if carried:                   # refreshed where the last row of h asks, else carried; extrapolated
                case = hf[-1] + hf[1] if outputs else hf[-1]
                carry, held_z = hc.refresh(case, x, u_meas, p, z[n_x + n_xc + n_a:n_x + n_xc + n_a + n_c])
                offsets = [0.0, h / 2, h] if ms is None else [0.0, h][:1 + int(ms.corrects or self.end_derivative)]
                stages = tuple(hc.scatter(v) for v in hc.stage_values(carry, offsets))
                y = bc.measure_held(x, u_meas, p, stages[0])
            elif shared:                  # one evaluation of the held part serves measurement and first step
                held_z = plant.held.part(x, u_meas, p)
                y = bc.measure_held(x, u_meas, p, held_z)
            else:
                y = bc.measure(x, u_meas, p)
            xc1, ua = bc.ctrl.law(xc, y)
            Uh = ca.mtimes(keep, U) + ca.repmat(ca.mtimes(put, ua), 1, 3 * m)
            if ms is not None:            # a multistep method: its derivative history after the held part's
                hist = z[n_x + n_xc + n_a + n_c:]
                Xs, K1, hist1 = ms.step(ms.index(hist, h), x, Uh, p, h, stages[0], stages[-1], hist)
                k_end = plant.held.rhs(Xs, Uh[:, -1], p, stages[-1]) if self.end_derivative else ca.MX.zeros(n_x)
                z_next = ca.vertcat(Xs, xc1, ua, hc.advanced(carry, h), hist1)
            elif carried:
                x1, K1 = held_rk4_step(plant.held, x, Uh, p, h, stages)
                Xs = x1
                k_end = plant.held.rhs(x1, Uh[:, -1], p, stages[2]) if self.end_derivative else ca.MX.zeros(n_x)
                z_next = ca.vertcat(x1, xc1, ua, hc.advanced(carry, h))
            else:
                Xs, K1, k_end = self._substeps(x, Uh, p, h, m, held_z if shared else None, self.end_derivative)
                z_next = ca.vertcat(Xs[:, -1], xc1, ua)
            aux = ca.vertcat(ca.vec(Xs), ca.vec(K1), k_end, xc1[:bc.ctrl.n_shown], ua)   # hidden states not recorded
            if outputs:   # the outputs at the sample start, from the held part already evaluated, where h[1] asks
                aux = ca.vertcat(aux, _outputs_when(plant)(x, Uh[:, 0], p, held_z, hf[1]))
            # dense: a structural zero (a law whose command is a constant 0) is not written by a buffered call
            z_next, aux = ca.densify(z_next), ca.densify(aux)
            return ca.Function(f"{plant.name}_closed_loop_{m}", [z, U, p, hf], [z_next, aux],
                               ["z", "U", "p", "h"], ["z_next", "aux"])

        return prepared(self.plant.owner, ("closed-loop body", id(bc.ctrl.law), bc.act.tobytes(),
                                           bc.ctrl.measurements, m, bc.method, self.carries_held(m),
                                           bc.held_order, self.end_derivative), build)

    def held_carry(self) -> HeldCarry:
        """The carried held part (:mod:`.held_carry`) of this loop's plant, measurements and order."""
        bc = self.bc
        return prepared(self.plant.owner, ("held carry", bc.ctrl.measurements, bc.held_order,
                                           bc.held_samples * bc.ctrl.dt),
                        lambda: HeldCarry(self.plant, bc.measure_held, bc.held_order,
                                          bc.held_samples * bc.ctrl.dt))[0]

    def multistep(self) -> MultistepHistory | None:
        """The derivative history of a multistep method (:mod:`.held_multistep`), else None."""
        bc = self.bc
        if bc.method not in MULTISTEP_METHODS:
            return None
        return prepared(self.plant.owner, ("multistep history", bc.method, bc.ctrl.dt),
                        lambda: MultistepHistory(self.plant, bc.method, bc.ctrl.dt))[0]

    def carries_held(self, m: int) -> bool:
        """Whether the held part is carried from sample to sample (``held_dt`` > the sample time, extrapolated
        with ``held_order`` > 0, or a multistep method)."""
        multi = self.bc.method in MULTISTEP_METHODS
        if self.bc.held_samples <= 1 and self.bc.held_order == 0 and not multi:
            return False
        if m != 1 or not self._shares_held_part():
            what = f"method {self.bc.method!r}" if multi else "held_dt > the sample time or held_order > 0"
            raise SimulationOptionError(
                f"{what} needs one step per controller sample and a held "
                f"part that does not depend on the commanded inputs {list(self.bc.ctrl.actuates)} (the commands change "
                f"at every sample); got {m} step(s) per sample"
                + ("" if self._shares_held_part() else " and a dependent held part") + ".")
        return True

    def n_h_rows(self, m: int) -> int:
        """Rows of the body's ``h``: the step; whether the outputs are wanted; whether the held part is refreshed."""
        return 1 + int(self.outputs_in_loop(m)) + int(self.carries_held(m))

    def initial_carry(self, m: int) -> np.ndarray:
        """``z`` at the first sample: plant, controller, held commands (and a placeholder for the held part)."""
        pad = self.held_carry().initial() if self.carries_held(m) else np.zeros(0)
        hist = self.multistep().initial() if self.multistep() is not None else np.zeros(0)
        return np.concatenate([self.x0, self.bc.ctrl.x0, self.u_init, pad, hist])

    def h_rows(self, k0: int, start: np.ndarray, length: np.ndarray, m: int, collector) -> np.ndarray:
        """The body's ``h`` for samples ``k0, k0 + 1, ...`` (see :meth:`n_h_rows`)."""
        rows = [length / m]
        wanted = collector.wanted(start) if self.outputs_in_loop(m) else np.zeros(start.size)
        if self.outputs_in_loop(m):
            rows.append(wanted)
        if self.carries_held(m):             # every held_samples-th sample, and where outputs are wanted
            due = (np.arange(k0, k0 + start.size) % self.bc.held_samples == 0).astype(float)
            rows.append(np.maximum(due, wanted))
        return np.vstack(rows)

    def outputs_in_loop(self, m: int) -> bool:
        """Whether the body returns the plant's outputs at every sample start (shared held part, m = 1)."""
        return m == 1 and self._shares_held_part() and self.plant.output_function is not None

    def _shares_held_part(self) -> bool:
        """With "rk4-held" and one sub-step per sample, the held part at the sample serves the measurement
        and the step when it does not depend on the commanded inputs (the commands change at the sample)."""
        if self._shares is None:
            held = self.plant.held if self.bc.method in HELD_METHODS else None
            self._shares = held is not None and held.outputs is not None and \
                not held.depends_on_inputs(self.bc.act)
        return self._shares

    def _substeps(self, x, Uh, p, h, m: int, held_z, end: bool = True):
        """``m`` sub-steps from ``x`` with inputs ``Uh`` (n_u, 3 m): states, stage-1 derivatives and the
        derivative at the end (for the dense output; zeros when ``end`` is False)."""
        plant = self.plant
        if held_z is not None and m == 1:
            x1, k1 = held_rk4_step(plant.held, x, Uh, p, h, held_z)
            return x1, k1, plant.held.rhs(x1, Uh[:, -1], p, held_z) if end else ca.MX.zeros(plant.n_x)
        step = self.rk4.symbolic_step()
        inner = step.mapaccum(f"{step.name()}_sub{m}", m, [0], [0])
        Xs, K1 = inner(x, Uh, ca.repmat(p, 1, m), ca.repmat(h, 1, m))
        return Xs, K1, plant.rhs(Xs[:, -1], Uh[:, -1], p) if end else ca.MX.zeros(plant.n_x)

    def sample_seconds(self, f: ca.Function) -> float:
        """Wall time of one sample of the body ``f`` [s] (buffered calls, best of two)."""
        z = np.concatenate([self.x0, self.bc.ctrl.x0, self.u_init])
        z = np.concatenate([z, np.zeros(f.numel_in(0) - z.size)])
        U = np.repeat(self.signal.at(0.0)[:, None], f.size2_in(1), axis=1)
        args = [z, np.asfortranarray(U).reshape(-1, order="F"), np.ascontiguousarray(self.p, dtype=float),
                np.array([self.bc.ctrl.dt, 1.0, 1.0][:f.numel_in(3)])]
        outs = [np.empty(f.numel_out(i)) for i in range(f.n_out())]
        buf, trigger = f.buffer()
        for i, a in enumerate(args):
            buf.set_arg(i, memoryview(a))
        for i, o in enumerate(outs):
            buf.set_res(i, memoryview(o))
        best = math.inf
        for _ in range(2):
            t0 = time.perf_counter()
            trigger()
            best = min(best, time.perf_counter() - t0)
        return best

    # ---------------------------------------------------------------- running
    def run(self, times: np.ndarray, m: int, compiled: bool, monitor) -> _Run:
        t0 = time.perf_counter()
        self.end_derivative = not _on_sample_starts(times, self.bc.ctrl.dt / m, self.tmax)
        if self.bc.ctrl.is_function:
            body, hit = self.body_with_hit(m)
            body, on, disk_hit = maybe_compile(body, compiled, with_hit=True)
            prep = time.perf_counter() - t0
            out = self._run_function(body, times, m, monitor)
        else:
            if self.bc.method in MULTISTEP_METHODS:
                raise SimulationOptionError(f"method {self.bc.method!r} carries its derivative history inside the "
                                            f"generated loop; the controller {self.bc.ctrl.name!r} is a Python "
                                            "callable (e.g. a DISCON library): use method='rk4-held' (or 'rk4').")
            if self.bc.held_samples > 1 or self.bc.held_order > 0:
                raise SimulationOptionError(f"held_dt > the sample time and held_order > 0 run inside the generated "
                                            f"loop; the controller {self.bc.ctrl.name!r} is a Python callable (e.g. a "
                                            "DISCON library): leave held_dt and held_order unset.")
            step, on, disk_hit = maybe_compile(self.rk4.symbolic_step(), compiled, with_hit=True)
            loop, hit = prepared(self.plant.owner, ("closed-loop substeps", id(step), m),
                                 lambda: PreparedLoop(step, m, on))
            rhs_f, _, rhs_hit = maybe_compile(dense_rhs(self.plant), compiled, with_hit=True)
            meas_f, _, meas_hit = maybe_compile(self.bc.measure, compiled, with_hit=True)   # once per sample too
            disk_hit = disk_hit and rhs_hit and meas_hit
            rhs = BufferedFunction(rhs_f, self.p)
            meas = BufferedFunction(meas_f, self.p)
            prep = time.perf_counter() - t0
            out = self._run_callable(loop, rhs, meas, times, m, monitor)
        if self.bc.held_samples > 1 or self.bc.held_order > 0:
            out.stats.update(held_dt=self.bc.held_samples * self.bc.ctrl.dt, held_order=self.bc.held_order)
        out.stats.update(prepare_wall_s=prep, compiled=on, method=self.bc.method, cache_hit=bool(hit),
                         disk_cache_hit=bool(disk_hit) if on else None,   # as Method.solve: None when nothing loaded
                         success=True, n_jac=0)
        return out

    def _sample_grid(self, k0: int, k1: int) -> tuple[np.ndarray, np.ndarray]:
        """Start times and lengths of samples k0..k1-1 (the last one ends at tmax)."""
        c = self.bc.ctrl
        start = np.arange(k0, k1) * c.dt
        end = np.minimum(start + c.dt, self.tmax)
        return start, end - start

    def _exogenous(self, start: np.ndarray, length: np.ndarray, m: int) -> np.ndarray:
        """Inputs at the RK4 stage times of every sub-step, (n_u, 3 m n_samples)."""
        j = np.arange(m)[:, None] + np.array([0.0, 0.5, 1.0])[None, :]          # (m, 3) in sub-steps
        t = start[:, None, None] + (length / m)[:, None, None] * j[None, :, :]
        return self.signal(t.reshape(-1)).T

    def _run_function(self, body: ca.Function, times, m, monitor) -> _Run:
        n_x, n_xc = self.plant.n_x, self.bc.ctrl.n_shown
        z = self.initial_carry(m)
        collector = _Collector(self, times, m)
        K, k0, per, wall, cpu = self.samples, 0, 0.0, 0.0, 0.0
        first = self.sample_seconds(body) if K > 64 else None
        stepwise = first is not None and first >= STEPWISE_FROM_S
        try:
            while k0 < K:
                L = (K if first is None else chunk_length(K, first)) if k0 == 0 else chunk_length(K - k0, per)
                loop = sample_loop(self.plant.owner, body, L, stepwise)
                start, length = self._sample_grid(k0, k0 + L)
                U = self._exogenous(start, length, m)
                t1, c1 = time.perf_counter(), time.process_time()
                H = self.h_rows(k0, start, length, m, collector)
                Zn, A = loop.run(z, U, self.p, H)
                dt_run = time.perf_counter() - t1
                wall += dt_run
                cpu += time.process_time() - c1
                per = max(dt_run / L, 1e-8)
                Xs = A[: n_x * m].reshape(n_x, m, L, order="F")
                K1 = A[n_x * m: 2 * n_x * m].reshape(n_x, m, L, order="F")
                k_end = A[2 * n_x * m: 2 * n_x * m + n_x]
                xc = A[2 * n_x * m + n_x: 2 * n_x * m + n_x + n_xc]
                off = 2 * n_x * m + n_x + n_xc
                ua, Y = A[off:off + self.bc.act.size], A[off + self.bc.act.size:]
                collector.add(k0, z[:n_x], Xs, K1, k_end, xc, ua, start, length,
                              Y if self.outputs_in_loop(m) else None)
                z = Zn[:, -1].copy()
                k0 += L
                if monitor is not None:
                    monitor.update(float(min(k0 * self.bc.ctrl.dt, self.tmax)))
        except KeyboardInterrupt:
            raise SimulationInterrupted(min(k0 * self.bc.ctrl.dt, self.tmax), collector.partial()) from None
        out = collector.result(wall, m)
        out.stats["integration_cpu_s"] = cpu            # CPU of this process in the loop (wall counts neighbours)
        return out

    def _run_callable(self, loop: PreparedLoop, rhs, meas, times, m, monitor) -> _Run:
        """One Python call of the law per sample; samples batched in chunks for inputs and outputs."""
        c, n_x, act = self.bc.ctrl, self.plant.n_x, self.bc.act
        x, xc, ua = self.x0.copy(), c.x0.copy(), self.u_init.copy()
        collector = _Collector(self, times, m)
        step = loop.runner(self.p)
        wall, k0, j, last_report = 0.0, 0, 0, time.perf_counter()
        try:
            while k0 < self.samples:
                L = min(CALLABLE_BATCH, self.samples - k0)
                start, length = self._sample_grid(k0, k0 + L)
                U_all = self._exogenous(start, length, m)            # (n_u, 3 m L)
                Xs, K1 = np.empty((n_x, m, L)), np.empty((n_x, m, L))
                KE, XC, UA = np.empty((n_x, L)), np.empty((c.n_shown, L)), np.empty((act.size, L))
                x_start = x.copy()
                t1 = time.perf_counter()
                for j in range(L):
                    U = U_all[:, 3 * m * j: 3 * m * (j + 1)]
                    u_meas = U[:, 0].copy()
                    u_meas[act] = ua
                    y = meas(x, u_meas).reshape(-1)
                    xc, ua = _call_law(c, float(start[j]), xc, y)
                    U[act, :] = ua[:, None]
                    Zn, K = step(x, U, float(length[j]) / m)
                    Xs[:, :, j], K1[:, :, j] = Zn, K
                    KE[:, j] = rhs(Zn[:, -1], U[:, -1])
                    XC[:, j], UA[:, j] = xc[:c.n_shown], ua
                    x = Zn[:, -1].copy()
                wall += time.perf_counter() - t1
                collector.add(k0, x_start, Xs, K1, KE, XC, UA, start, length)
                k0, j = k0 + L, 0
                if monitor is not None and time.perf_counter() - last_report > CHUNK_WALL_S:
                    monitor.update(float(min(k0 * c.dt, self.tmax)))
                    last_report = time.perf_counter()
        except KeyboardInterrupt:
            if k0 < self.samples and j > 0:                  # the samples of this batch done before Ctrl-C
                collector.add(k0, x_start, Xs[:, :, :j], K1[:, :, :j], KE[:, :j], XC[:, :j], UA[:, :j], start[:j],
                              length[:j])
            raise SimulationInterrupted(min((k0 + j) * c.dt, self.tmax), collector.partial()) from None
        return collector.result(wall, m)


def _outputs_when(plant) -> ca.Function:
    """``(x, u, p, z, flag) -> y``: the held outputs when flag > 0.5, else zeros, evaluated only then (a
    short-circuit ``if_else`` inside its own Function: given the body's expressions, the branch would take
    the body's symbols as inputs and evaluate the held part again)."""
    held = plant.held
    x, u, p = ca.MX.sym("x", plant.n_x), ca.MX.sym("u", plant.n_u), ca.MX.sym("p", plant.n_p)
    z, flag = ca.MX.sym("z", held.n_z), ca.MX.sym("flag")
    y = ca.vec(held.outputs(x, u, p, z))
    return ca.Function(f"{plant.name}_outputs_when", [x, u, p, z, flag],
                       [ca.if_else(flag > 0.5, y, ca.MX.zeros(y.numel()), True)])


def _on_sample_starts(times: np.ndarray, h: float, tmax: float) -> bool:
    """Whether every output time is the start of a sub-step (the last may be ``tmax``, a sub-step's end)."""
    inner = times[times < tmax * (1 - 1e-12)]
    k = inner / h
    return bool(np.all(np.abs(k - np.round(k)) <= 1e-9 * np.maximum(k, 1.0)))


def _masks(n_u: int, act: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``keep`` (n_u, n_u): zero on actuated rows; ``put`` (n_u, n_a): places u_ctrl on them."""
    keep = np.eye(n_u)
    keep[act, act] = 0.0
    put = np.zeros((n_u, act.size))
    put[act, np.arange(act.size)] = 1.0
    return keep, put


def _call_law(c: DiscreteController, t: float, xc: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if c.is_function:
        xc1, ua = c.law(xc, y)
        return np.asarray(xc1, dtype=float).reshape(-1), np.asarray(ua, dtype=float).reshape(-1)
    out = c.law(t, xc.copy(), y.copy())
    if not (isinstance(out, (tuple, list)) and len(out) == 2):
        raise DimensionError(f"controller {c.name!r}: law(t, xc, y) must return (xc_next, u); got {type(out).__name__} "
                             f"at t = {t:g} s.")
    try:
        xc1 = np.asarray(out[0], dtype=float).reshape(-1)
        ua = np.asarray(out[1], dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise DimensionError(f"controller {c.name!r}: law returned non-numeric values at t = {t:g} s.") from None
    if xc1.size != c.n_xc or ua.size != len(c.actuates):
        raise DimensionError(f"controller {c.name!r}: law(t, xc, y) returned xc_next of {xc1.size} and u of {ua.size} "
                             f"values at t = {t:g} s; expected {c.n_xc} and {len(c.actuates)} ({list(c.actuates)}).")
    if not (np.all(np.isfinite(xc1)) and np.all(np.isfinite(ua))):
        raise IntegrationError(f"controller {c.name!r} returned non-finite values at t = {t:g} s: xc_next = "
                               f"{xc1.tolist()}, u = {ua.tolist()}.")
    return xc1, ua


class _Collector:
    """Outputs of a closed-loop run at the requested times, chunk by chunk (Hermite within each sub-step)."""

    def __init__(self, loop: _ClosedLoop, times: np.ndarray, m: int) -> None:
        self.loop, self.times, self.m = loop, times, m
        n_x, c = loop.plant.n_x, loop.bc.ctrl
        self.x = np.empty((times.size, n_x))
        self.u = np.empty((times.size, loop.plant.n_u))
        self.xc = np.empty((times.size, c.n_shown))
        self.done = 0
        self.steps = 0
        self.h = c.dt / m
        self.y = (np.full((times.size, len(loop.plant.output_names)), np.nan) if loop.outputs_in_loop(m)
                  else None)

    def add(self, k0, x_start, Xs, K1, k_end, xc, ua, start, length, Y=None) -> None:
        """Samples k0.. of one chunk: sub-step end states Xs (n_x, m, L), start derivatives K1, end derivatives
        and, when the loop evaluates them, the plant's outputs at the sample starts Y (n_y, L)."""
        lp, m = self.loop, self.m
        n_x, L = Xs.shape[0], Xs.shape[2]
        bad = first_bad_column(Xs.reshape(n_x, -1, order="F"), lp.x0)
        if bad is not None:
            j = bad // m
            raise_diverged(lp.bc.method, float(start[j] + (bad % m + 1) * length[j] / m), float(length[j] / m),
                           Xs.reshape(n_x, -1, order="F")[:, bad], lp.plant.states, lp.x0,
                           where=f"controller sample {k0 + j + 1} of {lp.samples}")
        self.steps += L * m
        t_end = float(start[-1] + length[-1])
        last = k0 + L == lp.samples
        hi = self.times.size if last else int(np.searchsorted(self.times, t_end * (1 - 1e-12), side="left"))
        if hi <= self.done:
            return
        t = self.times[self.done:hi]
        # sample and sub-step of each output time
        j = np.clip(np.searchsorted(start, t * (1 + 1e-12) + 1e-12, side="right") - 1, 0, L - 1)
        h = length[j] / m
        s_abs = (t - start[j]) / h
        i = np.clip(np.floor(s_abs + 1e-9).astype(int), 0, m - 1)
        s = np.clip(s_abs - i, 0.0, 1.0)[:, None]
        XL = np.where((i == 0)[:, None], x_start_rows(x_start, Xs, j), Xs[:, np.maximum(i - 1, 0), j].T)
        if np.any(s):                   # Hermite within the sub-steps; at their starts (s = 0) it is XL itself
            XR = Xs[:, i, j].T
            FL = K1[:, i, j].T
            FR = np.where((i == m - 1)[:, None], k_end[:, j].T, K1[:, np.minimum(i + 1, m - 1), j].T)
            hh = h[:, None]
            s2, s3 = s * s, s * s * s
            XL = ((2 * s3 - 3 * s2 + 1) * XL + (s3 - 2 * s2 + s) * hh * FL
                  + (3 * s2 - 2 * s3) * XR + (s3 - s2) * hh * FR)
        self.x[self.done:hi] = XL
        U = lp.signal(t)
        U[:, lp.bc.act] = ua[:, j].T
        self.u[self.done:hi] = U
        self.xc[self.done:hi] = xc[:, j].T
        if Y is not None:
            at_start = (i == 0) & (s[:, 0] <= 1e-9) & (self.wanted(start)[j] > 0.5)     # the rows evaluated
            rows = self.done + np.flatnonzero(at_start)
            self.y[rows] = Y[:, j[at_start]].T
        self.done = hi

    def wanted(self, start: np.ndarray) -> np.ndarray:
        """1.0 for the samples whose start is an output time (to the tolerance of :meth:`add`), else 0.0."""
        k = np.clip(np.searchsorted(self.times, start), 0, self.times.size - 1)
        k0 = np.maximum(k - 1, 0)
        near = np.minimum(np.abs(self.times[k] - start), np.abs(self.times[k0] - start))
        return (near <= 1e-9 * self.h).astype(float)

    def partial(self):
        return self.times[: self.done], self.x[: self.done].copy()

    def result(self, wall: float, m: int) -> _Run:
        lp = self.loop
        stats = {"steps": self.steps, "n_rhs": self.steps * 4 + lp.samples, "integration_wall_s": wall,
                 "message": f"{lp.samples} controller samples of {lp.bc.ctrl.dt:g} s, {m} {lp.bc.method} sub-step(s) each, "
                            f"up to t = {lp.tmax:g} s."}
        if lp.bc.method in MULTISTEP_METHODS:        # RK4 for the start-up (and a shorter last step)
            start = min(START_STEPS, self.steps)
            stats["n_rhs"] = (start * 4 + (self.steps - start) * MULTISTEP_METHODS[lp.bc.method]
                              + int(lp.end_derivative) * self.steps)
            stats["message"] = stats["message"][:-1] + f" (the first {start} by RK4, as ElastoDyn starts its history)."

        return _Run(self.x, self.u, self.xc, stats, lp.samples, lp.bc.ctrl.dt / m, self.y)


def x_start_rows(x_start: np.ndarray, Xs: np.ndarray, j: np.ndarray) -> np.ndarray:
    """State at the start of samples ``j`` of a chunk: x_start for the first, else the previous sample's end."""
    prev = Xs[:, -1, np.maximum(j - 1, 0)].T
    return np.where((j == 0)[:, None], x_start[None, :], prev)
