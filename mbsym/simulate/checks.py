"""Input checks of :func:`mbsym.simulate` and the divergence test shared by every method.

All validation of user-supplied options lives here (scipy's ``_ivp/common.py``
plays the same role), so that messages are uniform: what is wrong, what was
expected, how to fix it.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..exceptions import IntegrationError, SimulationOptionError
from ..protocol import initial_state  # noqa: F401  (re-exported: simulate.checks.initial_state)

__all__ = [
    "SimulationOptionError",
    "SimulationOptionWarning",
    "DIVERGENCE_LIMIT",
    "check_tmax",
    "check_step",
    "check_tolerances",
    "check_accuracy",
    "check_t_out",
    "initial_state",
    "first_bad_column",
    "divergence_message",
    "raise_diverged",
]

#: A state whose magnitude exceeds ``DIVERGENCE_LIMIT * max(1, max|x0|)`` counts as diverged.
#: No physical state in SI units (m, rad, m/s, rad/s) of a multibody model gets there.
DIVERGENCE_LIMIT = 1e10


class SimulationOptionWarning(UserWarning):
    """An option of :func:`mbsym.simulate` was given explicitly but the chosen method does not use it."""


def _positive_number(value, what: str, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise SimulationOptionError(f"{what} must be a positive number {unit}; got {value!r}.")
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise SimulationOptionError(f"{what} must be a positive finite number {unit}; got {value!r}.")
    return value


def check_tmax(tmax) -> float:
    """End time [s] > 0 (simulations start at t = 0)."""
    return _positive_number(tmax, "tmax", "[s] (the simulation runs from 0 to tmax)")


def check_step(dt, tmax: float) -> tuple[float, int]:
    """Fixed step: ``(h, n_steps)`` with ``n_steps * h == tmax``.

    The step is ``dt`` when ``tmax`` is a multiple of it (to 1e-9 relative),
    otherwise it is shortened to ``tmax / ceil(tmax / dt)``; the step actually
    used is reported in the result's statistics.
    """
    dt = _positive_number(dt, "dt", "[s]")
    ratio = tmax / dt
    n = int(round(ratio)) if abs(ratio - round(ratio)) <= 1e-9 * max(ratio, 1.0) else int(np.ceil(ratio))
    n = max(n, 1)
    return tmax / n, n


def check_tolerances(rtol, atol) -> tuple[float, float]:
    """Relative and absolute tolerances of adaptive methods (positive, rtol >= 1e-14)."""
    rtol = _positive_number(rtol, "rtol", "[-]")
    atol = _positive_number(atol, "atol", "[state units]")
    if rtol < 1e-14:
        raise SimulationOptionError(f"rtol = {rtol:g} is below what double precision can deliver; use rtol >= 1e-14.")
    if rtol >= 1.0:
        raise SimulationOptionError(f"rtol = {rtol:g} allows errors as large as the solution itself; a relative "
                                    "tolerance must be below 1 (e.g. 1e-6).")
    return rtol, atol


def check_accuracy(accuracy) -> float:
    """``accuracy`` of the accuracy-driven default: a number in [1e-10, 0.5] [-]."""
    value = _positive_number(accuracy, "accuracy", "[-] (relative error, e.g. 1e-3)")
    if not 1e-10 <= value <= 0.5:
        raise SimulationOptionError(f"accuracy = {value:g} is outside [1e-10, 0.5]: it bounds the mean error relative "
                                    "to each state's range (1e-3 = 0.1 %); below 1e-10 double precision and the "
                                    "step count run out.")
    return value


def check_t_out(t_out, tmax: float) -> np.ndarray:
    """Output times [s]: 1-D, finite, strictly increasing, within ``[0, tmax]``."""
    try:
        t = np.asarray(t_out, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SimulationOptionError(f"t_out must be a 1-D array of times [s]; got {t_out!r}.") from exc
    if t.ndim != 1 or t.size == 0:
        raise SimulationOptionError(f"t_out must be a non-empty 1-D array of times [s]; got shape {t.shape}.")
    if not np.all(np.isfinite(t)):
        raise SimulationOptionError("all output times t_out must be finite.")
    if t.size > 1 and np.any(np.diff(t) <= 0.0):
        i = int(np.flatnonzero(np.diff(t) <= 0.0)[0])
        raise SimulationOptionError(f"t_out must be strictly increasing; t_out[{i}] = {t[i]:g} s is followed by "
                                    f"t_out[{i + 1}] = {t[i + 1]:g} s.")
    tol = 1e-12 * tmax
    if t[0] < -tol or t[-1] > tmax + tol:
        raise SimulationOptionError(f"t_out spans [{t[0]:g}, {t[-1]:g}] s; it must lie within [0, tmax] = "
                                    f"[0, {tmax:g}] s.")
    return np.clip(t, 0.0, tmax)


def first_bad_column(X: np.ndarray, x0: np.ndarray) -> int | None:
    """Index of the first column of X (n_x, N) that is not finite or exceeds the divergence limit."""
    limit = DIVERGENCE_LIMIT * max(1.0, float(np.max(np.abs(x0), initial=0.0)))
    if X.size == 0:
        return None
    # a column's max and min carry a NaN (compares False) and an infinity: two reductions, no temporaries (~30x
    # cheaper than isfinite & abs on the 261 x 105600 states of a blade-element run)
    with np.errstate(invalid="ignore"):
        bad = ~((X.max(axis=0) <= limit) & (X.min(axis=0) >= -limit))
    idx = np.flatnonzero(bad)
    return int(idx[0]) if idx.size else None


def divergence_message(method: str, t: float, step: float | None, x: np.ndarray, states: Sequence[str],
                       x0: np.ndarray, *, where: str = "", hint: str = "") -> str:
    """Message naming the method, time, step size and the first non-finite (or diverged) state."""
    limit = DIVERGENCE_LIMIT * max(1.0, float(np.max(np.abs(x0), initial=0.0)))
    nonfinite = np.flatnonzero(~np.isfinite(x))
    if nonfinite.size:
        i = int(nonfinite[0])
        what = f"first non-finite state {states[i]!r} = {x[i]}"
    else:
        with np.errstate(invalid="ignore"):
            over = np.flatnonzero(np.abs(x) > limit)
        i = int(over[0]) if over.size else int(np.argmax(np.abs(x)))
        what = f"state {states[i]!r} = {x[i]:.3g} exceeds the divergence limit {limit:.3g}"
    step_txt = "unknown step size" if step is None else f"step size dt = {step:.6g} s"
    where = f"{where}, " if where else ""
    return f"method {method!r} diverged at t = {t:.6g} s ({where}{step_txt}): {what}." + (f" {hint}" if hint else "")


def raise_diverged(method: str, t: float, step: float | None, x: np.ndarray, states: Sequence[str],
                   x0: np.ndarray, *, where: str = "", hint: str = "") -> None:
    """Raise :class:`IntegrationError` with :func:`divergence_message`."""
    raise IntegrationError(divergence_message(method, t, step, x, states, x0, where=where, hint=hint))
