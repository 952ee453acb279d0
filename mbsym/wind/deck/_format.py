"""Format-level reading of OpenFAST input files (private).

An OpenFAST input file is a sequence of lines ``<value(s)> <Key> [- description]``
(the first two lines are free text), ``---``/``===`` section rules, tables (a
header of column names, a units line, numeric rows) and ``OutList`` blocks ending
in ``END``.  :class:`_Deck` tokenizes one file into keyed entries (keys are
case-insensitive; ``PreCone(1)`` and ``PreCone1`` are the same key), tables and
OutLists, converts values (numbers, integers, booleans, strings, ``"default"``)
and collects every problem with file, line and key, to raise them together as one
:class:`~mbsym.exceptions.OpenFASTFormatError`.

Which keys a file has, and what they mean, is not known here: callers describe
them with :class:`_Key` and :class:`_TableSpec` (see :mod:`mbsym.wind.deck.openfast`).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ...exceptions import OpenFASTFormatError

_REQ = object()  # "no default: the key is required"
_Check = tuple[Callable[[Any], bool], str]


@dataclass(frozen=True)
class _Key:
    """One key: OpenFAST name, attribute path, value kind, scale, default, check."""

    key: str
    attr: str
    kind: str = "float"
    scale: float | None = None
    default: Any = _REQ
    check: _Check | None = None



@dataclass(frozen=True)
class _TableSpec:
    """A table: row-count key, header names that start it, column → attribute (scale)."""

    name: str
    count_key: str
    starts: tuple[str, ...]  # lower-case first header names; () = header right after the
    # count key and columns read by position
    columns: tuple[tuple[str, str, float | None, bool], ...]  # name, attribute, scale, required



_TOKEN = re.compile(r'"[^"]*"|\'[^\']*\'|[^\s,]+')
_KEYNAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\(\d+\))?$")
_REAL = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")
_INT = re.compile(r"^[+-]?\d+$")
_BOOL = {"true": True, "t": True, ".true.": True, "false": False, "f": False, ".false.": False}


def _canon(key: str) -> str:
    return key.replace("(", "").replace(")", "").lower()


def _is_key(token: str) -> bool:
    low = token.lower()
    return bool(_KEYNAME.match(token)) and low not in _BOOL and low != "default"


def _real(text: str) -> float | None:
    if not _REAL.match(text):
        return None
    value = float(text.replace("d", "e").replace("D", "E"))
    return value if math.isfinite(value) else None


def _convert(kind: str, values: list[str]) -> tuple[Any, str | None]:
    """Convert raw value tokens; return (value, error text or None)."""
    if kind == "floats":
        out = [_real(v) for v in values]
        bad = [v for v, x in zip(values, out) if x is None]
        return (tuple(out), None) if not bad else (None, f"expected numbers, got {bad[0]!r}")
    if len(values) != 1:
        return None, f"expected one value, got {len(values)} ({', '.join(map(repr, values))})"
    text = values[0]
    if kind == "str":
        return text, None
    if kind == "bool":
        low = text.lower()
        return (_BOOL[low], None) if low in _BOOL else (None, f"expected True or False, got {text!r}")
    if kind == "int":
        return (int(text), None) if _INT.match(text) else (None, f"expected an integer, got {text!r}")
    if kind == "float|default" and text.lower() == "default":
        return "default", None
    value = _real(text)
    return (value, None) if value is not None else (None, f"expected a number, got {text!r}")


@dataclass
class _Entry:
    key: str
    values: list[str]
    line: int


@dataclass
class _Table:
    header_line: int
    columns: list[str]
    rows: list[list[float | None]] = field(default_factory=list)
    lines: list[int] = field(default_factory=list)


class _Deck:
    """One OpenFAST input file, parsed into keyed entries, tables and OutLists."""

    def __init__(self, path: Path, tables: tuple[_TableSpec, ...] = ()) -> None:
        self.path = path
        self.entries: dict[str, _Entry] = {}
        self.tables: dict[str, _Table] = {}
        self.outlists: list[list[str]] = []
        self.problems: list[str] = []
        self.used: set[str] = set()
        self.last_line = 2
        self._parse(path.read_text(encoding="latin-1").splitlines(), tables)

    def where(self, line: int, key: str) -> str:
        return f"{self.path}, line {line}, key '{key}'"

    def problem(self, line: int, key: str, text: str) -> None:
        self.problems.append(f"{self.where(line, key)}: {text}")

    def raise_problems(self) -> None:
        if len(self.problems) == 1:
            raise OpenFASTFormatError(self.problems[0])
        if self.problems:
            raise OpenFASTFormatError(f"{len(self.problems)} problems in {self.path}:\n  - "
                                      + "\n  - ".join(self.problems))

    def _parse(self, lines: list[str], specs: tuple[_TableSpec, ...]) -> None:
        i, outlist, header_next = 2, None, None  # lines 1-2: free-text header
        while i < len(lines):
            number, text = i + 1, lines[i].strip()
            i += 1
            if not text or text.startswith(("!", "#")):
                continue
            if outlist is not None:
                if text[:3].upper() == "END":
                    outlist = None
                    continue
                for token in _TOKEN.findall(text):
                    if token == "-":
                        break
                    outlist.append(token.strip("\"'"))
                continue
            if text.startswith(("--", "==")):
                continue
            tokens = _TOKEN.findall(text)
            if tokens[0].lower() == "outlist":
                outlist = []
                self.outlists.append(outlist)
                continue
            spec = header_next or next((s for s in specs if tokens[0].lower() in s.starts
                                        and s.name not in self.tables), None)
            if spec is not None:
                header_next = None
                i = self._read_table(lines, i, number, tokens, spec)
                continue
            entry = self._add_entry(number, tokens, text)
            header_next = next((s for s in specs if not s.starts and entry is not None
                                and _canon(s.count_key) == _canon(entry.key)
                                and _convert("int", entry.values)[0] not in (None, 0)), None)

    def _add_entry(self, number: int, tokens: list[str], text: str) -> _Entry | None:
        j = next((j for j in range(1, len(tokens)) if _is_key(tokens[j])), None)
        if j is None:
            self.problems.append(
                f"{self.path}, line {number}: no key name found in {text!r}; expected "
                "'<value>  <Key>  - description' (or a table row: check the row-count key). "
                "Fix or remove that line.")
            return None
        entry = _Entry(tokens[j], [t.strip("\"'") for t in tokens[:j]], number)
        previous = self.entries.get(_canon(entry.key))
        if previous is not None:
            self.problem(number, entry.key, f"duplicate key (also on line {previous.line}). "
                         "Remove one of the two lines.")
        else:
            self.entries[_canon(entry.key)] = entry
        return entry

    def _read_table(self, lines: list[str], i: int, header: int, names: list[str],
                    spec: _TableSpec) -> int:
        table = _Table(header, [n.strip("\"'") for n in names])
        self.tables[spec.name] = table
        if i >= len(lines) or _real((_TOKEN.findall(lines[i]) or ["x"])[0]) is not None:
            self.problem(header + 1, table.columns[0], "expected a units line (e.g. '(-) (kg/m) "
                         f"...') after the column names of the {spec.name} table. Add it.")
        else:
            i += 1
        count = self.entries.get(_canon(spec.count_key))
        n_rows = _convert("int", count.values)[0] if count else None
        widths = []
        while i < len(lines):
            tokens = _TOKEN.findall(lines[i])
            numeric = bool(tokens) and all(_real(t) is not None for t in tokens)
            if n_rows is not None and len(table.rows) >= n_rows and not numeric:
                break  # all rows read; surplus numeric lines are counted below
            if tokens and (lines[i].strip().startswith(("--", "==")) or (
                    _real(tokens[0]) is None and (n_rows is None or any(map(_is_key, tokens))))):
                break
            i += 1
            if not tokens:
                continue
            row = [_real(t) for t in tokens]
            for col, token, value in zip(table.columns, tokens, row):
                if value is None:
                    self.problem(i, col, f"expected a number, got {token!r} (row "
                                 f"{len(table.rows) + 1} of the {spec.name} table). Fix it.")
            widths.append((i, len(tokens)))
            table.rows.append(row)
            table.lines.append(i)
        bad = [(line, n) for line, n in widths if n != len(table.columns)]
        if bad:
            self.problem(bad[0][0], table.columns[-1], f"row has {bad[0][1]} values but the "
                         f"header on line {header} names {len(table.columns)} columns "
                         f"({len(bad)} such rows). Make the header and the rows agree.")
        if count is not None and n_rows is not None and len(table.rows) != n_rows:
            self.problem(count.line, count.key, f"says {n_rows} rows, but the {spec.name} "
                         f"table (header on line {header}) has {len(table.rows)}. "
                         "Make the count match the table.")
            del table.rows[n_rows:], table.lines[n_rows:]
        return i

    def value(self, spec: _Key, key: str | None = None) -> Any:
        """Return the converted (deck-unit) value of a key, or its default; record problems."""
        key = key or spec.key
        entry = self.entries.get(_canon(key))
        if entry is None:
            if spec.default is _REQ:
                self.problem(self.last_line + 1, key, "missing. Expected a line "
                             f"'<value>  {key}  - description' after line {self.last_line}. Add it.")
                return None
            return spec.default
        self.used.add(_canon(key))
        self.last_line = entry.line
        value, error = _convert(spec.kind, entry.values)
        if error is None and spec.check is not None and value not in (None, "default") \
                and not spec.check[0](value):
            error = f"{spec.check[1]}; got {' '.join(entry.values)}"
        if error is not None:
            self.problem(entry.line, entry.key, f"{error}. Fix the value in that line.")
            return None
        return value

    def extra(self) -> dict[str, str]:
        """Raw text of every key not consumed by :meth:`value`."""
        return {e.key: " ".join(e.values) for c, e in self.entries.items() if c not in self.used}

    def line_of(self, key: str) -> int:
        entry = self.entries.get(_canon(key))
        return entry.line if entry else self.last_line


def _read_keys(deck: _Deck, keys: tuple[_Key, ...], n_blades: int = 3) -> dict[str, Any]:
    """Read ``keys`` into a nested dict keyed by attribute paths (SI units)."""
    out: dict[str, Any] = {}
    for spec in keys:
        names = [spec.key.replace("*", str(b)) for b in range(1, n_blades + 1)] \
            if "(*)" in spec.key else [spec.key]
        for b, name in enumerate(names):
            value = deck.value(spec, name)
            if value is not None and spec.scale is not None and value != "default":
                value = value * spec.scale
            _assign(out, f"{spec.attr}[{b}]" if "(*)" in spec.key else spec.attr, value)
    return out


def _assign(store: dict[str, Any], path: str, value: Any) -> None:
    head, _, rest = path.partition(".")
    if rest:
        _assign(store.setdefault(head, {}), rest, value)
        return
    name, *indices = head.replace("]", "").split("[")
    if not indices:
        store[name] = value
        return
    target = store.setdefault(name, [])
    for depth, index in enumerate(map(int, indices)):
        while len(target) <= index:
            target.append([] if depth < len(indices) - 1 else None)
        if depth < len(indices) - 1:
            target = target[index]
        else:
            target[index] = value


def _read_table_columns(deck: _Deck, spec: _TableSpec, out: dict[str, Any]) -> None:
    table = deck.tables.get(spec.name)
    if table is None:
        deck.problem(deck.line_of(spec.count_key), spec.count_key, f"the {spec.name} table "
                     f"is missing (expected a header line starting with '{spec.columns[0][0]}', "
                     "a units line and the rows after it). Add it.")
        return
    lowered = [c.lower() for c in table.columns]
    if not spec.starts:  # read by position, as ElastoDyn does (header names vary)
        lowered[:len(spec.columns)] = [c[0].lower() for c in spec.columns][:len(lowered)]
    width = len(lowered)
    data = np.array([r[:width] + [None] * (width - len(r)) for r in table.rows],
                    dtype=float).reshape(len(table.rows), width)
    known = set()
    for col, attr, scale, required in spec.columns:
        if col.lower() not in lowered:
            if required:
                deck.problem(table.header_line, col, f"column missing from the {spec.name} "
                             f"table header {table.columns}. Add the column.")
            out.setdefault(attr, None)
            continue
        known.add(col.lower())
        values = data[:, lowered.index(col.lower())]
        out[attr] = values * scale if scale else values
    out["extra_columns"] = {table.columns[j]: data[:, j] for j, c in enumerate(lowered)
                            if c not in known}


def _resolve(deck: _Deck, key: str, what: str) -> Path:
    """Path of a file named by ``key`` (relative to the deck's directory); raise if absent."""
    entry = deck.entries[_canon(key)]
    name = entry.values[0]
    candidates = [Path(name), Path(name.replace("\\", "/"))]
    tried = [c if c.is_absolute() else deck.path.parent / c for c in candidates]
    for path in tried:
        if path.is_file():
            return path
    raise OpenFASTFormatError(
        f"{deck.where(entry.line, entry.key)}: {what} not found: tried '{tried[0]}'. Fix the "
        f"file name in that line (relative paths start at the directory of {deck.path.name}).")

