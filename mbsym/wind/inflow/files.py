"""Wind files: OpenFAST InflowWind uniform wind files (``.hh``) and ``Time_[s],Wind1VelX_[m/s]`` CSV.

Uniform wind file (InflowWind ``WindType = 2``): lines starting with ``!`` are
comments; every other non-blank line holds 8 or 9 numbers

=====  ==========  ===========================================  =========================
col    InflowWind   meaning                                      :class:`UniformWind` field
=====  ==========  ===========================================  =========================
1      Time        time [s]                                     ``time``
2      HorSpd      horizontal wind speed [m/s]                  ``speed``
3      WndDir      wind direction [deg] (stored in rad)         ``direction``
4      VerSpd      vertical wind speed [m/s]                    ``vertical_speed``
5      HorShr      linear horizontal shear [-]                  ``horizontal_shear``
6      VerShr      power-law vertical shear exponent [-]        ``power_law_exponent``
7      LnVShr      linear vertical shear [-]                    ``linear_vertical_shear``
8      GstSpd      gust speed, added to HorSpd [m/s]            ``gust_speed``
9      Upflow      upflow angle [deg] (optional; stored in rad) ``upflow``
=====  ==========  ===========================================  =========================

At hub height InflowWind's uniform-wind model gives the longitudinal speed
``Wind1VelX = (HorSpd + GstSpd) cos(Upflow) cos(WndDir)``; the shears act only
away from the hub.  :meth:`UniformWind.signal` returns that hub signal and
refuses (unless told otherwise) a file whose direction, vertical speed, shears or
upflow are not zero, since a hub-height signal cannot carry them.

Every problem raises :class:`~mbsym.exceptions.OpenFASTFormatError` naming the
file and line.  Files are written with ``repr`` precision, so writing and reading
back gives the same numbers bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError, WindInputError
from .signals import TabulatedWind, WindSignal, _number

__all__ = ["UniformWind", "read_uniform_wind", "write_uniform_wind", "read_wind_csv", "write_wind_csv",
           "UNIFORM_COLUMNS"]

#: InflowWind column name → :class:`UniformWind` field (angles converted deg ↔ rad).
UNIFORM_COLUMNS = {"Time": "time", "HorSpd": "speed", "WndDir": "direction", "VerSpd": "vertical_speed",
                   "HorShr": "horizontal_shear", "VerShr": "power_law_exponent",
                   "LnVShr": "linear_vertical_shear", "GstSpd": "gust_speed", "Upflow": "upflow"}
_UNITS = ("(s)", "(m/s)", "(deg)", "(m/s)", "(-)", "(-)", "(-)", "(m/s)", "(deg)")
_ANGLES = ("direction", "upflow")
_UNMODELLED = ("direction", "vertical_speed", "horizontal_shear", "power_law_exponent",
               "linear_vertical_shear", "upflow")


@dataclass(frozen=True, eq=False)
class UniformWind:
    """The columns of an InflowWind uniform wind file, in SI units (angles in rad).

    All arrays have the length of ``time``; missing columns are zero.  ``path`` and
    ``lines`` (the line number of each row) are kept for messages.
    """

    time: np.ndarray
    speed: np.ndarray
    direction: np.ndarray | None = None
    vertical_speed: np.ndarray | None = None
    horizontal_shear: np.ndarray | None = None
    power_law_exponent: np.ndarray | None = None
    linear_vertical_shear: np.ndarray | None = None
    gust_speed: np.ndarray | None = None
    upflow: np.ndarray | None = None
    path: str | None = None
    lines: tuple[int, ...] = field(default=())

    def __post_init__(self) -> None:
        time = np.array(self.time, dtype=float).reshape(-1)
        where = f" ({self.path})" if self.path else ""
        for name in UNIFORM_COLUMNS.values():
            value = getattr(self, name)
            arr = np.zeros(time.size) if value is None else np.array(value, dtype=float).reshape(-1)
            if arr.shape != time.shape:
                raise WindInputError(f"UniformWind{where}: {name} has {arr.size} values; expected {time.size} "
                                     "(one per time).")
            if not np.all(np.isfinite(arr)):
                raise WindInputError(f"UniformWind{where}: {name} must be finite.")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        if time.size < 1:
            raise WindInputError(f"UniformWind{where}: at least one row is needed.")
        if np.any(np.diff(time) <= 0.0):
            j = int(np.flatnonzero(np.diff(time) <= 0.0)[0])
            raise WindInputError(f"UniformWind{where}: times must strictly increase; {time[j + 1]:g} s follows "
                                 f"{time[j]:g} s.")

    @property
    def hub_speed(self) -> np.ndarray:
        """Longitudinal hub-height speed ``(HorSpd + GstSpd) cos(Upflow) cos(WndDir)`` [m/s]."""
        return (self.speed + self.gust_speed) * np.cos(self.upflow) * np.cos(self.direction)

    def unmodelled(self) -> dict[str, float]:
        """Columns a hub-height signal cannot carry that are non-zero → their largest |value|."""
        return {name: float(np.max(np.abs(getattr(self, name)))) for name in _UNMODELLED
                if np.any(getattr(self, name) != 0.0)}

    def signal(self, *, allow_unmodelled: bool = False) -> TabulatedWind:
        """The hub-height longitudinal wind (:attr:`hub_speed`) as a :class:`TabulatedWind`.

        Raises
        ------
        WindInputError
            If direction, vertical speed, a shear or the upflow is non-zero and
            ``allow_unmodelled`` is False: a uniform-inflow rotor model would silently
            ignore them (with ``allow_unmodelled=True`` only the hub speed is used).
        """
        bad = self.unmodelled()
        if bad and not allow_unmodelled:
            listed = ", ".join(f"{k} (max |value| {v:g})" for k, v in bad.items())
            raise WindInputError(f"uniform wind {self.path or ''}: non-zero {listed}. The hub-height wind "
                                 "signal models only the speed along the rotor axis; set these columns to zero "
                                 "or pass allow_unmodelled=True to use Wind1VelX at the hub and ignore the rest.")
        return TabulatedWind(self.time, self.hub_speed, source=self.path or "uniform wind")

    @classmethod
    def from_signal(cls, wind: WindSignal, t_end: float, *, dt: float = 0.05) -> UniformWind:
        """Tabulate a signal over ``[0, t_end]`` (see :meth:`WindSignal.table`) as uniform wind."""
        time, speed = wind.table(t_end, dt=dt)
        return cls(time, speed)


def _file(path) -> Path:
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"wind file not found: tried '{p.absolute()}'. Check the path.")
    return p


def _raise(path: Path, problems: list[str]) -> None:
    if len(problems) == 1:
        raise OpenFASTFormatError(problems[0])
    if problems:
        shown = problems[:20] + ([f"... and {len(problems) - 20} more"] if len(problems) > 20 else [])
        raise OpenFASTFormatError(f"{len(problems)} problems in {path}:\n  - " + "\n  - ".join(shown))


def _numbers(tokens: list[str]) -> list[float] | None:
    try:
        values = [float(t.replace("d", "e").replace("D", "E")) for t in tokens]
    except ValueError:
        return None
    return values if all(math.isfinite(v) for v in values) else None


def read_uniform_wind(path) -> UniformWind:
    """Read an InflowWind uniform wind file (``.hh``); see the module docstring.

    Raises
    ------
    OpenFASTFormatError
        Missing file, a non-numeric or non-finite entry, a row with the wrong number
        of columns, times not strictly increasing, no data rows; names file and line.

    Examples
    --------
    >>> from mbsym.wind.inflow import read_uniform_wind
    >>> w = read_uniform_wind("step_10_14.hh")  # doctest: +SKIP
    >>> w.signal()(35.0)  # doctest: +SKIP
    14.0
    """
    p = _file(path)
    rows, lines, problems, width = [], [], [], None
    for number, raw in enumerate(p.read_text(encoding="latin-1").splitlines(), start=1):
        text = raw.strip()
        if not text or text.startswith(("!", "#")):
            continue
        values = _numbers(text.replace(",", " ").split())
        if values is None:
            problems.append(f"{p}, line {number}: expected numbers (Time HorSpd WndDir VerSpd HorShr VerShr "
                            f"LnVShr GstSpd [Upflow]), got {text[:60]!r}. Comment it out with '!' or fix it.")
            continue
        if len(values) not in (8, 9):
            problems.append(f"{p}, line {number}: expected 8 or 9 columns (Time HorSpd WndDir VerSpd HorShr VerShr "
                            f"LnVShr GstSpd [Upflow]), got {len(values)}. Fix the row.")
            continue
        if width is not None and len(values) != width:
            problems.append(f"{p}, line {number}: has {len(values)} columns but line {lines[0]} has {width}. "
                            "Give every row the same columns.")
            continue
        width = len(values)
        if rows and values[0] <= rows[-1][0]:
            problems.append(f"{p}, line {number}: time {values[0]:g} s does not increase (line {lines[-1]} has "
                            f"{rows[-1][0]:g} s). Times must strictly increase.")
            continue
        rows.append(values + [0.0] * (9 - len(values)))
        lines.append(number)
    if not rows and not problems:
        problems.append(f"{p}: no data rows found (every line is blank or a '!' comment). Add rows "
                        "'Time HorSpd WndDir VerSpd HorShr VerShr LnVShr GstSpd'.")
    _raise(p, problems)
    data = np.array(rows, dtype=float)
    columns = {name: data[:, j] for j, name in enumerate(UNIFORM_COLUMNS.values())}
    for name in _ANGLES:
        columns[name] = np.deg2rad(columns[name])
    return UniformWind(**columns, path=str(p), lines=tuple(lines))


def write_uniform_wind(path, wind: UniformWind | WindSignal, *, t_end: float | None = None, dt: float = 0.05,
                       comment: str = "") -> Path:
    """Write a uniform wind file readable by OpenFAST's InflowWind (``WindType = 2``).

    Parameters
    ----------
    path : str or Path
        File to write.
    wind : UniformWind or WindSignal
        A signal is tabulated over ``[0, t_end]`` with :meth:`WindSignal.table` (all
        other columns zero).
    t_end : float, optional
        End time [s]; required for a signal.
    dt : float, optional
        Sampling step [s] of smooth signals.
    comment : str, optional
        Extra comment line(s) for the header.

    Returns
    -------
    Path
        The file written.
    """
    if isinstance(wind, WindSignal):
        if t_end is None:
            raise WindInputError("t_end [s] is needed to tabulate a wind signal for a uniform wind file.")
        wind = UniformWind.from_signal(wind, t_end, dt=dt)
    elif not isinstance(wind, UniformWind):
        raise TypeError(f"wind must be a UniformWind or a WindSignal; got {type(wind).__name__}.")
    header = ["! OpenFAST InflowWind uniform wind file (WindType = 2), written by mbsym"]
    header += [f"! {line}" for line in comment.splitlines() if line.strip()]
    header.append("! " + " ".join(f"{name:>22}" for name in UNIFORM_COLUMNS))
    header.append("! " + " ".join(f"{unit:>22}" for unit in _UNITS))
    body = []
    for j in range(wind.time.size):
        row = []
        for name in UNIFORM_COLUMNS.values():
            value = float(getattr(wind, name)[j])
            row.append(repr(math.degrees(value) if name in _ANGLES else value))
        body.append("  " + " ".join(f"{v:>22}" for v in row))
    out = Path(path)
    out.write_text("\n".join(header + body) + "\n")
    return out


_TIME_NAMES = ("time_[s]", "time")
_SPEED_NAMES = ("wind1velx_[m/s]", "wind1velx")


def read_wind_csv(path) -> TabulatedWind:
    """Read a CSV with columns ``Time_[s]`` and ``Wind1VelX_[m/s]`` (other columns ignored).

    An OpenFAST output file converted to CSV (with those two channels among others)
    is accepted; the hub-height wind is ``Wind1VelX``.

    Raises
    ------
    OpenFASTFormatError
        Missing file or columns, non-numeric entries, ragged rows, times not
        strictly increasing; names file and line.
    """
    p = _file(path)
    lines = p.read_text(encoding="latin-1").splitlines()
    header = next(((n, line) for n, line in enumerate(lines, start=1) if line.strip()), None)
    if header is None:
        raise OpenFASTFormatError(f"{p}: the file is empty; expected a header 'Time_[s],Wind1VelX_[m/s]' and rows.")
    names = [c.strip().strip('"').lower() for c in header[1].split(",")]
    it = next((names.index(c) for c in _TIME_NAMES if c in names), None)
    iu = next((names.index(c) for c in _SPEED_NAMES if c in names), None)
    if it is None or iu is None:
        raise OpenFASTFormatError(f"{p}, line {header[0]}: the header must name the columns 'Time_[s]' and "
                                  f"'Wind1VelX_[m/s]'; got {header[1][:80]!r}. Rename the columns.")
    times, speeds, problems, last = [], [], [], None
    for number, raw in enumerate(lines[header[0]:], start=header[0] + 1):
        if not raw.strip():
            continue
        cells = raw.split(",")
        if len(cells) != len(names):
            problems.append(f"{p}, line {number}: {len(cells)} values but the header has {len(names)} columns.")
            continue
        values = _numbers([cells[it].strip(), cells[iu].strip()])
        if values is None:
            problems.append(f"{p}, line {number}: expected numbers in Time and Wind1VelX, got "
                            f"{cells[it].strip()!r}, {cells[iu].strip()!r}.")
            continue
        if last is not None and values[0] <= last[1]:
            problems.append(f"{p}, line {number}: time {values[0]:g} s does not increase (line {last[0]} has "
                            f"{last[1]:g} s).")
            continue
        times.append(values[0])
        speeds.append(values[1])
        last = (number, values[0])
    if not times and not problems:
        problems.append(f"{p}: no data rows after the header on line {header[0]}.")
    _raise(p, problems)
    return TabulatedWind(times, speeds, source=str(p))


def write_wind_csv(path, wind: WindSignal, *, t_end: float | None = None, dt: float = 0.05) -> Path:
    """Write ``Time_[s],Wind1VelX_[m/s]`` rows of a signal (a table is written as is).

    A :class:`TabulatedWind` is written at its own times; other signals are
    tabulated over ``[0, t_end]`` with :meth:`WindSignal.table`.
    """
    if not isinstance(wind, WindSignal):
        raise TypeError(f"wind must be a WindSignal; got {type(wind).__name__}.")
    if isinstance(wind, TabulatedWind) and t_end is None:
        time, speed = wind.time, wind.speed
    else:
        if t_end is None:
            raise WindInputError("t_end [s] is needed to tabulate a wind signal for a CSV file.")
        time, speed = wind.table(_number(t_end, "t_end", positive=True), dt=dt)
    rows = ["Time_[s],Wind1VelX_[m/s]"] + [f"{float(a)!r},{float(b)!r}" for a, b in zip(time, speed)]
    out = Path(path)
    out.write_text("\n".join(rows) + "\n")
    return out
