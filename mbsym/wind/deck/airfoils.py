"""Read AeroDyn 15 airfoil files (AirfoilInfo format): steady polars Cl, Cd, Cm vs AoA.

An AirfoilInfo file is a keyed OpenFAST file whose comment lines start with ``!``:
``InterpOrd``, ``NonDimArea``, ``NumCoords`` (often an ``@file`` include of the
shape coordinates, not needed here), ``BL_file``, ``NumTabs``, then per table
``Re`` (millions), ``UserProp``, ``InclUAdata`` (+ unsteady-aero constants),
``NumAlf`` and ``NumAlf`` rows of coefficients.  The columns holding AoA [deg],
Cl, Cd and Cm are named by the AeroDyn main file (``InCol_Alfa`` ... ``InCol_Cm``;
``InCol_Cm = 0`` means no Cm column).

mbsym reads the **first table** (what AeroDyn uses with ``AFTabMod = 1``), or with ``user_prop`` the table
whose ``UserProp`` equals it (``AFTabMod = 3``, whose input is 0 without ServoDyn's airfoil control); the
number of tables is kept in :attr:`AirfoilPolar.n_tables`.  The keys are read with
the strict, line-numbered parser of :mod:`mbsym.wind.deck._format`; the table rows
are read here.  Problems raise :class:`~mbsym.exceptions.OpenFASTFormatError`
naming the file and line, all problems of a file together.

Like AeroDyn's default (``InterpOrd = "default"`` = 1), the polars are meant to be
interpolated linearly in AoA; the file's choice is kept in ``interp_order``.

The unsteady-aerodynamics block of the first table (``InclUAdata`` and the constants
after it) becomes :attr:`AirfoilPolar.ua`, completed as AeroDyn does (see
:mod:`mbsym.wind.deck.airfoil_ua`): a missing line, ``"Default"`` (where AeroDyn
accepts it) or ``InclUAdata = False`` lets AeroDyn compute the constant.  A table
whose coefficients do not vary (AeroDyn's ``ConstData``) has no UA constants.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError, ParameterError
from ._format import _TOKEN, _canon, _Deck, _Key, _real
from ._record import _readonly, _Record
from .airfoil_ua import (_ANGLE_KEYS, _KEYWORD_DEFAULT_KEYS, UA_KEYS, UACoefficients,
                         ua_coefficients_from_polar)

__all__ = ["AirfoilPolar", "read_airfoil"]

_DEG = math.pi / 180.0
# Precision of the ConstData comparison: ReKi of OpenFAST's DOUBLE_PRECISION build (the CMake default of
# OpenFAST v5 and the shared v5.0.0 binary): float64, tolerance 1.1e-14 (a single-precision build would use
# float32, 5.96e-6).
_CONST_DATA_REAL = np.float64


@dataclass(frozen=True, eq=False)
class AirfoilPolar(_Record):
    """Steady aerodynamic coefficients of one airfoil (immutable).

    Attributes
    ----------
    name : str
        The airfoil's name (file stem, e.g. ``"DU21_A17"``).
    alpha : ndarray, shape (n,)
        Angle of attack [rad], strictly increasing, spanning [-π, π].
    cl, cd, cm : ndarray, shape (n,)
        Lift, drag and pitching-moment (about the 1/4 chord, nose up positive)
        coefficients [-]; ``cm`` is zero where the file has no Cm column.
    reynolds : float
        Reynolds number of the table [-] (the file gives it in millions).
    interp_order : int
        1 (linear, AeroDyn's default) or 3 (cubic spline), as the file asks.
    n_tables : int
        Number of tables in the file; one is kept (:attr:`table`).
    source : str or None
        The file read (not compared by ``==``).
    ua : UACoefficients or None
        Unsteady-aerodynamics (Beddoes-Leishman, UA_Mod 2/3) constants of the table, as
        AeroDyn completes them; None for constant data.
    constant_data : bool
        AeroDyn's ``ConstData``: fewer than 3 rows, or every row equal to the next in all
        coefficient columns (NWTC ``EqualRealNos`` in double precision, the shared OpenFAST build).
    table : int
        Which table of the file this is (0-based): the first (``AFTabMod = 1``), or the one for the airfoil
        input ``UserProp`` (``AFTabMod = 3``).
    """

    name: str
    alpha: np.ndarray
    cl: np.ndarray
    cd: np.ndarray
    cm: np.ndarray
    reynolds: float
    interp_order: int = 1
    n_tables: int = 1
    source: str | None = field(default=None, compare=False)
    ua: UACoefficients | None = None
    constant_data: bool = False
    table: int = 0

    def __post_init__(self) -> None:
        alpha = _readonly(self.alpha, f"AirfoilPolar({self.name}).alpha")
        if alpha.size < 2 or np.any(np.diff(alpha) <= 0):
            raise ParameterError(f"AirfoilPolar({self.name}).alpha must hold at least 2 strictly "
                                 "increasing angles [rad].")
        if alpha[0] > -math.pi + 1e-9 or alpha[-1] < math.pi - 1e-9:
            raise ParameterError(
                f"AirfoilPolar({self.name}).alpha spans [{math.degrees(alpha[0]):g}, "
                f"{math.degrees(alpha[-1]):g}] deg; it must span [-180, 180] deg (a full polar, "
                "as AeroDyn expects). Extend the table (e.g. with AirfoilPrep / Viterna).")
        object.__setattr__(self, "alpha", alpha)
        for name in ("cl", "cd", "cm"):
            values = _readonly(getattr(self, name), f"AirfoilPolar({self.name}).{name}")
            if values.shape != alpha.shape:
                raise ParameterError(f"AirfoilPolar({self.name}).{name} has {values.size} values; "
                                     f"expected {alpha.size} (one per angle of attack).")
            object.__setattr__(self, name, values)
        if self.interp_order not in (1, 3):
            raise ParameterError(f"AirfoilPolar({self.name}).interp_order must be 1 or 3; got "
                                 f"{self.interp_order!r}.")
        if self.ua is not None and not isinstance(self.ua, UACoefficients):
            raise ParameterError(f"AirfoilPolar({self.name}).ua must be UACoefficients or None; "
                                 f"got {type(self.ua).__name__}.")
        if not isinstance(self.constant_data, (bool, np.bool_)):
            raise ParameterError(f"AirfoilPolar({self.name}).constant_data must be True or False; "
                                 f"got {self.constant_data!r}.")
        object.__setattr__(self, "constant_data", bool(self.constant_data))

    def coefficients(self, alpha: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Linearly interpolated (cl, cd, cm) at ``alpha`` [rad] (wrapped to [-π, π])."""
        wrapped = np.mod(np.asarray(alpha, dtype=float) + math.pi, 2 * math.pi) - math.pi
        return (np.interp(wrapped, self.alpha, self.cl), np.interp(wrapped, self.alpha, self.cd),
                np.interp(wrapped, self.alpha, self.cm))


class _AirfoilDeck(_Deck):
    """The keyed part of an airfoil file: everything up to the first ``NumAlf`` line; with ``table = k`` the
    tables before the k-th (0-based, each from its ``Re`` line) read as blank lines, so that the k-th is read as
    the first with its own line numbers."""

    def __init__(self, path: Path, table: int = 0) -> None:
        self.table = table
        super().__init__(path)

    def _parse(self, lines: list[str], specs: tuple) -> None:  # type: ignore[override]
        if self.table:
            starts = [i for i, text in enumerate(lines) if _key_of(text) == "re"]
            lines = ["" if starts[0] <= i < starts[self.table] else text for i, text in enumerate(lines)]
        self.all_lines = lines
        self.numalf_index = next((i for i, text in enumerate(lines) if _key_of(text) == "numalf"),
                                 None)
        stop = len(lines) if self.numalf_index is None else self.numalf_index + 1
        super()._parse(lines[:stop], specs)


def _key_of(text: str) -> str | None:
    """Canonical key of a ``<value> <Key> ! ...`` line, or None."""
    stripped = text.strip()
    if not stripped or stripped.startswith(("!", "#", "=")):
        return None
    tokens = _TOKEN.findall(stripped)
    if stripped.startswith("-") and _real(tokens[0]) is None:         # a rule of dashes, not a negative value
        return None
    return _canon(tokens[1]) if len(tokens) > 1 else None


def _read_rows(deck: _AirfoilDeck, n_rows: int, n_cols: int) -> tuple[np.ndarray | None, list[int]]:
    """Read ``n_rows`` numeric rows after the NumAlf line (comments skipped)."""
    rows: list[list[float]] = []
    numbers: list[int] = []
    i = deck.numalf_index + 1
    lines = deck.all_lines
    while len(rows) < n_rows and i < len(lines):
        text, number = lines[i].strip(), i + 1
        i += 1
        if not text or text.startswith(("!", "#")):
            continue
        tokens = _TOKEN.findall(text)
        values = [_real(t) for t in tokens]
        if len(tokens) < n_cols or any(v is None for v in values[:n_cols]):
            bad = next((t for t, v in zip(tokens, values) if v is None), None)
            what = (f"expected a number, got {bad!r}" if bad is not None and len(tokens) >= n_cols
                    else f"expected at least {n_cols} numbers (the highest InCol_* column), got "
                    f"{len(tokens)}")
            deck.problems.append(f"{deck.path}, line {number}: {what} (row {len(rows) + 1} of the "
                                 "coefficient table). Fix the row, or NumAlf.")
            return None, numbers
        rows.append([float(v) for v in values[:n_cols]])  # type: ignore[arg-type]
        numbers.append(number)
    if len(rows) < n_rows:
        line = deck.numalf_index + 1
        deck.problems.append(f"{deck.path}, line {line}, key 'NumAlf': says {n_rows} rows, but "
                             f"only {len(rows)} follow. Make the count match the table.")
        return None, numbers
    return np.array(rows), numbers


def read_airfoil(path: str | Path, *, columns: tuple[int, int, int, int] = (1, 2, 3, 4),
                 user_prop: float | None = None) -> AirfoilPolar:
    """Read a coefficient table of an AeroDyn (AirfoilInfo) airfoil file: the first, or the one for ``user_prop``.

    Parameters
    ----------
    path : str or Path
        The airfoil file.
    columns : tuple of 4 int, optional
        1-based columns of AoA, Cl, Cd and Cm (AeroDyn's ``InCol_Alfa``,
        ``InCol_Cl``, ``InCol_Cd``, ``InCol_Cm``; Cm column 0 = none).
    user_prop : float, optional, keyword-only
        AeroDyn's airfoil input ``UserProp`` (``AFTabMod = 3``: the tables are interpolated in it; 0 without
        ServoDyn's airfoil control): the table whose ``UserProp`` equals it. A file of one table is read
        whatever its ``UserProp``; a value between two tables' (AeroDyn would blend them) is refused.

    Returns
    -------
    AirfoilPolar
        AoA in rad, coefficients as written; a single-row table (constant data)
        becomes a constant polar over [-π, π].  ``constant_data`` is AeroDyn's
        ``ConstData``; ``ua`` holds the unsteady-aero constants of the table as AeroDyn
        (UA_Mod 2/3) completes them (angles in rad), None for constant data.

    Raises
    ------
    OpenFASTFormatError
        If the file is missing, a key is missing or malformed, the table is short,
        a value is not a number, or the AoA does not strictly increase over
        [-180, 180] deg; also if an unsteady-aero value is one AeroDyn stops on
        (a non-number, ``"Default"`` where AeroDyn reads a number only, or UA lines
        after ``InclUAdata = False``); the message names the file and line.
    """
    path = Path(path)
    if not path.is_file():
        raise OpenFASTFormatError(f"airfoil file not found: tried '{path.absolute()}'. Check the "
                                  "AFNames entry of the AeroDyn file (paths are relative to it).")
    if len(columns) != 4 or any(not isinstance(c, int) or c < 0 for c in columns) or \
            min(columns[:3]) < 1:
        raise ParameterError(f"columns must be 4 column numbers (AoA, Cl, Cd >= 1; Cm >= 0); got "
                             f"{columns!r}.")
    deck = _AirfoilDeck(path, _table_for(path, user_prop))
    head = [t.strip() for t in deck.all_lines[:2]]
    for number, text in enumerate(head, start=1):
        if text and not text.startswith(("!", "#", "-", "=")) and _key_of(text) is not None:
            deck.problems.append(f"{path}, line {number}: mbsym reads the first two lines of an "
                                 "airfoil file as free text, but this one holds a key. Insert a "
                                 "comment line ('! ...') above it.")
    order = deck.value(_Key("InterpOrd", "", "float|default", default="default"))
    n_tables = deck.value(_Key("NumTabs", "", "int",
                               check=(lambda v: v >= 1, "must be at least 1")))
    reynolds = deck.value(_Key("Re", "", check=(lambda v: v >= 0, "must not be negative")))
    given = _read_ua_block(deck)
    n_alpha = deck.value(_Key("NumAlf", "", "int", check=(lambda v: v >= 1, "must be at least 1")))
    interp = 1 if order in ("default", None) else order
    if interp not in (1, 3, 1.0, 3.0):
        deck.problem(deck.line_of("InterpOrd"), "InterpOrd", f"must be 1, 3 or \"default\"; got "
                     f"{order:g}. Fix it.")
    data, numbers = (None, [])
    if deck.numalf_index is not None and isinstance(n_alpha, int) and n_alpha >= 1:
        data, numbers = _read_rows(deck, n_alpha, max(columns))
    constant, ua = True, None
    if data is not None:
        alpha, cl, cd = (data[:, c - 1] for c in columns[:3])
        cm = data[:, columns[3] - 1] if columns[3] else np.zeros(len(data))
        constant = _constant_data(np.column_stack([cl, cd, cm] if columns[3] else [cl, cd]))
        if len(data) == 1:  # constant data, as AeroDyn's ConstData
            alpha, cl, cd, cm = (np.array([-180.0, 180.0]), np.repeat(cl, 2), np.repeat(cd, 2),
                                 np.repeat(cm, 2))
        _check_alpha(deck, alpha, numbers)
        if not constant and not deck.problems:
            try:
                ua = ua_coefficients_from_polar(alpha * _DEG, cl, cd, cm, given, columns[3] > 0)
            except ParameterError as error:
                deck.problem(deck.numalf_index + 1, "NumAlf", f"{error}")
    deck.raise_problems()
    return AirfoilPolar(name=path.stem, alpha=alpha * _DEG, cl=cl, cd=cd, cm=cm,
                        reynolds=reynolds * 1e6, interp_order=int(interp), n_tables=n_tables,
                        source=str(path), ua=ua, constant_data=constant, table=deck.table)


def _table_for(path: Path, user_prop: float | None) -> int:
    """The 0-based table of ``path`` whose ``UserProp`` is ``user_prop`` (0: the first, also without a value or
    with one table)."""
    if user_prop is None:
        return 0
    values = []
    for number, text in enumerate(path.read_text(encoding="latin-1").splitlines(), start=1):
        if _key_of(text) == "userprop":
            values.append((number, _real(_TOKEN.findall(text.strip())[0])))
    if len(values) <= 1:
        return 0
    for k, (_, value) in enumerate(values):
        if value is not None and math.isclose(value, user_prop, rel_tol=0.0, abs_tol=1e-9):
            return k
    raise OpenFASTFormatError(
        f"{path}, line {values[0][0]}, key 'UserProp': AFTabMod = 3 interpolates this file's "
        f"{len(values)} tables in UserProp ({', '.join(f'{v:g}' for _, v in values if v is not None)}) at the "
        f"airfoil input {user_prop:g} (0 without airfoil control), which no table has: mbsym reads one table and "
        "does not blend them. Add a table for it, or set AFTabMod = 1 (the first table).")


def _read_ua_block(deck: _AirfoilDeck) -> dict[str, float | None]:
    """The UA constants of the first table as given (angles in rad); None = AeroDyn computes.

    AeroDyn (OpenFAST v5 ReadAFfile) reads them only if ``InclUAdata`` is True; a missing
    line means "compute".  ``"Default"`` selects the default only for the keys read with
    ParseVarWDefault: for the others AeroDyn does not consume the line and then stops at
    ``NumAlf``, so such a file is an error here too, as is any other non-number.
    """
    include = deck.value(_Key("InclUAdata", "", "bool", default=False))
    present = [k for k in UA_KEYS if _canon(k) in deck.entries]
    given: dict[str, float | None] = dict.fromkeys(UA_KEYS)
    if not include:
        if present and include is not None:
            entry = deck.entries[_canon(present[0])]
            deck.problem(entry.line, entry.key, "InclUAdata is False (or missing), so AeroDyn "
                         "does not read the unsteady-aero constants and stops here, expecting "
                         "NumAlf. Set InclUAdata to True, or remove the unsteady-aero lines.")
        return given
    for key in present:
        entry = deck.entries[_canon(key)]
        deck.used.add(_canon(key))
        if len(entry.values) != 1:
            deck.problem(entry.line, entry.key, f"expected one value, got {len(entry.values)} "
                         f"({', '.join(map(repr, entry.values))}). Fix the value in that line.")
            continue
        text = entry.values[0]
        if key in _KEYWORD_DEFAULT_KEYS and text.upper().startswith("DEFAULT"):
            continue
        value = _real(text)
        if value is None:
            if key in _KEYWORD_DEFAULT_KEYS:
                what = f'expected a number or "Default", got {text!r}. Fix the value in that line.'
            elif text.upper().startswith("DEFAULT"):
                what = (f'AeroDyn reads {key} as a number only ("Default" is accepted for '
                        f'{", ".join(sorted(_KEYWORD_DEFAULT_KEYS))}) and stops at this line. '
                        "Give a number, or delete the line to let AeroDyn compute the value.")
            else:
                what = f"expected a number, got {text!r}. Fix the value in that line."
            deck.problem(entry.line, entry.key, what)
            continue
        given[key] = value * _DEG if key in _ANGLE_KEYS else value
    return given


def _constant_data(coefficients: np.ndarray) -> bool:
    """AeroDyn's ``ConstData`` of a table (rows x coefficient columns).

    True for fewer than 3 rows, or if every row equals the next in every column by NWTC
    ``EqualRealNos`` in :data:`_CONST_DATA_REAL`: |a - b| <= max(|a + b|, 1) * 50 eps.
    """
    if coefficients.shape[0] < 3:
        return True
    real = _CONST_DATA_REAL
    values = coefficients.astype(real)
    a, b = values[:-1], values[1:]
    tol = real(100.0) * np.finfo(real).eps / real(2.0)
    return bool(np.all(np.abs(a - b) <= np.maximum(np.abs(a + b), real(1.0)) * tol))


def _check_alpha(deck: _AirfoilDeck, alpha: np.ndarray, numbers: list[int]) -> None:
    steps = np.diff(alpha)
    if np.any(steps <= 0):
        j = int(np.argmax(steps <= 0)) + 1
        deck.problems.append(f"{deck.path}, line {numbers[j]}: the angle of attack must strictly "
                             f"increase; {alpha[j]:g} deg follows {alpha[j - 1]:g} deg (line "
                             f"{numbers[j - 1]}). Fix the order.")
    elif alpha[0] > -180.0 + 1e-6 or alpha[-1] < 180.0 - 1e-6:
        deck.problems.append(f"{deck.path}, line {numbers[0]}: the table spans "
                             f"[{alpha[0]:g}, {alpha[-1]:g}] deg; it must span [-180, 180] deg "
                             "(a full polar, as AeroDyn expects). Extend the table.")
