"""Cases of a sweep: grids, lists, and the resolution of each setting onto a model.

A case is a mapping ``{key: value}``. Each key is resolved, in this order:

1. a *setter* given to :func:`mbsym.sweep` (``setters={key: f}``), ``f(value)`` returning a
   dict with any of ``"p"``, ``"x0"``, ``"inputs"``, ``"options"`` (how a later layer maps
   deck keys or wind specifications onto a model);
2. a parameter name of the model → parameter value;
3. a state name → initial state entry;
4. an input name → input specification (a number, a table ``(grid, values)``, a callable
   ``f(t)``; see :mod:`mbsym.simulate.inputs`);
5. a run option: ``tmax`` [s], ``dt`` [s].

Unknown keys stop the sweep before anything runs; a value that fails (a setter that
raises, a non-finite number) fails its case only.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

from ..exceptions import SweepError

__all__ = ["Case", "grid", "as_cases", "resolve_case", "check_keys", "OPTIONS"]

#: Run options a case may set.
OPTIONS: tuple[str, ...] = ("tmax", "dt")
_PARTS = ("p", "x0", "inputs", "options")


@dataclass
class Case:
    """One resolved case.

    Attributes
    ----------
    index : int
        Row of the case in the sweep's table.
    settings : dict
        The case as given (keys exactly as passed).
    p : dict
        Parameter values by name (on top of the model's defaults).
    x0 : dict
        Initial-state entries by state name (on top of the model's default state).
    inputs : dict
        Input specifications by input name.
    options : dict
        ``tmax``, ``dt``.
    """

    index: int
    settings: dict
    p: dict = field(default_factory=dict)
    x0: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    options: dict = field(default_factory=dict)


def grid(axes: Mapping[str, Sequence] | None = None, /, **more: Sequence) -> list[dict]:
    """Every combination of the values of each key (the last key varies fastest).

    Keys may be given as a dict (any string, e.g. ``"TwrFADmp(1)"``) and/or as keywords.

    Examples
    --------
    >>> grid({"k": [1.0, 2.0]}, c=[0.1, 0.2])
    [{'k': 1.0, 'c': 0.1}, {'k': 1.0, 'c': 0.2}, {'k': 2.0, 'c': 0.1}, {'k': 2.0, 'c': 0.2}]
    """
    merged = {**dict(axes or {}), **more}
    for key, values in merged.items():
        if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) and not hasattr(values, "__len__"):
            raise SweepError(f"grid axis {key!r} must be a sequence of values (e.g. [1.0, 2.0]); got {values!r}.")
        if len(values) == 0:
            raise SweepError(f"grid axis {key!r} has no values.")
    keys = list(merged)
    return [dict(zip(keys, combo)) for combo in itertools.product(*(list(merged[k]) for k in keys))]


def as_cases(cases: Any) -> list[dict]:
    """A list of case dicts from a grid (a dict of value lists) or a sequence of dicts."""
    if isinstance(cases, Mapping):
        return grid(cases)
    if isinstance(cases, (str, bytes)) or not isinstance(cases, Sequence):
        raise SweepError("cases must be a dict of value lists (a grid) or a list of dicts (one per case); "
                         f"got {type(cases).__name__}.")
    out = []
    for i, c in enumerate(cases):
        if not isinstance(c, Mapping):
            raise SweepError(f"case {i} must be a dict {{key: value}}; got {type(c).__name__}.")
        out.append(dict(c))
    if not out:
        raise SweepError("no cases to run: cases is empty.")
    return out


def check_keys(cases: Sequence[Mapping], *, parameters: Sequence[str], states: Sequence[str],
               inputs: Sequence[str], setters: Mapping[str, Callable]) -> None:
    """Raise SweepError listing every key no case can resolve (nothing has run yet)."""
    known = set(setters) | set(parameters) | set(states) | set(inputs) | set(OPTIONS)
    unknown = sorted({k for c in cases for k in c if k not in known}, key=str)
    if unknown:
        raise SweepError(f"case keys {unknown} are not parameters, states, inputs or options of this model; "
                         f"parameters: {list(parameters)}; states: {list(states)}; inputs: {list(inputs)}; "
                         f"options: {list(OPTIONS)}" + (f"; setters: {list(setters)}" if setters else "") + ".")


def resolve_case(index: int, settings: Mapping, base: Mapping[str, Mapping], *, parameters: Sequence[str],
                 states: Sequence[str], inputs: Sequence[str], setters: Mapping[str, Callable]) -> Case:
    """The :class:`Case` of ``settings`` on top of ``base`` (dicts ``p``, ``x0``, ``inputs``, ``options``).

    Raises
    ------
    SweepError
        A setter that does not return a dict of the known parts.
    Exception
        Whatever a setter raises (the sweep records it in the case's row).
    """
    parts = {k: dict(base.get(k) or {}) for k in _PARTS}
    pset, sset, iset = set(parameters), set(states), set(inputs)
    for key, value in settings.items():
        if key in setters:
            got = setters[key](value)
            if not isinstance(got, Mapping) or set(got) - set(_PARTS):
                raise SweepError(f"the setter of {key!r} must return a dict with keys among {list(_PARTS)}; "
                                 f"got {got!r}.")
            for part, values in got.items():
                parts[part].update(values)
        elif key in pset:
            parts["p"][key] = value
        elif key in sset:
            parts["x0"][key] = value
        elif key in iset:
            parts["inputs"][key] = value
        else:
            parts["options"][key] = value
    return Case(index, dict(settings), **parts)
