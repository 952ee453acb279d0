"""Shared behaviour of the wind-parameter records (private).

:class:`_Record` gives the frozen dataclasses of :mod:`mbsym.wind.deck.parameters`
exact equality (arrays compared element-wise, fields with ``compare=False``
skipped) and JSON-compatible ``to_dict``/``from_dict`` round trips driven by the
type hints; :func:`_set_array` and :func:`_freeze_columns` store read-only,
finite float64 copies of array fields, checking their shapes.
"""

from __future__ import annotations

import dataclasses
import types
import typing
from typing import Any

import numpy as np

from ...exceptions import ParameterError


def _readonly(value: Any, name: str, shape_tail: tuple[int, ...] = ()) -> np.ndarray:
    """Return a read-only float64 copy of ``value``, checking finiteness and shape."""
    arr = np.array(value, dtype=float)
    want_ndim = 1 + len(shape_tail)
    if arr.ndim != want_ndim or arr.shape[1:] != shape_tail:
        expected = "(n,)" if not shape_tail else str(shape_tail)
        raise ParameterError(f"`{name}` has shape {arr.shape}; expected {expected}.")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"All entries of `{name}` must be finite numbers.")
    arr.setflags(write=False)
    return arr


def _values_equal(a: Any, b: Any) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return (isinstance(a, np.ndarray) and isinstance(b, np.ndarray)
                and a.shape == b.shape and bool(np.array_equal(a, b)))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_values_equal(a[k], b[k]) for k in a)
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(_values_equal(x, y) for x, y in zip(a, b))
    return bool(a == b)


class _Record:
    """Shared behaviour: exact equality with arrays, and dict (JSON) round trips."""

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return all(_values_equal(getattr(self, f.name), getattr(other, f.name))
                   for f in dataclasses.fields(self) if f.compare)  # type: ignore[arg-type]

    __hash__ = None  # type: ignore[assignment]

    def to_dict(self) -> dict[str, Any]:
        """Return a JSON-compatible dict (arrays and tuples become lists).

        Returns
        -------
        dict
            Field name → value; nested records become nested dicts.
        """
        return {f.name: _to_plain(getattr(self, f.name))
                for f in dataclasses.fields(self)}  # type: ignore[arg-type]

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Any:
        """Build an instance from :meth:`to_dict` output.

        Parameters
        ----------
        data : dict
            As produced by :meth:`to_dict` (e.g. loaded from JSON).

        Raises
        ------
        ParameterError
            If a field without a default is missing, a field is unknown, or a value is invalid
            (a field with a default may be missing: data written before it existed).
        """
        hints = typing.get_type_hints(cls)
        fields = dataclasses.fields(cls)  # type: ignore[arg-type]
        names = [f.name for f in fields]
        optional = {f.name for f in fields if f.default is not dataclasses.MISSING
                    or f.default_factory is not dataclasses.MISSING}
        missing = [n for n in names if n not in data and n not in optional]
        unknown = [k for k in data if k not in names]
        if missing or unknown:
            raise ParameterError(
                f"Cannot build {cls.__name__}: missing fields {missing}, unknown fields "
                f"{unknown}. Regenerate the data with {cls.__name__}.to_dict().")
        return cls(**{n: _from_plain(data[n], hints[n]) for n in names if n in data})


def _to_plain(value: Any) -> Any:
    if isinstance(value, _Record):
        return value.to_dict()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, tuple):
        return [_to_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _to_plain(v) for k, v in value.items()}
    return value


def _from_plain(value: Any, hint: Any) -> Any:
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if value is None:
        return None
    if origin in (typing.Union, types.UnionType):
        inner = [a for a in args if a is not type(None)]
        return _from_plain(value, inner[0])
    if isinstance(hint, type) and issubclass(hint, _Record):
        return hint.from_dict(value)
    if hint is np.ndarray:
        return np.array(value, dtype=float)
    if origin is tuple:
        return tuple(_from_plain(v, args[0]) for v in value)
    if origin is dict:
        return {k: _from_plain(v, args[1]) for k, v in value.items()}
    return value


def _freeze_columns(obj: Any) -> None:
    n = obj.station_fraction.shape[0]
    columns = {}
    for key, value in obj.extra_columns.items():
        columns[key] = _readonly(value, f"{type(obj).__name__}.extra_columns[{key!r}]")
        if columns[key].shape[0] != n:
            raise ParameterError(f"Column {key!r} has {columns[key].shape[0]} rows; expected {n}.")
    object.__setattr__(obj, "extra_columns", columns)


def _set_array(obj: Any, name: str, tail: tuple[int, ...], n: int) -> None:
    arr = _readonly(getattr(obj, name), f"{type(obj).__name__}.{name}", tail)
    if arr.shape[0] != n:
        raise ParameterError(
            f"`{type(obj).__name__}.{name}` has {arr.shape[0]} rows; expected {n} "
            "(one per station or mode).")
    object.__setattr__(obj, name, arr)
