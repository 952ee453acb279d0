"""Rotor performance tables in ROSCO's ``Cp_Ct_Cq.*.txt`` format.

A performance table holds the steady rotor power, thrust and torque coefficients
on a grid of tip-speed ratio (TSR, rows) × collective blade pitch (columns).
ROSCO writes and reads it as::

    # ----- Rotor performance tables for the <name> wind turbine -----
    # ------------ Written on <date> using the ROSCO toolbox ------------
    <blank>
    # Pitch angle vector, <n> entries - x axis (matrix columns) (deg)
    <pitch values, deg>
    # TSR vector, <m> entries - y axis (matrix rows) (-)
    <tsr values>
    # Wind speed vector - z axis (m/s)
    <one wind speed>
    <blank>
    # Power coefficient
    <blank>
    <m rows of n values>
    <blank>
    <blank>
    #  Thrust coefficient
    ...
    # Torque coefficient
    ...

ROSCO's own Fortran reader (``ReadCpFile``) reads this **by line position**, so
:func:`write_performance_table` reproduces that layout line for line.
:func:`read_performance_table` is stricter and more forgiving at once: it finds
the sections by their comment labels (``pitch angle``, ``tsr``, ``wind speed``,
``power``, ``thrust``, ``torque``), ignores other comment lines and blank lines,
and reports every problem (missing section, wrong count, a row of the wrong
length, a non-number, a non-increasing axis) with the file and line, all
together, as one :class:`~mbsym.exceptions.OpenFASTFormatError`.

Units: the file holds pitch in **degrees**; :class:`PerformanceTable` stores it in
**radians** (``pitch``, as everywhere in mbsym) and offers ``pitch_deg``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...exceptions import DimensionError, OpenFASTFormatError, ParameterError

__all__ = ["PerformanceTable", "read_performance_table", "write_performance_table"]

_REAL = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")
_ENTRIES = re.compile(r"(\d+)\s+entries", re.I)
# (section name, words that identify its comment label), in file order
_SECTIONS = (("pitch", ("pitch",)), ("tsr", ("tsr",)), ("wind", ("wind speed",)),
             ("cp", ("power coefficient",)), ("ct", ("thrust coefficient",)),
             ("cq", ("torque coefficient",)))
_LABELS = {"pitch": "# Pitch angle vector, {n} entries - x axis (matrix columns) (deg)",
           "tsr": "# TSR vector, {n} entries - y axis (matrix rows) (-)",
           "wind": "# Wind speed vector - z axis (m/s)", "cp": "# Power coefficient",
           "ct": "#  Thrust coefficient", "cq": "# Torque coefficient"}


def _frozen(values: Any, name: str, ndim: int) -> np.ndarray:
    try:
        array = np.array(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"PerformanceTable.{name} must be an array of numbers: {exc}") from None
    if array.ndim != ndim:
        raise DimensionError(f"PerformanceTable.{name} must be {ndim}-D; got shape {array.shape}.")
    if not np.all(np.isfinite(array)):
        raise ParameterError(f"PerformanceTable.{name} holds non-finite values; every entry must be "
                             "a finite number.")
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class PerformanceTable:
    """Steady rotor coefficients on a tip-speed ratio × pitch grid (immutable).

    Attributes
    ----------
    tsr : ndarray, shape (m,)
        Tip-speed ratios λ = Ω R / U [-], strictly increasing (matrix rows).
    pitch : ndarray, shape (n,)
        Collective blade pitch [rad], strictly increasing (matrix columns).
    cp, ct, cq : ndarray, shape (m, n)
        Power, thrust and torque coefficients [-]:
        ``P = ½ ρ π R² U³ cp``, ``T = ½ ρ π R² U² ct``, ``Q = ½ ρ π R³ U² cq``
        (so ``cq = cp / tsr`` for a consistent table).
    wind_speed : float or None
        The single "z axis" wind speed written in ROSCO's file [m/s] (informational;
        ROSCO writes the rated speed). None if unknown.
    source : str or None
        The file the table was read from, or a description of how it was made.

    Arrays are read-only float64 copies; change a value with
    :func:`dataclasses.replace`.
    """

    tsr: np.ndarray
    pitch: np.ndarray
    cp: np.ndarray
    ct: np.ndarray
    cq: np.ndarray
    wind_speed: float | None = None
    source: str | None = field(default=None)

    def __post_init__(self) -> None:
        for name in ("tsr", "pitch"):
            axis = _frozen(getattr(self, name), name, 1)
            if axis.size < 2 or np.any(np.diff(axis) <= 0):
                raise ParameterError(f"PerformanceTable.{name} must hold at least 2 strictly "
                                     f"increasing values; got {axis.tolist()}.")
            object.__setattr__(self, name, axis)
        shape = (self.tsr.size, self.pitch.size)
        for name in ("cp", "ct", "cq"):
            matrix = _frozen(getattr(self, name), name, 2)
            if matrix.shape != shape:
                raise DimensionError(f"PerformanceTable.{name} must have shape (len(tsr), "
                                     f"len(pitch)) = {shape}; got {matrix.shape}.")
            object.__setattr__(self, name, matrix)
        if self.wind_speed is not None:
            speed = float(self.wind_speed)
            if not (math.isfinite(speed) and speed > 0):
                raise ParameterError(f"PerformanceTable.wind_speed must be a positive number "
                                     f"[m/s] or None; got {self.wind_speed!r}.")
            object.__setattr__(self, "wind_speed", speed)

    @property
    def pitch_deg(self) -> np.ndarray:
        """Collective pitch [deg] (a new array)."""
        return np.rad2deg(self.pitch)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, PerformanceTable):
            return NotImplemented
        return (self.wind_speed == other.wind_speed and all(
            np.array_equal(getattr(self, n), getattr(other, n))
            for n in ("tsr", "pitch", "cp", "ct", "cq")))

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return (f"PerformanceTable({self.tsr.size} TSR in [{self.tsr[0]:g}, {self.tsr[-1]:g}] x "
                f"{self.pitch.size} pitch in [{self.pitch_deg[0]:g}, {self.pitch_deg[-1]:g}] deg, "
                f"max cp {self.cp.max():.4f}, source={self.source!r})")


# ----------------------------------------------------------------------------- reading
@dataclass
class _Section:
    name: str
    label_line: int
    count: int | None  # "<n> entries" from the label, if given
    broken: bool = False  # a row had a non-number (already reported)
    rows: list[list[float]] = field(default_factory=list)
    lines: list[int] = field(default_factory=list)


def _section_of(comment: str) -> str | None:
    low = comment.lower()
    return next((name for name, words in _SECTIONS if any(w in low for w in words)), None)


def _parse(path: Path, lines: list[str], problems: list[str]) -> dict[str, _Section]:
    sections: dict[str, _Section] = {}
    current: _Section | None = None
    for number, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text:
            continue
        if text.startswith("#"):
            name = _section_of(text) if not text.lstrip("#").lstrip().startswith("---") else None
            if name is None:
                continue  # free-text comment (title lines)
            if name in sections:
                problems.append(f"{path}, line {number}: a second '{text}' section (the first is on "
                                f"line {sections[name].label_line}). Remove one of them.")
                current = None
                continue
            count = _ENTRIES.search(text)
            current = sections[name] = _Section(name, number, int(count.group(1)) if count else None)
            continue
        tokens = text.replace(",", " ").split()
        bad = [t for t in tokens if not _REAL.match(t)]
        if bad:
            problems.append(f"{path}, line {number}: expected numbers, got {bad[0]!r}. Fix the "
                            "value (finite numbers only) or start comment lines with '#'.")
            if current is not None:  # keep the row's place: no second, derived problem
                current.broken = True
                current.rows.append([math.nan] * len(tokens))
                current.lines.append(number)
            continue
        if current is None:
            problems.append(f"{path}, line {number}: numbers before any section label; expected a "
                            "label such as '# Pitch angle vector ...' first. Add it.")
            continue
        current.rows.append([float(t.replace("d", "e").replace("D", "E")) for t in tokens])
        current.lines.append(number)
    return sections


def _vector(path: Path, section: _Section, problems: list[str], what: str) -> np.ndarray | None:
    if section.broken:
        return None
    values = np.array([v for row in section.rows for v in row], dtype=float)
    where = f"{path}, line {section.label_line}"
    if values.size < 2:
        problems.append(f"{where}: the {what} needs at least 2 values; got {values.size}. "
                        "Add them on the line after the label.")
        return None
    if section.count is not None and section.count != values.size:
        problems.append(f"{where}: the label says {section.count} entries, but {values.size} "
                        f"values follow. Make the count match the {what}.")
    steps = np.diff(values)
    if np.any(steps <= 0):
        j = int(np.argmax(steps <= 0)) + 1
        problems.append(f"{path}, line {section.lines[0]}: the {what} must strictly increase; "
                        f"value {j + 1} ({values[j]:g}) follows {values[j - 1]:g}. Fix the order.")
        return None
    return values


def _matrix(path: Path, section: _Section, shape: tuple[int, int], problems: list[str],
            what: str) -> np.ndarray | None:
    n_rows, n_cols = shape
    ok = True
    if len(section.rows) != n_rows:
        problems.append(f"{path}, line {section.label_line}: the {what} table has "
                        f"{len(section.rows)} rows; expected {n_rows} (one per TSR value). "
                        "Make the table match the TSR vector.")
        ok = False
    for line, row in zip(section.lines, section.rows):
        if len(row) != n_cols:
            problems.append(f"{path}, line {line}: this {what} row has {len(row)} values; "
                            f"expected {n_cols} (one per pitch value). Fix the row.")
            ok = False
            break
    if not ok or section.broken:
        return None
    matrix = np.array(section.rows, dtype=float)
    if not np.all(np.isfinite(matrix)):
        row = int(np.argmax(~np.all(np.isfinite(matrix), axis=1)))
        problems.append(f"{path}, line {section.lines[row]}: a {what} value overflows to a "
                        "non-finite number. Fix it.")
        return None
    return matrix


def read_performance_table(path: str | Path) -> PerformanceTable:
    """Read a rotor performance table in ROSCO's ``Cp_Ct_Cq`` text format.

    Parameters
    ----------
    path : str or Path
        The ``Cp_Ct_Cq.*.txt`` file (pitch in deg in the file).

    Returns
    -------
    PerformanceTable
        TSR [-], pitch [rad], cp, ct, cq [-], the file's wind speed [m/s] and
        ``source`` = the path.

    Raises
    ------
    OpenFASTFormatError
        If the file is missing, a section (pitch, TSR, power, thrust or torque
        coefficient) is missing or repeated, a count or row length is wrong, a
        value is not a finite number, or an axis does not strictly increase;
        every problem is reported with file and line, all together.

    Examples
    --------
    >>> from mbsym.wind.deck.performance import read_performance_table
    >>> table = read_performance_table("Cp_Ct_Cq.NREL5MW.txt")  # doctest: +SKIP
    >>> table.cp.shape, table.pitch_deg[0]  # doctest: +SKIP
    ((26, 36), -5.0)
    """
    path = Path(path)
    if not path.is_file():
        raise OpenFASTFormatError(f"rotor performance table not found: tried '{path.absolute()}'. "
                                  "Check the path (DISCON.IN names it as PerfFileName).")
    lines = path.read_text(encoding="latin-1").splitlines()
    problems: list[str] = []
    sections = _parse(path, lines, problems)
    missing = [_LABELS[name].format(n="<n>") for name, _ in _SECTIONS
               if name != "wind" and name not in sections]
    for label in missing:
        problems.append(f"{path}, line {len(lines)}: the section '{label}' is missing (a label "
                        "line starting with '#', then its numbers). Add it.")
    pitch = tsr = None
    if "pitch" in sections:
        pitch = _vector(path, sections["pitch"], problems, "pitch angle vector")
    if "tsr" in sections:
        tsr = _vector(path, sections["tsr"], problems, "TSR vector")
    wind_speed = None
    if "wind" in sections:
        values = [v for row in sections["wind"].rows for v in row]
        if len(values) > 1 or (values and not values[0] > 0):
            problems.append(f"{path}, line {sections['wind'].label_line}: expected one positive "
                            f"wind speed [m/s]; got {values}. Fix it (performance tables are 2-D).")
        elif values:
            wind_speed = values[0]
    matrices: dict[str, np.ndarray | None] = {}
    if pitch is not None and tsr is not None:
        for name, what in (("cp", "power coefficient"), ("ct", "thrust coefficient"),
                           ("cq", "torque coefficient")):
            if name in sections:
                matrices[name] = _matrix(path, sections[name], (tsr.size, pitch.size), problems,
                                         what)
    if problems:
        problems.sort(key=lambda text: int(re.search(r", line (\d+)", text).group(1)))
        if len(problems) == 1:
            raise OpenFASTFormatError(problems[0])
        raise OpenFASTFormatError(f"{len(problems)} problems in {path}:\n  - "
                                  + "\n  - ".join(problems))
    return PerformanceTable(tsr=tsr, pitch=np.deg2rad(pitch), cp=matrices["cp"],
                            ct=matrices["ct"], cq=matrices["cq"], wind_speed=wind_speed,
                            source=str(path))


# ----------------------------------------------------------------------------- writing
def _axis(values: np.ndarray) -> list[float]:
    """Axis values rounded to 12 significant digits (undoes deg/rad round-off)."""
    return [float(f"{v:.12g}") for v in values]


def _row(values: Any, fmt: str) -> str:
    return "".join(f"{fmt.format(v)}   " for v in values)


def write_performance_table(table: PerformanceTable, path: str | Path, *,
                            turbine_name: str = "mbsym", decimals: int = 6,
                            wind_speed: float | None = None) -> Path:
    """Write ``table`` in ROSCO's ``Cp_Ct_Cq`` text format (ROSCO's line layout).

    Parameters
    ----------
    table : PerformanceTable
        The table (pitch in rad; written in deg).
    path : str or Path
        Output file (overwritten).
    turbine_name : str, optional
        Name in the title line.
    decimals : int, optional
        Decimals of the cp, ct, cq values (ROSCO writes 6). The axes are written
        with full precision (``repr``), so they round-trip exactly.
    wind_speed : float, optional
        The "z axis" wind speed [m/s]; default ``table.wind_speed``, or 0 if unknown
        (ROSCO reads and ignores it).

    Returns
    -------
    Path
        The file written.
    """
    if not isinstance(table, PerformanceTable):
        raise TypeError(f"write_performance_table needs a PerformanceTable; got "
                        f"{type(table).__name__}.")
    if not isinstance(decimals, int) or isinstance(decimals, bool) or not 1 <= decimals <= 16:
        raise ParameterError(f"decimals must be an integer in [1, 16]; got {decimals!r}.")
    speed = table.wind_speed if wind_speed is None else float(wind_speed)
    speed = 0.0 if speed is None else speed
    value_fmt = f"{{:.{decimals}f}}"
    out = [f"# ----- Rotor performance tables for the {turbine_name} wind turbine ----- ",
           "# ------------ Written by mbsym ------------ ", "",
           _LABELS["pitch"].format(n=table.pitch.size),
           _row(_axis(table.pitch_deg), "{!r}"),
           _LABELS["tsr"].format(n=table.tsr.size), _row(_axis(table.tsr), "{!r}"),
           _LABELS["wind"], f"{speed!r}   ", ""]
    for name in ("cp", "ct", "cq"):
        out += [_LABELS[name], ""]
        out += [_row(row, value_fmt) for row in getattr(table, name)]
        out += ["", ""] if name != "cq" else [""]
    path = Path(path)
    path.write_text("\n".join(out) + "\n", encoding="utf-8")
    return path
