"""The tidy result of a sweep: one row per case, named columns, CSV out.

Column order (the contract the ``mbsym sweep`` command writes as CSV): the case keys
exactly as given (first-seen order), then the summary columns in the order the runs
produced them (``<channel>_mean``, ``_std``, ``_max``, ``_min`` per channel, then
``<channel>_del_m<m>``; modal columns for linearizations), then ``error`` (empty when
the case succeeded).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator, Sequence

import numpy as np

__all__ = ["SweepTable", "SweepResult"]


class SweepTable:
    """Columns of equal length by name (a light, dependency-free table).

    ``table["k"]`` is a numpy array for numeric columns and a list otherwise;
    ``table.rows()`` gives dicts; ``to_csv`` writes it; ``to_pandas`` converts it when
    pandas is installed.
    """

    def __init__(self, columns: dict[str, Sequence]) -> None:
        lengths = {len(v) for v in columns.values()}
        if len(lengths) > 1:
            raise ValueError(f"columns must have one length; got lengths {sorted(lengths)}.")
        self._columns = {str(k): list(v) for k, v in columns.items()}
        self._n = lengths.pop() if lengths else 0

    @property
    def columns(self) -> tuple[str, ...]:
        return tuple(self._columns)

    def __len__(self) -> int:
        return self._n

    def __contains__(self, name: str) -> bool:
        return name in self._columns

    def __getitem__(self, name: str):
        try:
            values = self._columns[name]
        except KeyError:
            raise KeyError(f"no column {name!r}; columns are {list(self._columns)}.") from None
        if all(isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) for v in values):
            return np.array(values, dtype=float)
        return list(values)

    def row(self, i: int) -> dict[str, Any]:
        return {k: v[i] for k, v in self._columns.items()}

    def rows(self) -> list[dict[str, Any]]:
        return [self.row(i) for i in range(self._n)]

    def __iter__(self) -> Iterator[dict[str, Any]]:
        return iter(self.rows())

    @property
    def failed(self) -> list[int]:
        """Indices of the rows whose case failed."""
        return [i for i, e in enumerate(self._columns.get("error", [])) if e]

    def to_csv(self, path) -> Path:
        """Write the table as CSV (numbers with 17 significant digits: exact round trip) and return the path."""
        path = Path(path)
        with path.open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(self.columns)
            for i in range(self._n):
                w.writerow([_cell(v[i]) for v in self._columns.values()])
        return path

    def to_pandas(self):
        """A ``pandas.DataFrame`` of the table (needs pandas)."""
        import pandas as pd

        return pd.DataFrame({k: self[k] for k in self._columns})

    def __repr__(self) -> str:
        return f"SweepTable({self._n} rows, columns={list(self._columns)})"

    def __str__(self) -> str:
        head = list(self._columns)[:8]
        lines = ["  ".join(f"{h[:14]:>14}" for h in head)]
        for i in range(min(self._n, 20)):
            lines.append("  ".join(f"{_short(self._columns[h][i]):>14}" for h in head))
        more = [] if self._n <= 20 else [f"... {self._n - 20} more rows"]
        extra = [] if len(self._columns) <= 8 else [f"... {len(self._columns) - 8} more columns"]
        return "\n".join(lines + more + extra)


def _cell(v) -> str:
    if v is None:
        return ""
    if isinstance(v, (float, np.floating)):
        return "nan" if math.isnan(v) else repr(float(v))
    return str(v)


def _short(v) -> str:
    if isinstance(v, (float, np.floating)):
        return f"{v:.6g}"
    return str(v)[:14]


@dataclass
class SweepResult:
    """What :func:`mbsym.sweep` returns.

    Attributes
    ----------
    table : SweepTable
        One row per case.
    series : list or None
        With ``series=True``: one entry per case (a ``SimulationResult`` for simulations, a dict
        ``A``, ``B``, ``eigenvalues`` for linearizations, the runner's return value for callables;
        None for a failed case).
    cases : list of Case
        The resolved cases (None where the case failed before running).
    executor : str
    wall_s : float
        Total wall time of the sweep [s].
    case_wall_s, case_cpu_s : ndarray
        Wall and CPU time of each case's evaluation (and summary) in its worker [s] (for mapped chunks, the
        chunk's time / size; CPU time of the process for in-process chunks, of the thread in workers).
    prepare_wall_s : float
        Building the plans (Functions, serialization) and sampling the inputs in this process [s].
    """

    table: SweepTable
    series: list | None
    cases: list
    executor: str
    wall_s: float
    case_wall_s: np.ndarray = field(default_factory=lambda: np.zeros(0))
    prepare_wall_s: float = 0.0
    case_cpu_s: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def to_csv(self, path) -> Path:
        """``table.to_csv(path)``."""
        return self.table.to_csv(path)

    def __repr__(self) -> str:
        return (f"SweepResult({len(self.table)} cases, {len(self.table.failed)} failed, executor={self.executor!r}, "
                f"wall {self.wall_s:.3g} s)")
