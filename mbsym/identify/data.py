"""Measured time series for identification: records, a generic CSV reader, checks.

A *record* is one experiment: a time grid and named channels sampled on it. The
identification accepts, for each record,

- a mapping with a ``"time"`` entry (array (N,) [s]) and one array (N,) per channel;
- an object with attributes ``time`` (N,), ``names`` (n) and ``data`` (N, n), e.g.
  :class:`mbsym.wind.analysis.compare.TimeSeries`;
- a path to a CSV file, read by ``reader`` (a callable ``path -> one of the above``)
  or, by default, by :func:`read_csv`;
- a :class:`Record`;

and a list of those for several records.
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from ..exceptions import DataError

__all__ = ["Record", "read_csv", "as_records"]


@dataclass(frozen=True)
class Record:
    """One measured time series.

    Attributes
    ----------
    time : ndarray (N,)
        Strictly increasing sample times [s].
    names : tuple of str
        Channel names.
    values : ndarray (N, n)
        Samples, one column per channel (may hold non-finite values in channels
        that are not used; used channels are checked).
    units : tuple of str
        One per channel ("" when unknown).
    source : str
        File name or ``"array"`` (for messages).
    """

    time: np.ndarray
    names: tuple[str, ...]
    values: np.ndarray
    units: tuple[str, ...]
    source: str = "array"

    def channel(self, name: str) -> np.ndarray:
        """Samples of one channel (N,)."""
        if name not in self.names:
            raise DataError(f"{self.source}: no channel {name!r}; its channels are {list(self.names)}.")
        return self.values[:, self.names.index(name)]


def _split_header(h: str) -> tuple[str, str]:
    h = h.strip()
    if h.endswith("]") and "_[" in h:
        name, unit = h[:-1].rsplit("_[", 1)
        return name, unit
    if h.endswith(")") and " (" in h:
        name, unit = h[:-1].rsplit(" (", 1)
        return name.strip(), unit
    return h, ""


def read_csv(path: str | os.PathLike) -> Record:
    """Read a CSV table: one header row, the first column time [s], then one column per channel.

    Headers ``Name_[unit]`` (OpenFAST's CSV layout), ``Name (unit)`` or ``Name`` are
    accepted; lines starting with ``#`` are skipped.

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    DataError
        No header, a non-numeric table, or a row with the wrong number of values.

    Examples
    --------
    >>> import tempfile, os
    >>> path = os.path.join(tempfile.mkdtemp(), "d.csv")
    >>> _ = open(path, "w").write("Time_[s],x_[m]\\n0,1\\n0.1,0.5\\n0.2,0.25\\n")
    >>> r = read_csv(path)
    >>> r.names, r.units, r.values[:, 0].tolist()
    (('x',), ('m',), [1.0, 0.5, 0.25])
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"data file not found: {path}")
    with path.open(newline="") as fh:
        rows = (line for line in fh if line.strip() and not line.lstrip().startswith("#"))
        header = next(csv.reader(rows), None)
    if not header or len(header) < 2:
        raise DataError(f"{path}: expected a header row 'Time, channel, ...' with at least one channel; "
                        f"got {header!r}.")
    try:
        table = np.loadtxt(path, delimiter=",", skiprows=1, comments="#", ndmin=2)
    except ValueError as exc:
        raise DataError(f"{path}: not a numeric CSV table after the header ({exc}).") from None
    if table.shape[1] != len(header):
        raise DataError(f"{path}: {len(header)} header columns but {table.shape[1]} data columns.")
    names, units = zip(*(_split_header(h) for h in header[1:]))
    return _checked(table[:, 0], names, table[:, 1:], units, str(path))


def _checked(time, names, values, units, source: str) -> Record:
    t = np.asarray(time, dtype=float).reshape(-1)
    v = np.asarray(values, dtype=float)
    if v.ndim == 1:
        v = v[:, None]
    names = tuple(str(n) for n in names)
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise DataError(f"{source}: channel names must be unique; {dup} appear more than once.")
    if v.shape != (t.size, len(names)):
        raise DataError(f"{source}: {len(names)} channels of {t.size} samples expected; data has shape {v.shape}.")
    if t.size < 3:
        raise DataError(f"{source}: at least 3 samples are needed; got {t.size}.")
    if not np.all(np.isfinite(t)):
        raise DataError(f"{source}: the time column must be finite; sample {int(np.flatnonzero(~np.isfinite(t))[0])} "
                        "is not.")
    if np.any(np.diff(t) <= 0):
        k = int(np.flatnonzero(np.diff(t) <= 0)[0])
        raise DataError(f"{source}: times must increase strictly; t[{k + 1}] = {t[k + 1]:g} s follows "
                        f"t[{k}] = {t[k]:g} s.")
    units = tuple(str(u) for u in units) if units is not None else ("",) * len(names)
    return Record(t, names, v, units, source)


def _from_mapping(data: Mapping, source: str) -> Record:
    key = next((k for k in ("time", "Time", "t", "Time_[s]") if k in data), None)
    if key is None:
        raise DataError(f"{source}: a data mapping needs a 'time' entry (array [s]) and one array per channel; "
                        f"got keys {list(data)}.")
    names = [k for k in data if k != key]
    try:
        cols = [np.asarray(data[n], dtype=float).reshape(-1) for n in names]
    except (TypeError, ValueError):
        raise DataError(f"{source}: every channel must be an array of numbers.") from None
    t = np.asarray(data[key], dtype=float).reshape(-1)
    bad = [n for n, c in zip(names, cols) if c.size != t.size]
    if bad:
        raise DataError(f"{source}: channels {bad} do not have {t.size} samples like 'time'.")
    values = np.column_stack(cols) if cols else np.zeros((t.size, 0))
    return _checked(t, names, values, None, source)


def _one(item: Any, reader: Callable | None, i: int) -> Record:
    source = f"record {i}"
    if isinstance(item, Record):
        return _checked(item.time, item.names, item.values, item.units, item.source)
    if isinstance(item, (str, os.PathLike)):
        got = reader(item) if reader is not None else read_csv(item)
        return _one(got, None, i) if not isinstance(got, Record) else got
    if isinstance(item, Mapping):
        return _from_mapping(item, source)
    if all(hasattr(item, a) for a in ("time", "names", "data")):
        return _checked(item.time, item.names, item.data, getattr(item, "units", None), source)
    raise TypeError(f"data {source} must be a dict with 'time', an object with time/names/data (e.g. an OpenFAST "
                    f"TimeSeries), a CSV path or a Record; got {type(item).__name__}.")


def as_records(data: Any, reader: Callable | None = None) -> list[Record]:
    """One :class:`Record` per experiment in ``data`` (see the module docstring).

    Raises
    ------
    TypeError
        Unsupported data kinds.
    DataError
        Inconsistent sizes, non-increasing or non-finite times.
    """
    if reader is not None and not callable(reader):
        raise TypeError(f"reader must be a callable path -> data; got {type(reader).__name__}.")
    items = list(data) if isinstance(data, (list, tuple)) else [data]
    if not items:
        raise DataError("data holds no record; pass one time series or a list of them.")
    return [_one(item, reader, i) for i, item in enumerate(items)]


def check_channels(records: Sequence[Record], channels: Sequence[str]) -> np.ndarray:
    """Data of ``channels`` per record stacked as a list of arrays (N_r, n_c); all must exist and be finite.

    Raises
    ------
    DataError
        A channel missing from a record, or a non-finite sample (names the channel and time).
    """
    out = []
    for r in records:
        missing = [c for c in channels if c not in r.names]
        if missing:
            raise DataError(f"{r.source}: channels {missing} are not in the data; its channels are "
                            f"{list(r.names)}. Choose channels present in both the model and the data.")
        Y = np.column_stack([r.channel(c) for c in channels])
        bad = ~np.isfinite(Y)
        if bad.any():
            k, j = map(int, np.argwhere(bad)[0])
            raise DataError(f"{r.source}: channel {channels[j]!r} is not finite at t = {r.time[k]:g} s "
                            f"(sample {k}: {Y[k, j]}); {int(bad[:, j].sum())} such samples. Remove or "
                            "interpolate them before identifying.")
        out.append(Y)
    return out
