"""Input checks shared by the optimal-control classes: names, weights, bounds, callables."""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import casadi as ca
import numpy as np

from ..exceptions import ControlDefinitionError, DimensionError

__all__ = ["positive_int", "finite_number", "weight_root", "check_names", "symbolic_call", "bound_pair",
           "vector", "named_values"]


def positive_int(value: Any, what: str, minimum: int = 1) -> int:
    """``value`` as an int ≥ ``minimum`` or a ControlDefinitionError."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ControlDefinitionError(f"{what} must be an integer ≥ {minimum}; got {value!r}.")
    return int(value)


def finite_number(value: Any, what: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    """``value`` as a finite float (optionally > 0 or ≥ 0) or a ControlDefinitionError."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ControlDefinitionError(f"{what} must be a number; got {value!r}.") from None
    if not np.isfinite(v) or (positive and v <= 0) or (nonnegative and v < 0):
        need = "a positive" if positive else "a non-negative" if nonnegative else "a finite"
        raise ControlDefinitionError(f"{what} must be {need} finite number; got {value!r}.")
    return v


def weight_root(weight: Any, n: int, what: str) -> np.ndarray:
    """A matrix ``L`` with ``LᵀL = W`` for a weight given as a scalar, n numbers (diagonal) or an n×n matrix.

    Raises
    ------
    ControlDefinitionError
        Negative, non-finite, non-symmetric or indefinite weights, or the wrong size.
    """
    try:
        W = np.asarray(weight, dtype=float)
    except (TypeError, ValueError):
        raise ControlDefinitionError(f"{what} must be numbers; got {weight!r}.") from None
    if not np.all(np.isfinite(W)):
        raise ControlDefinitionError(f"{what} must be finite; got {weight!r}.")
    if W.ndim == 0 or (W.ndim == 1 and W.size in (1, n)):
        d = np.broadcast_to(W.reshape(-1), (n,)) if W.size == 1 else W.reshape(-1)
        if np.any(d < 0):
            raise ControlDefinitionError(f"{what} must be ≥ 0 (a weight on a squared deviation); got {d.tolist()}.")
        return np.diag(np.sqrt(d))
    if W.shape != (n, n):
        raise ControlDefinitionError(f"{what} must be a number, {n} numbers or an {n}×{n} matrix; "
                                     f"got shape {W.shape}.")
    if not np.allclose(W, W.T, rtol=1e-10, atol=1e-12 * max(1.0, np.abs(W).max())):
        raise ControlDefinitionError(f"{what} must be symmetric.")
    lam, V = np.linalg.eigh(0.5 * (W + W.T))
    if lam.min() < -1e-10 * max(1.0, abs(lam).max()):
        raise ControlDefinitionError(f"{what} must be positive semi-definite; its smallest eigenvalue is "
                                     f"{lam.min():.3g}.")
    return np.diag(np.sqrt(np.clip(lam, 0.0, None))) @ V.T


def check_names(names: Any, known: Sequence[str], what: str) -> tuple[str, ...]:
    """Names (a string of space-separated names or a sequence) all in ``known``, without repeats."""
    if isinstance(names, str):
        names = names.split()
    try:
        out = tuple(str(n) for n in names)
    except TypeError:
        raise ControlDefinitionError(f"{what} must be a sequence of names; got {names!r}.") from None
    unknown = [n for n in out if n not in known]
    if unknown:
        raise ControlDefinitionError(f"{what}: unknown names {unknown}; expected names from {list(known)}.")
    if len(set(out)) != len(out):
        raise ControlDefinitionError(f"{what}: names repeat in {list(out)}.")
    return out


def symbolic_call(fn: Any, args: Sequence, what: str, n_out: int | None = None):
    """Call a casadi.Function or Python callable on symbols; the result as a column; checked size."""
    if isinstance(fn, ca.Function):
        if fn.n_in() != len(args):
            raise ControlDefinitionError(f"{what} must take {len(args)} arguments; the Function takes {fn.n_in()}.")
        for i, a in enumerate(args):
            if fn.numel_in(i) != a.numel():
                raise ControlDefinitionError(f"{what}: argument {i} ({fn.name_in(i)}) has {fn.numel_in(i)} entries; "
                                             f"expected {a.numel()}.")
        out = fn(*args)
        out = out[0] if isinstance(out, (list, tuple)) else out
    elif callable(fn):
        try:
            out = fn(*args)
        except Exception as exc:       # a user callable fails on symbols: say where
            raise ControlDefinitionError(f"{what} failed on CasADi symbols: {exc}") from exc
    else:
        raise TypeError(f"{what} must be a casadi.Function or a callable; got {type(fn).__name__}.")
    try:
        out = ca.vec(ca.vertcat(out))
    except Exception as exc:
        raise ControlDefinitionError(f"{what} must return a CasADi expression; got {type(out).__name__}.") from exc
    if n_out is not None and out.numel() != n_out:
        raise ControlDefinitionError(f"{what} must return {n_out} value(s); it returns {out.numel()}.")
    return out


def bound_pair(lower: Any, upper: Any, n: int, what: str) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds (None: unbounded) broadcast to ``n`` entries, lower ≤ upper, no NaN."""
    out = []
    for value, default in ((lower, -np.inf), (upper, np.inf)):
        if value is None:
            out.append(np.full(n, default))
            continue
        try:
            arr = np.asarray(value, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise ControlDefinitionError(f"{what} bounds must be numbers; got {value!r}.") from None
        if arr.size not in (1, n):
            raise ControlDefinitionError(f"{what} bounds have {arr.size} entries; expected 1 or {n}.")
        if np.any(np.isnan(arr)):
            raise ControlDefinitionError(f"{what} bounds must not be NaN.")
        out.append(np.broadcast_to(arr, (n,)).astype(float))
    lo, hi = out
    if np.any(lo > hi):
        raise ControlDefinitionError(f"{what}: lower bound {lo.tolist()} exceeds upper bound {hi.tolist()}.")
    return lo, hi


def vector(value: Any, n: int, what: str, names: Sequence[str] = ()) -> np.ndarray:
    """``value`` as a finite float array of ``n`` entries or a DimensionError naming the expected order."""
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise DimensionError(f"{what} must be {n} numbers; got {value!r}.") from None
    if arr.size != n:
        order = f" in order {list(names)}" if names else ""
        raise DimensionError(f"{what} has {arr.size} entries; expected {n}{order}.")
    if not np.all(np.isfinite(arr)):
        raise DimensionError(f"{what} must be finite; got {arr.tolist()}.")
    return arr


def named_values(values: Mapping[str, Any] | None, known: Sequence[str], what: str) -> dict[str, Any]:
    """A dict whose keys are all in ``known`` (None: empty)."""
    if values is None:
        return {}
    if not isinstance(values, Mapping):
        raise TypeError(f"{what} must be a dict by name; got {type(values).__name__}.")
    unknown = sorted(set(values) - set(known))
    if unknown:
        raise ControlDefinitionError(f"{what}: unknown names {unknown}; expected names from {list(known)}.")
    return dict(values)

