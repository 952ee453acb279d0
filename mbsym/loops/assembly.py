"""Assembling a closed loop: independent coordinates, the assembled configuration, rank checks.

Given the constraint rows ``g(q, p)`` of a tree (:func:`mbsym.constraints.constraint_rows`), the
user's independent coordinates and a guess, :func:`assemble` finds the configuration on the
branch nearest the guess (Gauss–Newton on the dependent coordinates, the independent ones held)
and checks it:

- *inconsistent*: no configuration satisfies every row near the guess → the row with the largest
  residual is named;
- *redundant*: a row of ``∂g/∂q`` is a combination of the others (the loop is over-constrained,
  e.g. a planar loop closed along three axes) → the row and its partners are named;
- *badly chosen independent coordinates*: ``∂g/∂q_dep`` is singular although ``∂g/∂q`` is not
  → a set of dependent coordinates that works is suggested.

Everything raises :class:`~mbsym.exceptions.ConstraintError`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from ..exceptions import ConstraintError
from ..symbols import check_finite_number

__all__ = ["LoopChoice", "guess_vector", "choose", "assemble", "check_redundant", "ASSEMBLY_TOL"]

#: Largest constraint residual accepted at the assembled configuration [m or the units of g].
ASSEMBLY_TOL = 1e-10
#: Relative singular-value threshold below which a constraint row counts as dependent.
RANK_TOL = 1e-9


@dataclass(frozen=True)
class LoopChoice:
    """Indices of the independent and dependent coordinates, and the starting configuration."""

    independent: tuple[int, ...]
    dependent: tuple[int, ...]
    q_guess: np.ndarray


def choose(coordinates: Sequence[str], n_rows: int, row_names: Sequence[str], independent,
           guess: Mapping[str, float] | None) -> LoopChoice:
    """Check ``independent`` and ``guess`` against the coordinates and the number of constraint rows.

    Raises
    ------
    ConstraintError
        If ``independent`` is missing, not a list of distinct coordinate names, or does not leave
        exactly one dependent coordinate per constraint row; if ``guess`` is not a dict of finite
        numbers by coordinate name.
    """
    coords = list(coordinates)
    n_dof = len(coords) - n_rows
    if n_rows == 0:
        raise ConstraintError("independent= and guess= are for systems with closed loops; this system has no "
                              "closure or constraint (use sys.add_closure(...) or call sys.equations()).")
    if independent is None:
        raise ConstraintError(
            f"this system has {n_rows} constraint rows {list(row_names)} on {len(coords)} coordinates {coords}: "
            f"name its {n_dof} independent coordinates, e.g. sys.equations(independent={coords[:max(n_dof, 0)]}, "
            "guess={...}).")
    if isinstance(independent, str) or not all(isinstance(n, str) for n in independent):
        raise ConstraintError(f"independent= must be a list of coordinate names, e.g. ['q1']; got {independent!r}.")
    independent = list(independent)
    unknown = [n for n in independent if n not in coords]
    if unknown or len(set(independent)) != len(independent):
        raise ConstraintError(f"independent= names {unknown or independent} that are not distinct coordinates of "
                              f"this system; the coordinates are {coords}.")
    if n_dof < 1:
        raise ConstraintError(f"{n_rows} constraint rows {list(row_names)} on {len(coords)} coordinates leave no "
                              "degree of freedom; remove redundant closure directions (a planar loop closes along "
                              "two axes) or add coordinates.")
    if len(independent) != n_dof:
        raise ConstraintError(
            f"independent= lists {len(independent)} coordinates {independent}, but {len(coords)} coordinates and "
            f"{n_rows} constraint rows {list(row_names)} leave {n_dof} degrees of freedom; name exactly {n_dof}.")
    q0 = guess_vector(coords, guess)
    ind = tuple(coords.index(n) for n in independent)
    dep = tuple(i for i in range(len(coords)) if i not in ind)
    return LoopChoice(ind, dep, q0)


def guess_vector(coordinates: Sequence[str], guess: Mapping[str, float] | None) -> np.ndarray:
    """The guessed configuration (zeros where ``guess`` is silent); ConstraintError for bad guesses."""
    coords = list(coordinates)
    guess = {} if guess is None else guess
    if not isinstance(guess, Mapping):
        raise ConstraintError(f"guess= must be a dict of coordinate values by name, e.g. {{'q2': 0.9}}; "
                              f"got {type(guess).__name__}.")
    unknown = sorted(set(guess) - set(coords))
    if unknown:
        raise ConstraintError(f"guess= names unknown coordinates {unknown}; the coordinates are {coords}.")
    try:
        q0 = np.array([check_finite_number(guess.get(n, 0.0), f"guess[{n!r}]") for n in coords])
    except ValueError as exc:
        raise ConstraintError(f"{exc} Give every guess as a finite number.") from exc
    return q0


def assemble(g_fn: ca.Function, choice: LoopChoice, p: np.ndarray, coordinates: Sequence[str],
             row_names: Sequence[str], *, iterations: int = 60) -> np.ndarray:
    """The configuration satisfying ``g(q, p) = 0`` nearest the guess (independent coordinates held).

    Parameters
    ----------
    g_fn : casadi.Function
        ``(q, p) -> (g, G)``: constraint rows and their Jacobian ``∂g/∂q``.
    choice : LoopChoice
    p : ndarray
        Parameter values.

    Raises
    ------
    ConstraintError
        Inconsistent or redundant constraints, or dependent coordinates that the constraints do
        not determine at the assembled configuration (module docstring).
    """
    q = choice.q_guess.copy()
    dep = list(choice.dependent)
    for _ in range(iterations):
        gv, G = (np.array(v, dtype=float) for v in g_fn(q, p))
        gv = gv.reshape(-1)
        if np.max(np.abs(gv)) < 1e-13:
            break
        step = np.linalg.lstsq(G[:, dep], gv, rcond=None)[0]
        q[dep] -= _damped(step)
    gv, G = (np.array(v, dtype=float) for v in g_fn(q, p))
    gv = gv.reshape(-1)
    check_redundant(G, row_names)
    if np.max(np.abs(gv)) > ASSEMBLY_TOL:
        k = int(np.argmax(np.abs(gv)))
        raise ConstraintError(
            f"the constraints cannot be satisfied near the guess: row {row_names[k]!r} keeps a residual of "
            f"{gv[k]:.3g} (largest of {dict(zip(row_names, np.round(gv, 6)))}), so the closures are inconsistent "
            "(e.g. links too short to close the loop) or the guess is too far from an assembled configuration. "
            "Check the geometry, or give a guess closer to an assembly.")
    _check_dependent(G, dep, coordinates, row_names)
    return q


def _damped(step: np.ndarray, limit: float = 0.5) -> np.ndarray:
    """A Gauss–Newton step shortened to at most ``limit`` (rad or m) per entry (keeps the guessed branch)."""
    big = np.max(np.abs(step)) if step.size else 0.0
    return step if big <= limit else step * (limit / big)


def check_redundant(G: np.ndarray, row_names: Sequence[str], where: str = "at the assembled configuration") -> None:
    """Name the first constraint row that is a combination of the previous ones."""
    scale = max(np.max(np.abs(G)), 1.0)
    for k in range(1, G.shape[0] + 1):
        s = np.linalg.svd(G[:k], compute_uv=False)
        if s[-1] < RANK_TOL * scale:
            coef = np.linalg.lstsq(G[:k - 1].T, G[k - 1], rcond=None)[0] if k > 1 else np.zeros(0)
            partners = [row_names[i] for i in np.flatnonzero(np.abs(coef) > 1e-9)]
            with_ = f"a combination of {partners}" if partners else "identically zero"
            raise ConstraintError(
                f"constraint row {row_names[k - 1]!r} is redundant {where}: its Jacobian "
                f"row is {with_}. Remove it (e.g. close a planar loop along its two in-plane axes only, "
                "directions='xz'), or assemble at a non-singular configuration.")


def _check_dependent(G: np.ndarray, dep: list[int], coordinates: Sequence[str], row_names: Sequence[str]) -> None:
    """``∂g/∂q_dep`` must be invertible: else suggest dependent coordinates that work."""
    Gd = G[:, dep]
    s = np.linalg.svd(Gd, compute_uv=False)
    if s[-1] >= RANK_TOL * max(np.max(np.abs(G)), 1.0):
        return
    _, _, piv = _pivoted_qr(G)
    good = sorted(piv[: G.shape[0]])
    raise ConstraintError(
        f"the constraints {list(row_names)} do not determine the dependent coordinates "
        f"{[coordinates[i] for i in dep]} at the assembled configuration (their Jacobian is singular: the "
        f"independent coordinates are locked or the loop is at a singular position). Choose other independent "
        f"coordinates, e.g. dependent {[coordinates[i] for i in good]} (independent "
        f"{[c for i, c in enumerate(coordinates) if i not in good]}), or another guess.")


def _pivoted_qr(G: np.ndarray):
    """Columns of G in greedy order of independence (Gram–Schmidt with column pivoting)."""
    A = G.astype(float).copy()
    piv = list(range(A.shape[1]))
    for k in range(min(A.shape)):
        j = k + int(np.argmax(np.linalg.norm(A[k:, k:], axis=0)))
        A[:, [k, j]] = A[:, [j, k]]
        piv[k], piv[j] = piv[j], piv[k]
        v = A[k:, k].copy()
        nv = np.linalg.norm(v)
        if nv == 0:
            break
        v[0] += np.copysign(nv, v[0])
        v /= np.linalg.norm(v)
        A[k:, :] -= 2.0 * np.outer(v, v @ A[k:, :])
    return A, None, piv



def turn_series(g_fn: ca.Function, q_ref: np.ndarray, j: int, dep: Sequence[int], p: np.ndarray, *,
                samples: int = 64, tol: float = 1e-4, max_harmonics: int = 12) -> dict | None:
    """A Fourier series of the dependent coordinates over a full turn of independent coordinate ``j``.

    For a loop with one independent coordinate that turns fully (a crank): the dependent coordinates
    are assembled at ``samples`` angles around the turn by numeric continuation from the assembly;
    each is ``w δ + periodic(δ)`` with ``δ = q_j - q_j*`` and ``w`` its whole number of turns per turn
    of ``q_j`` (a relative joint angle that winds). The series keeps the fewest harmonics that
    predict the odd samples from the even ones to ``tol``. None when the coordinate cannot turn
    (the continuation fails: a rocker) or no series up to ``max_harmonics`` is that good.

    Returns
    -------
    dict or None
        ``winding`` (m,), ``a`` and ``b`` (N + 1, m): the series' coefficients.
    """
    dep = list(dep)
    h = 2.0 * np.pi / samples
    g_fn = _Buffered(g_fn, q_ref.size, p)
    q = q_ref.copy()
    Z = [q[dep].copy()]
    for _ in range(samples):
        _, G = g_fn(q, p)
        try:                                        # tangent predictor, then Newton
            q[dep] -= np.linalg.solve(G[:, dep], G[:, j] * h)
        except np.linalg.LinAlgError:
            return None
        q[j] += h
        if not _newton_numeric(g_fn, q, dep, p):
            return None
        Z.append(q[dep].copy())
    Z = np.array(Z)
    turns = (Z[-1] - Z[0]) / (2 * np.pi)
    winding = np.round(turns)
    if np.max(np.abs(turns - winding)) > 1e-8:
        return None                                 # not back on the same configuration after a turn
    delta = h * np.arange(samples)
    Y = Z[:-1] - np.outer(delta, winding)
    for n in range(1, max_harmonics + 1):
        a, b = _fit(delta[::2], Y[::2], n)
        if np.max(np.abs(_series(a, b, delta[1::2]) - Y[1::2])) < tol:
            return {"winding": winding, "a": a, "b": b}
    return None


class _Buffered:
    """``(q, p) -> (g, G)`` through ``Function.buffer()``: numpy in and out without conversions (~100x faster
    than a DM call for these small Functions)."""

    def __init__(self, f: ca.Function, n: int, p: np.ndarray) -> None:
        self.q, self.p = np.zeros(n), np.ascontiguousarray(p, dtype=float)
        m = f.size1_out(0)
        self.g, self.G = np.zeros(m), np.zeros(m * n)
        self.shape = (n, m)
        self.buf, self.trigger = f.buffer()
        self.buf.set_arg(0, memoryview(self.q))
        self.buf.set_arg(1, memoryview(self.p))
        self.buf.set_res(0, memoryview(self.g))
        self.buf.set_res(1, memoryview(self.G))

    def __call__(self, q: np.ndarray, p=None):
        self.q[:] = q
        self.trigger()
        return self.g.copy(), self.G.reshape(self.shape).T.copy()        # CasADi's column-major (m, n)


def _newton_numeric(g_fn: ca.Function, q: np.ndarray, dep: list[int], p: np.ndarray, iterations: int = 12) -> bool:
    """Newton on the dependent coordinates in place; False when it does not converge (no assembly there)."""
    for _ in range(iterations):
        gv, G = (np.array(v, dtype=float) for v in g_fn(q, p))
        gv = gv.reshape(-1)
        if np.max(np.abs(gv)) < 1e-14:
            return True
        try:
            step = np.linalg.solve(G[:, dep], gv)
        except np.linalg.LinAlgError:
            return False
        if not np.all(np.isfinite(step)) or np.max(np.abs(step)) > 0.5:
            return False                            # a jump, not a correction: near a limit of the assembly
        q[dep] -= step
    return bool(np.max(np.abs(gv)) < 1e-12)


def _fit(delta: np.ndarray, Y: np.ndarray, n: int):
    """Least-squares Fourier coefficients (n harmonics) of the columns of Y at angles delta."""
    cols = [np.ones_like(delta)] + [f(k * delta) for k in range(1, n + 1) for f in (np.cos, np.sin)]
    coef = np.linalg.lstsq(np.column_stack(cols), Y, rcond=None)[0]
    a = np.vstack([coef[0], coef[1::2]])
    b = np.vstack([np.zeros_like(coef[0]), coef[2::2]])
    return a, b


def _series(a: np.ndarray, b: np.ndarray, delta: np.ndarray) -> np.ndarray:
    k = np.arange(a.shape[0])
    return np.cos(np.outer(delta, k)) @ a + np.sin(np.outer(delta, k)) @ b
