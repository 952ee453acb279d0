"""Input signals u(t) of a simulation: constants, tables on a time grid, callables.

:func:`input_signal` turns the ``inputs=`` argument of :func:`mbsym.simulate`
into an :class:`InputSignal`, which every method samples at the times it needs
(the stage times of a fixed-step method, the integration grid of CVODES, each
right-hand-side call of scipy's Radau).

Accepted forms (``names`` are the model's input names, ``eom.inputs``):

- ``None``: every input is zero;
- an array of ``n_u`` numbers: constant inputs in order ``names``;
- a callable ``f(t) -> n_u numbers`` [t in s] (a bare function of time for all inputs, in
  order ``names``; called once per time);
- a dict by input name (missing inputs are zero) whose values are

  - a number: constant;
  - a pair ``(grid, values)`` (a tuple): a table, interpolated linearly;
  - an array of values on the shared grid given under the key ``"t"``
    (``{"t": grid, "F": values}``; not available if an input is named ``t``);
  - a callable ``f(t) -> float`` [t in s]. It is first called with an array
    of times (a single number back counts for every time, as from
    ``lambda t: 2.0``); if that raises or returns another shape, once per time.

Tables must cover ``[0, tmax]`` (values are never extrapolated). All values must
be finite.
"""

from __future__ import annotations

from numbers import Real
from typing import Callable, Mapping, Sequence

import numpy as np

from ..exceptions import ArgumentTypeError, DimensionError

__all__ = ["InputSignal", "input_signal"]

_NUMBER = (Real, np.integer, np.floating)


class _Constant:
    def __init__(self, value: float) -> None:
        self.value = value

    def sample(self, t: np.ndarray) -> np.ndarray:
        return np.full(t.shape, self.value)

    def at(self, t: float) -> float:
        return self.value


class _Table:
    def __init__(self, grid: np.ndarray, values: np.ndarray) -> None:
        self.grid, self.values = grid, values

    def sample(self, t: np.ndarray) -> np.ndarray:
        return np.interp(t, self.grid, self.values)

    def at(self, t: float) -> float:
        return float(np.interp(t, self.grid, self.values))


class _Function:
    def __init__(self, f: Callable, name: str) -> None:
        self.f, self.name = f, name

    def sample(self, t: np.ndarray) -> np.ndarray:
        try:
            with np.errstate(all="ignore"):
                v = np.asarray(self.f(t), dtype=float)
        except Exception:   # noqa: BLE001 - any failure on an array means "not vectorized": call per time
            v = None
        if v is not None and v.shape == () and t.shape != ():
            v = np.full(t.shape, float(v))      # f ignores t (e.g. a constant speed): broadcast
        if v is None or v.shape != t.shape:
            v = np.array([self.at(ti) for ti in t.tolist()], dtype=float).reshape(t.shape)
        return self._finite(v, t)

    def at(self, t: float) -> float:
        try:
            out = self.f(t)
        except Exception as exc:
            exc.add_note(f"(while evaluating input {self.name!r} at t = {t:g} s)")
            raise
        v = _numbers(out, f"input {self.name!r}: f(t)", t)
        if v.size != 1:
            raise DimensionError(f"input {self.name!r}: f(t) must return one number; got shape {v.shape} "
                                 f"at t = {t:g} s.")
        return float(self._finite(v.reshape(()), np.asarray(t)))

    def _finite(self, v: np.ndarray, t: np.ndarray) -> np.ndarray:
        if not np.all(np.isfinite(v)):
            i = int(np.flatnonzero(~np.isfinite(np.atleast_1d(v)))[0])
            raise DimensionError(f"input {self.name!r} is not finite at t = {np.atleast_1d(t)[i]:g} s "
                                 f"(value {np.atleast_1d(v)[i]}); inputs must be finite.")
        return v


def _numbers(out, what: str, t: float) -> np.ndarray:
    """``out`` as a float array, or ArgumentTypeError naming what returned it."""
    if isinstance(out, (str, bytes)):
        raise ArgumentTypeError(f"{what} returned {out!r} (a string) at t = {t:g} s; it must return numbers.")
    try:
        return np.asarray(out, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{what} returned {out!r} ({type(out).__name__}) at t = {t:g} s; it must return "
                                "numbers.") from None


class _Component:
    """Input ``j`` of a bare callable ``f(t) -> n_u values`` (one call per time, shared by the inputs)."""

    def __init__(self, vector: "_VectorFunction", j: int) -> None:
        self.vector, self.j = vector, j

    def sample(self, t: np.ndarray) -> np.ndarray:
        return np.array([self.vector.at(ti)[self.j] for ti in np.asarray(t, dtype=float).reshape(-1)]).reshape(t.shape)

    def at(self, t: float) -> float:
        return float(self.vector.at(t)[self.j])


class _VectorFunction:
    def __init__(self, f: Callable, names: tuple[str, ...]) -> None:
        self.f, self.names = f, names
        self._t: float | None = None
        self._v = np.zeros(len(names))

    def at(self, t: float) -> np.ndarray:
        t = float(t)
        if t != self._t:
            try:
                out = self.f(t)
            except Exception as exc:
                exc.add_note(f"(while evaluating inputs(t) at t = {t:g} s)")
                raise
            v = _numbers(out, "inputs(t)", t).reshape(-1)
            if v.size != len(self.names):
                raise DimensionError(f"inputs(t) returned {v.size} values at t = {t:g} s; expected {len(self.names)} "
                                     f"in order {list(self.names)}.")
            if not np.all(np.isfinite(v)):
                raise DimensionError(f"inputs(t) is not finite at t = {t:g} s ({v.tolist()}); inputs must be finite.")
            self._t, self._v = t, v
        return self._v


class InputSignal:
    """Vector input ``u(t)`` (n_u) of a simulation.

    Attributes
    ----------
    names : tuple of str
        Input names, in the order of ``u``.
    knots : ndarray
        Times [s] in ``(0, tmax)`` where a table input may have a kink (its
        grid points); adaptive methods stop there.
    """

    def __init__(self, names: Sequence[str], channels: Sequence, knots: np.ndarray) -> None:
        self.names = tuple(names)
        self._channels = tuple(channels)
        self.knots = knots
        self._groups = _table_groups(self._channels)
        grouped = {j for _, cols, _ in self._groups for j in cols}
        self._single = tuple((j, ch) for j, ch in enumerate(self._channels) if j not in grouped)

    @property
    def n_u(self) -> int:
        return len(self.names)

    @property
    def constant(self) -> bool:
        """Whether every input is constant in time."""
        return all(isinstance(ch, _Constant) for ch in self._channels)

    @property
    def callables(self) -> tuple[int, ...]:
        """Indices of the inputs given as callables ``f(t)`` (known only through samples)."""
        return tuple(j for j, ch in enumerate(self._channels) if isinstance(ch, (_Function, _Component)))

    def __call__(self, t) -> np.ndarray:
        """Inputs at the times ``t`` [s] (1-D), shape ``(len(t), n_u)``."""
        t = np.asarray(t, dtype=float).reshape(-1)
        out = np.empty((t.size, self.n_u))
        for j, ch in self._single:
            out[:, j] = ch.sample(t)
        for grid, cols, values in self._groups:
            out[:, cols] = _interp_columns(grid, values, t)
        return out

    def at(self, t: float) -> np.ndarray:
        """Inputs at one time ``t`` [s], shape ``(n_u,)`` (fast path for adaptive methods)."""
        if not self._groups:
            return np.array([ch.at(t) for ch in self._channels], dtype=float)
        return self(np.array([t]))[0]


#: Tables sharing one time grid are interpolated together from this many on (e.g. a floating platform's sea).
_GROUP_MIN = 4


def _table_groups(channels) -> tuple:
    """``(grid, columns, values (len(grid), len(columns)))`` of the tables that share a grid array, when
    :data:`_GROUP_MIN` or more do."""
    by_grid: dict[int, list[int]] = {}
    for j, ch in enumerate(channels):
        if isinstance(ch, _Table):
            by_grid.setdefault(id(ch.grid), []).append(j)
    return tuple((channels[cols[0]].grid, np.array(cols), np.column_stack([channels[j].values for j in cols]))
                 for cols in by_grid.values() if len(cols) >= _GROUP_MIN)


def _interp_columns(grid: np.ndarray, values: np.ndarray, t: np.ndarray) -> np.ndarray:
    """``np.interp`` of every column of ``values`` at ``t`` (inside the grid), with one search."""
    t = np.clip(t, grid[0], grid[-1])                       # np.interp holds the end values
    i = np.clip(np.searchsorted(grid, t, side="right") - 1, 0, grid.size - 2)
    slope = (values[i + 1] - values[i]) / (grid[i + 1] - grid[i])[:, None]
    return slope * (t - grid[i])[:, None] + values[i]


def input_signal(inputs, names: Sequence[str], tmax: float) -> InputSignal:
    """Build the :class:`InputSignal` of the ``inputs=`` argument (see the module docstring).

    Raises
    ------
    DimensionError
        Unknown input names, wrong sizes, non-finite values, a table that does
        not cover ``[0, tmax]`` or is not strictly increasing.
    TypeError
        A value of an unsupported type.
    """
    names = tuple(names)
    zeros = [_Constant(0.0) for _ in names]
    if inputs is None:
        return InputSignal(names, zeros, np.zeros(0))
    if isinstance(inputs, Mapping):
        return _from_dict(inputs, names, tmax)
    if callable(inputs):
        vector = _VectorFunction(inputs, names)
        return InputSignal(names, [_Component(vector, j) for j in range(len(names))], np.zeros(0))
    if isinstance(inputs, (str, bytes)):
        raise ArgumentTypeError(f"inputs must be None, an array of {len(names)} numbers or a dict by input name "
                        f"{list(names)}; got {type(inputs).__name__}. Give callables per input: {{'name': f}}.")
    try:
        u = np.asarray(inputs, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise ArgumentTypeError(f"inputs must be None, an array of {len(names)} numbers or a dict by input name; "
                        f"got {inputs!r}.") from exc
    if u.size != len(names):
        raise DimensionError(f"inputs has {u.size} entries; expected {len(names)} in order {list(names)}.")
    if not np.all(np.isfinite(u)):
        raise DimensionError(f"inputs must be finite; got {u.tolist()} for {list(names)}.")
    return InputSignal(names, [_Constant(float(v)) for v in u], np.zeros(0))


def _from_dict(inputs: Mapping, names: tuple[str, ...], tmax: float) -> InputSignal:
    shared = None
    if "t" in inputs and "t" not in names:
        shared = _grid(inputs["t"], tmax, "inputs['t']")
    unknown = sorted(str(k) for k in inputs if k not in names and not (k == "t" and shared is not None))
    if unknown:
        raise DimensionError(f"inputs names unknown inputs {unknown}; this model's inputs are {list(names)}"
                             + (" (it has none)." if not names else "."))
    channels, grids = [], []
    for name in names:
        if name not in inputs:
            channels.append(_Constant(0.0))
            continue
        ch = _channel(inputs[name], name, shared, tmax)
        channels.append(ch)
        if isinstance(ch, _Table):
            grids.append(ch.grid)
    knots = np.unique(np.concatenate(grids)) if grids else np.zeros(0)
    knots = knots[(knots > 1e-12 * tmax) & (knots < tmax * (1 - 1e-12))]
    return InputSignal(names, channels, knots)


def _channel(value, name: str, shared: np.ndarray | None, tmax: float):
    if isinstance(value, bool):
        raise ArgumentTypeError(f"input {name!r}: got a bool; give a number, a table or a callable f(t).")
    if isinstance(value, _NUMBER) or (isinstance(value, np.ndarray) and value.ndim == 0):
        v = float(value)
        if not np.isfinite(v):
            raise DimensionError(f"input {name!r} must be finite; got {v}.")
        return _Constant(v)
    if callable(value):
        return _Function(value, name)
    if isinstance(value, tuple):
        if len(value) != 2:
            raise DimensionError(f"input {name!r}: a tuple must be a pair (grid, values); got {len(value)} items.")
        grid = _grid(value[0], tmax, f"the grid of input {name!r}")
        return _Table(grid, _values(value[1], grid, name))
    if isinstance(value, (str, bytes, Mapping)):
        raise ArgumentTypeError(f"input {name!r}: unsupported value of type {type(value).__name__}; give a number, "
                        "a pair (grid, values), values on the shared grid 't', or a callable f(t).")
    if shared is None:
        raise DimensionError(f"input {name!r} is an array but no time grid is given; pass "
                             f"{{'t': grid, {name!r}: values}} or {name!r}: (grid, values).")
    return _Table(shared, _values(value, shared, name))


def _grid(grid, tmax: float, what: str) -> np.ndarray:
    try:
        g = np.asarray(grid, dtype=float)
    except (TypeError, ValueError) as exc:
        raise DimensionError(f"{what} must be a 1-D array of times [s]; got {grid!r}.") from exc
    if g.ndim != 1 or g.size < 2:
        raise DimensionError(f"{what} must be a 1-D array of at least 2 times [s]; got shape {g.shape}.")
    if not np.all(np.isfinite(g)) or np.any(np.diff(g) <= 0.0):
        raise DimensionError(f"{what} must be finite and strictly increasing.")
    tol = 1e-9 * tmax
    if g[0] > tol or g[-1] < tmax - tol:
        raise DimensionError(f"{what} spans [{g[0]:g}, {g[-1]:g}] s but the simulation runs over [0, {tmax:g}] s; "
                             "extend it (table inputs are never extrapolated).")
    return g


def _values(values, grid: np.ndarray, name: str) -> np.ndarray:
    try:
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise DimensionError(f"input {name!r}: values must be numbers; got {values!r}.") from exc
    if v.shape != grid.shape:
        raise DimensionError(f"input {name!r} has {v.size} values (shape {v.shape}) on a grid of {grid.size} "
                             "times; give one value per grid time.")
    if not np.all(np.isfinite(v)):
        i = int(np.flatnonzero(~np.isfinite(v))[0])
        raise DimensionError(f"input {name!r} is not finite at t = {grid[i]:g} s (value {v[i]}).")
    return v
