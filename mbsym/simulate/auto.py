"""The accuracy-driven default of :func:`mbsym.simulate`: method, step and compilation from ``accuracy``.

``accuracy`` (default :data:`DEFAULT_ACCURACY` = 1e-3) bounds the error against the converged
solution in the metric of the benchmarks (``benchmarks/work_precision.py``):

    ε = max over states of mean_t |x(t) - x_ref(t)| / range_t(x_ref)

on the output times (states whose range is zero are left out).

How the run is chosen (all of it reported in ``result.statistics``):

1. **Linearized spectrum.** ``J = df/dx`` at the initial state (central differences of the rhs:
   2 n_x evaluations, no Jacobian Function to build) and ``f0 = f(x0, u(0), p)``.
2. **RK4's error on that linear model, exactly.** The affine model ``y' = J y + f0`` (``y = x - x0``)
   is propagated by RK4's stability polynomial ``P(Jh) = I + Jh + (Jh)^2/2 + (Jh)^3/6 + (Jh)^4/24``
   (its known error constant for every mode at once, damping and phase) and by the exact
   exponential, over the whole run, on at most 400 sample times; ``ε_lin(h)`` is the metric above
   between the two. A few secant steps in ``log h`` (``ε ~ h^4``) give the largest step with
   ``ε_lin(h) <= SAFETY * accuracy``; the step also keeps ``|P(λh)| <= 1`` for every eigenvalue
   ``λ`` of J (stiff modes that are not excited still bound an explicit method).
3. **Stiffness.** The same prediction without the strongly damped modes (damping ratio >= 0.5:
   transients an A-stable method steps over) gives the step such a method would need; when RK4's
   step (accuracy and stability) is below 1/:data:`STIFF_RATIO` of it, RK4 would spend its steps
   on stability: BDF (``cvodes``, exact Jacobian) with ``rtol = accuracy *``
   :data:`BDF_RTOL_FACTOR` runs instead. Fast modes that are lightly damped (a blade's edgewise
   mode) are not stiff in this sense: BDF would have to resolve them as well.
4. **Compilation.** The RK4 step runs compiled (generated C, :mod:`mbsym.codegen`) when its library
   is already in the disk cache, or when the predicted run in CasADi's virtual machine (one step
   timed, times the steps) costs more than compiling (:func:`mbsym.codegen.estimate_compile_seconds`).
   Otherwise it runs in the virtual machine, and when that run takes more than
   :data:`BACKGROUND_COMPILE_MIN_S`, the step is compiled into the disk cache in a background thread
   so that the next run of the model (in this process or a later one) finds it.
5. **A-posteriori check (step doubling).** The run is repeated with twice the step (half the cost);
   Richardson's estimate ``e_h ~ (x_2h - x_h) / (2^4 - 1)`` gives ``error_estimate``. Above
   ``accuracy``, the step shrinks by ``(accuracy / estimate)^(1/4)`` and the run is redone (at most
   :data:`MAX_REFINEMENTS` times). When twice the step would be unstable, the check runs at half the
   step instead and its (more accurate) result is returned. BDF: runs at ``rtol`` and ``rtol/10``;
   the finer result is returned with the distance between the two as its error estimate.

The linear prediction makes the first run right in most cases; the check makes the estimate
honest for nonlinear motion (a spinning rotor, large rotations) and for inputs that vary in time,
which the linearization at t = 0 does not see. Measured on the work-precision scenes:
``benchmarks/README.md``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import codegen
from ..exceptions import IntegrationError
from .base import Problem
from .fixed import RK4
from .monitor import check_resources

__all__ = ["DEFAULT_ACCURACY", "Selection", "linearized", "predict_rk4_error", "rk4_stability_limit",
           "select", "run_auto", "epsilon"]

#: Default ``accuracy`` of :func:`mbsym.simulate` [-].
DEFAULT_ACCURACY = 1e-3
#: The linear prediction aims at SAFETY x accuracy (the check then confirms) [-].
SAFETY = 0.5
#: BDF instead of RK4 when the stability limit is this many times below the step accuracy allows [-].
STIFF_RATIO = 4.0
#: BDF tolerance: rtol = BDF_RTOL_FACTOR x accuracy (work-precision scenes: ε ~ 3-25 rtol) [-].
BDF_RTOL_FACTOR = 0.05
#: At most this many smaller-step reruns after a failed check.
MAX_REFINEMENTS = 2
#: Compilation is considered (library from the disk cache, or compiled now or in the background for the next
#: runs) only when the run in the virtual machine would take longer than this [s]: below it, loading a
#: library (~10-20 ms: key, dlopen) saves nothing.
BACKGROUND_COMPILE_MIN_S = 0.01
#: At most this many sample times in the linear prediction.
PREDICTION_SAMPLES = 400
#: Steps per run at least (the step is at most tmax / MIN_STEPS).
MIN_STEPS = 8


def epsilon(x: np.ndarray, ref: np.ndarray) -> float:
    """max over states of mean|x - ref| / range(ref) (rows: times; states of zero range skipped)."""
    rng = np.ptp(ref, axis=0)
    keep = rng > 1e-12 * np.maximum(1.0, np.max(np.abs(ref), axis=0))
    if not np.any(keep):
        return float(np.max(np.abs(x - ref), initial=0.0))
    return float(np.max(np.mean(np.abs(x - ref), axis=0)[keep] / rng[keep]))


# ------------------------------------------------------------------------------------------- spectrum
def linearized(rhs, x0: np.ndarray, u0: np.ndarray, p: np.ndarray, owner: Any = None) -> tuple[np.ndarray, np.ndarray]:
    """``(J, f0)``: the rhs Jacobian at ``x0`` by central differences (step ~eps^(1/3)) and ``f(x0)``.

    The 2 n_x + 1 evaluations are one call of the rhs mapped over the points (cached per ``owner``).
    """
    n = x0.size
    d = 6e-6 * np.maximum(1.0, np.abs(x0))
    X = np.repeat(x0[:, None], 2 * n + 1, axis=1)
    X[np.arange(n), 1 + np.arange(n)] += d
    X[np.arange(n), 1 + n + np.arange(n)] -= d
    mapped = _mapped_rhs(rhs, 2 * n + 1, owner)
    F = np.asarray(mapped(X, u0, p), dtype=float).reshape(n, 2 * n + 1)
    J = (F[:, 1: n + 1] - F[:, n + 1:]) / (2 * d[None, :])
    return J, F[:, 0].copy()


def _mapped_rhs(rhs, m: int, owner: Any):
    from .base import prepared

    def build():
        return rhs.map(f"{rhs.name()}_fd", "serial", m, [1, 2], [])      # u and p shared by the m points

    if owner is None:
        return build()
    return prepared(owner, ("finite-difference rhs", m), build)[0]


def _rk4_poly(z):
    return 1 + z + z * z / 2 + z ** 3 / 6 + z ** 4 / 24


def rk4_stability_limit(eigenvalues: np.ndarray) -> float:
    """Largest step [s] with ``|P(λh)| <= 1`` for every eigenvalue with ``Re λ <= 0`` (inf if none limits).

    Bisection along each eigenvalue's ray at once (RK4's region reaches 2.79 on the negative real
    axis and 2.83 on the imaginary one); eigenvalues near zero (rigid-body modes) do not limit.
    """
    lam = np.asarray(eigenvalues, dtype=complex)
    rho = float(np.max(np.abs(lam), initial=0.0))
    lam = lam[(lam.real <= 1e-6 * rho) & (np.abs(lam) > 1e-9 * max(rho, 1e-300))]
    if lam.size == 0:
        return math.inf
    lo, hi = np.zeros(lam.size), np.full(lam.size, 3.0) / np.abs(lam)
    for _ in range(45):
        mid = 0.5 * (lo + hi)
        ok = np.abs(_rk4_poly(lam * mid)) <= 1 + 1e-9
        lo, hi = np.where(ok, mid, lo), np.where(ok, hi, mid)
    return float(np.min(lo))


def _expm(A: np.ndarray) -> np.ndarray:
    """exp(A) by scaling and squaring with a degree-18 Taylor polynomial (numpy only)."""
    norm = float(np.max(np.sum(np.abs(A), axis=0), initial=0.0))
    s = max(0, int(math.ceil(math.log2(norm))) + 1) if norm > 0 else 0
    B = A / 2.0 ** s
    E, term = np.eye(A.shape[0]), np.eye(A.shape[0])
    for k in range(1, 19):
        term = term @ B / k
        E = E + term
    for _ in range(s):
        E = E @ E
    return E


def predict_rk4_error(J: np.ndarray, f0: np.ndarray, tmax: float, h: float,
                      samples: int = PREDICTION_SAMPLES) -> float:
    """ε of RK4 with step ~``h`` on the affine model ``y' = J y + f0`` over ``[0, tmax]`` (see the module).

    The step is adjusted to ``tmax / ceil(tmax / h)``; ε over at most ``samples`` equally spaced steps.
    """
    n_x = J.shape[0]
    n = max(int(math.ceil(tmax / h - 1e-9)), 1)
    h = tmax / n
    stride = max(1, int(math.ceil(n / samples)))
    m = n // stride
    A = np.zeros((n_x + 1, n_x + 1))
    A[:n_x, :n_x], A[:n_x, n_x] = J, f0
    Ah = A * h
    P = np.eye(n_x + 1) + Ah @ (np.eye(n_x + 1) + Ah @ (np.eye(n_x + 1) / 2 + Ah @ (np.eye(n_x + 1) / 6
                                                                                     + Ah / 24)))
    with np.errstate(all="ignore"):
        P = np.linalg.matrix_power(P, stride)
        E = _expm(A * (h * stride))
        y_num, y_ex = _orbit(P, m), _orbit(E, m)
        if not np.all(np.isfinite(y_num)):
            return math.inf
        return epsilon(y_num[:, :n_x], y_ex[:, :n_x])


def _orbit(P: np.ndarray, m: int) -> np.ndarray:
    """Rows ``P^j e`` for j = 0..m, e the last unit vector (the affine term), by doubling: log2(m) products."""
    Y = np.zeros((P.shape[0], 1))
    Y[-1, 0] = 1.0
    Pk = P
    while Y.shape[1] < m + 1:
        Y = np.hstack([Y, Pk @ Y])
        Pk = Pk @ Pk
    return Y[:, : m + 1].T


def _accurate_step(J, f0, tmax, target, h_max) -> tuple[float, float]:
    """Largest step ``h <= h_max`` with predicted ε <= target, and that ε (secant in log h, ε ~ h^4)."""
    rho = float(np.max(np.abs(np.linalg.eigvals(J)), initial=0.0)) if J.size else 0.0
    h = min(h_max, 1.0 / rho) if rho > 0 else h_max
    best = None
    for _ in range(12):
        e = predict_rk4_error(J, f0, tmax, h)
        if e <= target:
            best = (h, e) if best is None or h > best[0] else best
            if h >= h_max * 0.999 or e >= 0.6 * target:
                break
            grow = (0.9 * target / max(e, 1e-300)) ** 0.25
            h = min(h_max, h * min(grow, 8.0))
        else:
            shrink = (0.9 * target / e) ** 0.25 if math.isfinite(e) else 0.1
            h *= min(max(shrink, 0.1), 0.9)
            if best is not None and h <= best[0]:
                break
    return best if best is not None else (h, predict_rk4_error(J, f0, tmax, h))


# ------------------------------------------------------------------------------------------- selection
@dataclass
class Selection:
    """What the accuracy-driven default chose, and why."""

    method: str
    dt: float | None = None
    rtol: float | None = None
    atol: float | None = None
    compile: bool = False
    compile_reason: str = ""
    predicted_error: float = math.nan
    spectral_radius: float = math.nan
    stability_limit: float = math.inf
    reason: str = ""
    background_compile: bool = False


@dataclass
class PlantStep:
    """RK4 on the plant linearized at t = 0: the step accuracy allows, the stability limit, the spectrum."""

    J: np.ndarray
    f0: np.ndarray
    h_accuracy: float
    h_stability: float
    predicted: float
    rho: float

    def predicted_error(self, tmax: float, h: float) -> float:
        return predict_rk4_error(self.J, self.f0, tmax, h)


def plant_step(plant, x0, u0, p, tmax, accuracy, h_max=None) -> PlantStep:
    """:class:`PlantStep` of RK4 on ``plant`` at ``(x0, u0, p)`` for ``accuracy`` over ``[0, tmax]``."""
    J, f0 = linearized(plant.rhs, x0, u0, p, plant.owner)
    if not (np.all(np.isfinite(J)) and np.all(np.isfinite(f0))):
        return PlantStep(J, f0, math.nan, math.nan, math.nan, math.nan)
    lam = np.linalg.eigvals(J) if J.size else np.zeros(0)
    rho = float(np.max(np.abs(lam), initial=0.0))
    h_acc, e = _accurate_step(J, f0, tmax, SAFETY * accuracy, tmax / MIN_STEPS if h_max is None else h_max)
    return PlantStep(J, f0, h_acc, rk4_stability_limit(lam), e, rho)


#: Modes with a damping ratio at least this large are "stiff" candidates: an A-stable method follows
#: their quasi-static response with steps far longer than their time constant [-].
STIFF_DAMPING = 0.5


def nonstiff_step(ps: PlantStep, tmax: float, accuracy: float) -> float:
    """The step an A-stable method of RK4's order would need: strongly damped modes (damping ratio >=
    :data:`STIFF_DAMPING`) removed from the linear model (their decaying transients), the rest kept.

    Returns the step RK4 itself needs when no mode is removed or the eigenvectors are ill-conditioned.
    """
    rk4 = min(ps.h_accuracy, ps.h_stability)
    lam, V = np.linalg.eig(ps.J)
    mag = np.abs(lam)
    stiff = (mag > 1e-9 * max(ps.rho, 1e-300)) & (-lam.real >= STIFF_DAMPING * mag)
    if not np.any(stiff) or np.all(stiff) or np.linalg.cond(V) > 1e10:
        return rk4
    W = np.linalg.inv(V)
    keep = ~stiff
    Jr = np.real(V[:, keep] @ np.diag(lam[keep]) @ W[keep, :])
    fr = np.real(V[:, keep] @ (W[keep, :] @ ps.f0))
    h, _ = _accurate_step(Jr, fr, tmax, SAFETY * accuracy, tmax / MIN_STEPS)
    return min(h, rk4_stability_limit(lam[keep]))


def select(plant, x0: np.ndarray, p: np.ndarray, signal, tmax: float, accuracy: float) -> Selection:
    """Method and step (not compilation yet: see :func:`decide_compilation`) for ``accuracy``."""
    ps = plant_step(plant, x0, signal.at(0.0), p, tmax, accuracy)
    h_acc, h_stab, rho = ps.h_accuracy, ps.h_stability, ps.rho
    if not math.isfinite(h_acc):
        return Selection("cvodes", rtol=BDF_RTOL_FACTOR * accuracy, atol=_atol(x0, BDF_RTOL_FACTOR * accuracy),
                         reason="the rhs is not finite near the initial state (no spectrum): BDF")
    h_rk4 = min(h_acc, h_stab)
    h_free = nonstiff_step(ps, tmax, accuracy)
    if h_free > STIFF_RATIO * h_rk4:
        rtol = BDF_RTOL_FACTOR * accuracy
        return Selection("cvodes", rtol=rtol, atol=_atol(x0, rtol), predicted_error=math.nan, spectral_radius=rho,
                         stability_limit=h_stab,
                         reason=(f"stiff: RK4 would need dt = {h_rk4:.3g} s (stability of strongly damped fast "
                                 f"modes, |λ|max = {rho:.3g} 1/s), {h_free / h_rk4:.0f}x below the {h_free:.3g} s "
                                 f"the slower dynamics need; BDF (cvodes) at rtol = {rtol:.1e}"))
    h = min(h_acc, 0.95 * h_stab)
    n = _even_steps(tmax, h)
    h = tmax / n
    return Selection("rk4", dt=h, predicted_error=ps.predicted_error(tmax, h), spectral_radius=rho,
                     stability_limit=h_stab,
                     reason=(f"rk4, dt = {h:.4g} s from the linearized spectrum at t = 0 (|λ|max = {rho:.3g} 1/s, "
                             f"stable up to {h_stab:.3g} s)"))


def _even_steps(tmax: float, h: float) -> int:
    n = max(int(math.ceil(tmax / h - 1e-9)), MIN_STEPS)
    return n + (n % 2)


def _atol(x0: np.ndarray, rtol: float) -> float:
    scale = np.abs(x0[np.abs(x0) > 0])
    return float(max(rtol * (np.median(scale) if scale.size else 1.0) * 1e-2, 1e-14))


def decide_compilation(method: RK4, compile: bool | None, steps: int, with_check: bool) -> tuple[bool, str, bool]:
    """``(compile, reason, background)`` for the RK4 step of ``method`` (see the module docstring, 4)."""
    if compile is True:
        return True, "compile=True", False
    if compile is False:
        return False, "compile=False", False
    step = method.symbolic_step()
    per_step = min(method._step_seconds(step, method.problem.x0) for _ in range(2))
    vm = per_step * steps * (1.5 if with_check else 1.0)
    if vm <= BACKGROUND_COMPILE_MIN_S:               # loading a library would cost more than it saves
        return False, f"virtual machine: ~{1e3 * vm:.3g} ms", False
    if codegen.compile_disabled() or codegen.compiler_command() is None:
        return False, "virtual machine: compilation unavailable (no compiler, or MBSYM_NO_COMPILE)", False
    if codegen.cached_library(step) is not None:
        return True, "compiled: its library is in the disk cache", False
    cost = codegen.estimate_compile_seconds(step)
    if vm > cost:
        return True, f"compiled: the run would take {vm:.2g} s in the virtual machine, compiling ~{cost:.2g} s", False
    return False, (f"virtual machine: ~{1e3 * vm:.3g} ms, below the ~{cost:.2g} s of compiling; compiling in the "
                   "background for the next runs"), True


# ------------------------------------------------------------------------------------------- runs
def run_auto(plant, x0: np.ndarray, p: np.ndarray, signal, times: np.ndarray, tmax: float, accuracy: float,
             compile: bool | None, monitor=None) -> tuple[np.ndarray, dict]:
    """Select, integrate, check; return the states on ``times`` and the statistics."""
    t0 = time.perf_counter()
    sel = select(plant, x0, p, signal, tmax, accuracy)
    t_select = time.perf_counter() - t0
    if sel.method == "cvodes":
        X, stats = _run_bdf(plant, x0, p, signal, times, tmax, accuracy, sel, compile, monitor)
    else:
        X, stats = _run_rk4(plant, x0, p, signal, times, tmax, accuracy, sel, compile, monitor)
    stats["selection_wall_s"] = t_select
    stats["prepare_wall_s"] = stats.get("prepare_wall_s", 0.0) + t_select
    stats["accuracy"] = accuracy
    stats["selection"] = sel.reason
    stats["predicted_error"] = sel.predicted_error
    return X, stats


#: The step-doubling check compares the runs on at most this many output times (a subsample).
CHECK_SAMPLES = 1000


def _subsample(times: np.ndarray) -> slice:
    """Every k-th output time, at most about CHECK_SAMPLES of them (the check's interpolation is then cheap)."""
    return slice(None, None, max(1, int(math.ceil(times.size / CHECK_SAMPLES))))


def _stage(monitor, name: str):
    """A monitor for a further pass (the accuracy check): same callback, told the stage when it can be."""
    if monitor is None:
        return None
    from .monitor import RunMonitor

    set_stage = getattr(monitor.progress, "set_stage", None)
    if callable(set_stage):
        set_stage(name)
    return RunMonitor(monitor.tmax, monitor.progress)


def _problem(plant, x0, p, signal, times, tmax, *, dt=None, rtol=1e-6, atol=1e-8, compile=False, monitor=None):
    n = None
    if dt is not None:
        n = max(int(round(tmax / dt)), 1)
        dt = tmax / n
    return Problem(plant, x0, p, signal, times, tmax, dt=dt, n_steps=n, rtol=rtol, atol=atol, compile=compile,
                   monitor=monitor)


def _run_rk4(plant, x0, p, signal, times, tmax, accuracy, sel, compile, monitor):
    h = sel.dt
    stats: dict = {}
    integration = prepare = 0.0
    for attempt in range(MAX_REFINEMENTS + 1):
        n = _even_steps(tmax, h)
        h = tmax / n
        check_resources(times.size, 1, 1.5 * n, tmax, fewer_steps="request a looser accuracy")   # outputs: checked
        main = RK4(_problem(plant, x0, p, signal, times, tmax, dt=h, monitor=monitor))
        on, reason, background = decide_compilation(main, compile, n, True)
        if on:
            main = RK4(_problem(plant, x0, p, signal, times, tmax, dt=h, compile=True, monitor=monitor))
        elif background:
            codegen.compile_in_background(main.symbolic_step())
        double_ok = 2 * h < 0.95 * sel.stability_limit
        X, stats = main.solve()
        integration += stats["integration_wall_s"]
        prepare += stats["prepare_wall_s"]
        check_h = 2 * h if double_ok else h / 2
        sub = _subsample(times) if double_ok else slice(None)
        chk = RK4(_problem(plant, x0, p, signal, times[sub], tmax, dt=check_h, compile=on,
                           monitor=_stage(monitor, "accuracy check")))
        try:
            Xc, cstats = chk.solve()
            integration += cstats["integration_wall_s"]
            prepare += cstats["prepare_wall_s"]
            # Richardson: x_2h - x_h ~ (2^4 - 1) e_h; with dt / 2, the finer run is the answer, e ~ (x_h - x_h/2) / 15
            estimate = (epsilon(X[sub], Xc) if double_ok else epsilon(Xc, X)) / 15.0
            if not double_ok:
                X, stats = Xc, cstats
                h = check_h
        except IntegrationError:
            estimate = math.inf
        stats.update(compile_choice=reason, background_compile=background, error_estimate=estimate,
                     check=f"step doubling ({'2 dt' if double_ok else 'dt / 2'})",
                     check_steps=n // 2 if double_ok else 2 * n)
        if estimate <= accuracy or attempt == MAX_REFINEMENTS:
            break
        shrink = (0.7 * accuracy / estimate) ** 0.25 if math.isfinite(estimate) else 0.25
        h *= min(max(shrink, 0.1), 0.9)
        sel.reason += f"; refined to dt = {h:.4g} s after the check estimated ε = {estimate:.2g}"
    stats["integration_wall_s"], stats["prepare_wall_s"] = integration, prepare
    stats["dt"] = h
    return X, stats


def _run_bdf(plant, x0, p, signal, times, tmax, accuracy, sel, compile, monitor):
    from .casadi_methods import Cvodes

    on = bool(compile)
    rtol, atol = sel.rtol, sel.atol
    integration = prepare = 0.0
    coarse = None
    stats: dict = {}
    for attempt in range(MAX_REFINEMENTS + 2):
        fine = Cvodes(_problem(plant, x0, p, signal, times, tmax, rtol=rtol, atol=atol, compile=on, monitor=monitor))
        X, stats = fine.solve()
        integration += stats["integration_wall_s"]
        prepare += stats["prepare_wall_s"]
        if coarse is not None:
            estimate = epsilon(coarse, X)
            stats.update(error_estimate=estimate, check="tolerance / 10")
            if estimate <= accuracy or attempt == MAX_REFINEMENTS + 1:
                break
        coarse = X
        rtol, atol = rtol / 10, atol / 10
    stats["integration_wall_s"], stats["prepare_wall_s"] = integration, prepare
    stats["compile_choice"] = "compile=True" if on else "virtual machine (BDF path)"
    return X, stats
