"""Sweeps: many cases of one model, on one machine or a Dask cluster, as one tidy table.

:func:`sweep` resolves each case (parameter values, initial states, inputs, run options,
or any key through a setter), builds the CasADi Functions once (a *plan*), ships them to
the executor's workers by serialization, and tabulates per-case statistics (mean, std,
max, min, damage-equivalent loads) or modal summaries, with failures recorded per row.
This layer is general: it never imports :mod:`mbsym.wind`.
"""

from .api import DEFAULT_DT, sweep
from .cases import OPTIONS, Case, grid
from .executors import ExecutorSpec, parse_executor
from .stats import STATISTICS, channel_statistics, damage_equivalent_load, modal_summary
from .table import SweepResult, SweepTable

__all__ = ["sweep", "grid", "Case", "SweepResult", "SweepTable", "ExecutorSpec", "parse_executor",
           "damage_equivalent_load", "channel_statistics", "modal_summary", "STATISTICS", "OPTIONS", "DEFAULT_DT"]
