"""Gauss–Newton for multiple shooting on the measurement grid, with condensing.

Unknowns: the estimated parameters ``θ`` and, per record, the states ``s_k`` at
every sample (the shooting nodes); the free entries of ``s_0`` (initial states
being estimated) are unknowns, the others are fixed. The problem is

    min ½ Σ_k ‖r_k‖²,  r_k = W (h(s_k, u_k, θ) − y_k)      (wrapped for periodic channels)
    s.t. s_{k+1} = Φ(s_k, u_k, u_{k+1}, θ, h_k)             (RK4 over the interval)

Each iteration linearizes residuals and continuity conditions with their exact
derivatives (CasADi AD), ``Δs_{k+1} = A_k Δs_k + B_k Δθ + g_k`` with the gaps
``g_k = Φ(s_k) − s_{k+1}``, and *condenses* the node increments by the forward
recursion ``Δs_k = G_k Δs_0 + P_k Δθ + d_k`` (Bock's condensing, a compiled
accumulation of :class:`~mbsym.identify.shooting.ShootingFunctions`): the
Gauss–Newton step is then a dense linear least-squares problem in the few
unknowns ``(Δs_0,free, Δθ)``, solved with column scaling (bounds on ``θ`` by
bounded-variable least squares). The node increments follow from the recursion,
so every step closes the gaps to first order; nodes initialized from the data
(rather than from a simulation) keep the iterates near the measured trajectory,
which avoids the local minima of single shooting on long oscillating records.

Globalization: a backtracking *filter* line search (Fletcher & Leyffer; the
variant of Wächter & Biegler, Math. Program. 106, 2006, with their default
constants) on the pair (cost ``½‖r‖²``, scaled gap norm ``Σ|g_k|/x_scale``): a trial
point is accepted if it sufficiently reduces the cost or the gaps and is not
dominated by an earlier iterate in the filter, with an Armijo condition on the
cost once the gaps are small. No multipliers are needed. Convergence: the scaled
step in ``θ`` and in the nodes and the scaled gaps below ``tol``.

Jacobian reuse: the Jacobians ``A, B, C, D`` (the expensive part, ~85 % of an
iteration) are re-evaluated only when the iterate has moved more than
``refresh = 1e-3`` (scaled, accumulated) since they were evaluated, or after a
shortened step; otherwise the iteration re-condenses the old Jacobians with the new
residuals and gaps (a simplified Gauss–Newton step, contracting by about the
distance moved). The statistics at the end use Jacobians evaluated within that
distance of the optimum (a relative error ≲ 1e-3 in the standard errors, below
their own sampling uncertainty).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..exceptions import SolverError

__all__ = ["ShootingRecord", "GaussNewtonResult", "gauss_newton", "linearize", "condensed", "stack"]

# Filter line-search constants (Wächter & Biegler 2006, ipopt's defaults)
_GAMMA_H, _GAMMA_F, _ETA, _DELTA, _S_H, _S_F = 1e-5, 1e-5, 1e-4, 1.0, 1.1, 2.3


@dataclass
class ShootingRecord:
    """One record of the shooting problem (numbers only).

    ``U`` (N + 1, n_u), ``H`` (N,), data ``Y`` (N + 1, n_c), weights ``w`` (n_c,),
    periods (n_c,; 0 = not periodic), initial state ``x0`` (n_x,) and the indices
    ``free0`` of its entries that are estimated.
    """

    U: np.ndarray
    H: np.ndarray
    Y: np.ndarray
    w: np.ndarray
    period: np.ndarray
    x0: np.ndarray
    free0: np.ndarray


@dataclass
class Linearization:
    """One record linearized at some nodes: Jacobians ``A`` (N, n_x, n_x), ``B`` (N, n_x, n_θ) of the
    intervals and weighted ``C`` (N + 1, n_c, n_x), ``D`` (N + 1, n_c, n_θ) of the channels."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray


@dataclass
class GaussNewtonResult:
    """Outcome: ``theta``, nodes ``S`` per record, the condensed Jacobian ``J`` and residuals ``r`` at the end."""

    theta: np.ndarray
    S: list
    J: np.ndarray
    r: np.ndarray
    iterations: int
    success: bool
    message: str
    cost: float
    max_gap: float
    history: list = field(default_factory=list)
    wall_s: float = 0.0
    jacobians: int = 0
    unobserved: tuple = ()


def wrap(e: np.ndarray, period: np.ndarray) -> np.ndarray:
    """``e`` with periodic columns wrapped to [-P/2, P/2)."""
    if not np.any(period):
        return e
    P = np.where(period > 0, period, 1.0)
    return np.where(period > 0, e - P * np.round(e / P), e)


def residuals(fun, rec: ShootingRecord, S: np.ndarray, theta: np.ndarray, p: np.ndarray):
    """Weighted residuals (N + 1, n_c) and gaps (N, n_x) at nodes ``S`` (no derivatives)."""
    xn = fun.intervals(S[:-1], rec.U[:-1], rec.U[1:], theta, p, rec.H)
    y = fun.outputs(S, rec.U, theta, p)
    return wrap(y - rec.Y, rec.period) * rec.w, xn - S[1:]


def linearize(fun, rec: ShootingRecord, S: np.ndarray, theta: np.ndarray, p: np.ndarray):
    """Jacobians at nodes ``S`` and the residuals and gaps there: ``(Linearization, r, g)``."""
    xn, A, B = fun.intervals_jac(S[:-1], rec.U[:-1], rec.U[1:], theta, p, rec.H)
    y, C, D = fun.outputs(S, rec.U, theta, p, jac=True)
    w = rec.w[None, :, None]
    return Linearization(A, B, C * w, D * w), wrap(y - rec.Y, rec.period) * rec.w, xn - S[1:]


def condensed(fun, rec: ShootingRecord, lin: Linearization, r: np.ndarray, g: np.ndarray):
    """Sensitivities ``Z`` (N + 1, n_x, n_z), residual Jacobian (M, n_f + n_θ) and the residuals after
    closing the gaps linearly (M,), for the Jacobians ``lin`` and the residuals ``r`` and gaps ``g``."""
    n_f, n_th, n_z = fun.n_f, fun.n_th, fun.n_z
    Z0 = np.zeros((fun.n_x, n_z))
    Z0[rec.free0, np.arange(n_f)] = 1.0
    Z = fun.condense(Z0, lin.A, lin.B, g)
    J = np.einsum("kcx,kxj->kcj", lin.C, Z)
    J[:, :, n_f:n_f + n_th] += lin.D
    rl = r + J[:, :, -1]
    return Z, J[:, :, :-1].reshape(-1, n_z - 1), rl.reshape(-1)


def stack(blocks: list[tuple[np.ndarray, np.ndarray]], recs: list[ShootingRecord],
          n_th: int) -> tuple[np.ndarray, np.ndarray]:
    """Condensed Jacobian of all records, columns ``[free s0 of record 1 | ... | θ]``, and the residuals
    after closing the gaps linearly."""
    n_free = [r.free0.size for r in recs]
    n_col = sum(n_free) + n_th
    out, res, off = [], [], 0
    for (Jr, rl), nf in zip(blocks, n_free):
        full = np.zeros((Jr.shape[0], n_col))
        full[:, off:off + nf] = Jr[:, :nf]
        full[:, n_col - n_th:] = Jr[:, nf:]
        out.append(full)
        res.append(rl)
        off += nf
    return np.vstack(out), np.concatenate(res)


#: Advice appended to the errors of a failed iteration.
ADVICE = ("Check that the model describes the data (an operating turbine needs its aerodynamics and measured pitch and "
          "torque as inputs), that the data start where the initial state is (or estimate it), and that the starting "
          "values are physical; fit fewer channels or parameters, or give bounds.")


def check_finite(what: str, values: np.ndarray, columns: list[str] | None = None) -> None:
    """Raise :class:`SolverError` (with advice) if ``values`` has NaN or infinite entries (before LAPACK sees them)."""
    bad = ~np.isfinite(values)
    if not bad.any():
        return
    where = ""
    if columns is not None and values.ndim == 2 and values.shape[1] == len(columns):
        names = [c for c, b in zip(columns, bad.any(axis=0)) if b]
        where = f" (in the columns of {names})"
    raise SolverError(f"the {what} are not finite{where}: the model's trajectory left the range where it is "
                      f"defined. {ADVICE}")


def unobserved_columns(J: np.ndarray, scale: np.ndarray, n_cols: int, tol: float = 1e-7) -> np.ndarray:
    """Indices among the first ``n_cols`` columns (free initial states) that the residuals hardly see:
    scaled column norm below ``tol`` times the largest. They are left out of every step."""
    norms = np.linalg.norm(J, axis=0) * scale
    top = float(np.max(norms)) if norms.size else 0.0
    return np.flatnonzero(norms[:n_cols] <= tol * top) if top > 0 else np.arange(n_cols)


def _solve_ls(J: np.ndarray, rl: np.ndarray, lo: np.ndarray, hi: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """``min ‖rl + J Δ‖`` with ``lo ≤ Δ ≤ hi``.

    Unknowns are scaled by their typical size ``scale`` (not by the column norms, which would
    inflate a column that the data hardly see): directions whose scaled singular value is below
    1e-10 of the largest are left out (minimum-norm step), so an initial state the channels do
    not observe stays where it is.
    """
    Js = J * scale
    try:
        d = np.linalg.lstsq(Js, -rl, rcond=1e-10)[0] * scale
    except np.linalg.LinAlgError as exc:
        raise SolverError(f"the Gauss-Newton step could not be computed ({exc}). {ADVICE}") from None
    if np.all(d >= lo) and np.all(d <= hi):
        return d
    from scipy.optimize import lsq_linear

    lo_s, hi_s = np.minimum(lo / scale, 0.0), np.maximum(hi / scale, 0.0)
    sol = lsq_linear(Js, -rl, bounds=(lo_s, hi_s), method="bvls", lsq_solver="exact")
    return np.clip(sol.x * scale, lo, hi)


def _acceptable(f: float, h: float, filt: list[tuple[float, float]]) -> bool:
    return all(h < (1 - _GAMMA_H) * hj or f < fj - _GAMMA_F * hj for hj, fj in filt)


def gauss_newton(fun, recs: list[ShootingRecord], p: np.ndarray, theta0: np.ndarray, S0: list,
                 lb: np.ndarray, ub: np.ndarray, theta_scale: np.ndarray, *, tol: float = 1e-8,
                 max_iter: int = 50, refresh: float = 1e-3, verbose: bool = False,
                 progress: Callable[[dict], None] | None = None, max_time: float | None = None,
                 columns: list[str] | None = None) -> GaussNewtonResult:
    """Solve the shooting least-squares problem (module docstring) from nodes ``S0`` and ``theta0``.

    ``progress`` is called after every iteration with its history entry (plus ``elapsed_s``);
    ``max_time`` [s] stops the iteration (unconverged) once exceeded; ``columns`` names the
    unknowns for error messages. Free initial states the residuals do not see (scaled column norm
    below 1e-7 of the largest at the start) are not moved (:attr:`GaussNewtonResult.unobserved`).
    Raises :class:`SolverError` when residuals, gaps or Jacobians become non-finite."""
    t0 = time.perf_counter()
    n_th = theta0.size
    n_free = [r.free0.size for r in recs]
    theta, S = theta0.astype(float).copy(), [s.astype(float).copy() for s in S0]
    x_scale = np.maximum(np.max(np.abs(np.vstack(S)), axis=0), 1e-6)

    def measures(rs, gs) -> tuple[float, float]:
        return (0.5 * sum(float(np.sum(r ** 2)) for r in rs),
                sum(float(np.sum(np.abs(g) / x_scale)) for g in gs))

    def relinearize():
        out = [linearize(fun, rec, s, theta, p) for rec, s in zip(recs, S)]
        return [o[0] for o in out], [o[1] for o in out], [o[2] for o in out]

    lins, rs, gs = relinearize()
    n_jac, moved = 1, 0.0
    cost, h = measures(rs, gs)
    filt = [(max(1e4, 1e4 * h), -np.inf)]
    history, success, message, it = [], False, f"no convergence in {max_iter} iterations", 0
    scale = np.concatenate([*(x_scale[r.free0] for r in recs), theta_scale])
    dead = None
    while True:
        cond = [condensed(fun, rec, ln, r, g) for rec, ln, r, g in zip(recs, lins, rs, gs)]
        J, rl = stack([(c[1], c[2]) for c in cond], recs, n_th)
        check_finite("residuals after closing the gaps", rl)
        check_finite("Jacobians of the residuals", J, columns)
        if dead is None:
            dead = unobserved_columns(J, scale, sum(n_free))
        J[:, dead] = 0.0
        gap = max(float(np.max(np.abs(g) / x_scale)) if g.size else 0.0 for g in gs)
        if history and history[-1]["step"] <= tol and gap <= tol:
            success, message = True, f"converged: scaled step {history[-1]['step']:.2e}, gaps {gap:.2e}"
            break
        if it >= max_iter:
            break
        if max_time is not None and time.perf_counter() - t0 > max_time:
            message = f"stopped at the time limit of {max_time:g} s after {it} iterations (not converged)"
            break
        it += 1
        lo = np.concatenate([np.full(sum(n_free), -np.inf), lb - theta])
        hi = np.concatenate([np.full(sum(n_free), np.inf), ub - theta])
        delta = _solve_ls(J, rl, lo, hi, scale)
        dth = delta[sum(n_free):]
        dS, off = [], 0
        for (Z, _, _), nf in zip(cond, n_free):
            dS.append(Z @ np.concatenate([delta[off:off + nf], dth, [1.0]]))
            off += nf
        r_all = np.concatenate([r.reshape(-1) for r in rs])
        slope = float(r_all @ (rl + J @ delta - r_all))            # d cost / d alpha at alpha = 0
        alpha, accepted, kind, trial = 1.0, False, "", None
        for _ in range(40):
            th_new = np.clip(theta + alpha * dth, lb, ub)
            S_new = [s + alpha * d for s, d in zip(S, dS)]
            trial = [residuals(fun, rec, s, th_new, p) for rec, s in zip(recs, S_new)]
            if all(np.all(np.isfinite(r)) and np.all(np.isfinite(g)) for r, g in trial):
                f_t, h_t = measures([r for r, _ in trial], [g for _, g in trial])
                if _acceptable(f_t, h_t, filt):
                    switching = slope < 0 and alpha * (-slope) ** _S_F > _DELTA * h ** _S_H
                    if switching and f_t <= cost + _ETA * alpha * slope:
                        accepted, kind = True, "f"
                    elif not switching and (h_t <= (1 - _GAMMA_H) * h or f_t <= cost - _GAMMA_F * h):
                        accepted, kind = True, "h"
                    if accepted:
                        break
            alpha *= 0.5
        step = max(float(np.max(np.abs(alpha * dth) / theta_scale)) if n_th else 0.0,
                   max(float(np.max(np.abs(alpha * d) / x_scale)) for d in dS))
        history.append({"iteration": it, "cost": cost, "gap": gap, "alpha": alpha, "step": step, "type": kind,
                        "jacobians": n_jac})
        if progress is not None:
            progress({**history[-1], "elapsed_s": time.perf_counter() - t0})
        if verbose:
            print(f"  GN {it:3d}  cost {cost:.6e}  gap {gap:.2e}  step {step:.2e}  alpha {alpha:g} {kind} "
                  f"(Jacobians evaluated: {n_jac})")
        if not accepted:
            if moved > 0.0:                 # a stale Jacobian: evaluate it here and try again
                lins, rs, gs = relinearize()
                n_jac, moved = n_jac + 1, 0.0
                continue
            message = "line search failed: no acceptable point along the Gauss-Newton step"
            break
        if kind == "h":
            filt.append((h, cost))
        theta, S = th_new, S_new
        moved += step
        if moved > refresh or alpha < 1.0:
            lins, rs, gs = relinearize()
            n_jac, moved = n_jac + 1, 0.0
        else:
            rs, gs = [r for r, _ in trial], [g for _, g in trial]
        cost, h = measures(rs, gs)
    r = np.concatenate([r.reshape(-1) for r in rs])
    gap = max(float(np.max(np.abs(g) / x_scale)) if g.size else 0.0 for g in gs)
    check_finite("residuals at the end", r)
    return GaussNewtonResult(theta, S, J, r, it, success, message, 0.5 * float(r @ r), gap, history,
                             time.perf_counter() - t0, n_jac, tuple(int(i) for i in (dead if dead is not None else ())))
