"""Positional reading of OpenFAST input files (private): the HydroDyn and SeaState layout.

HydroDyn and SeaState read their input files line by line, in a fixed order: a section
rule, then ``<value(s)> <Key> - description`` lines, multi-line vectors and matrices
without a key on their continuation lines (``AddF0``, ``AddCLin`` …), and tables
introduced by a row-count key, two header lines and exactly that many rows.  The
key-based :class:`~mbsym.wind.deck._format._Deck` cannot read such files, so
:class:`_Lines` walks them the same way, checking every key name and number and naming
the file, line and key of each problem (:class:`~mbsym.exceptions.OpenFASTFormatError`).

A structural problem (a key where another was expected, a missing line) stops the
reading at once, since every later line would be misread; malformed values are
collected and raised together by :meth:`_Lines.raise_problems`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ...exceptions import OpenFASTFormatError
from ._format import _BOOL, _TOKEN, _canon, _convert, _real


class _Lines:
    """A cursor over the lines of one positional OpenFAST file (see the module docstring)."""

    def __init__(self, path: Path, what: str) -> None:
        self.path = Path(path)
        if not self.path.is_file():
            raise OpenFASTFormatError(f"{what} not found: tried '{self.path.absolute()}'. Check the path.")
        self.what = what
        self.lines = self.path.read_text(encoding="utf-8", errors="replace").splitlines()
        self.i = 2  # lines 1-2: free-text header
        self.problems: list[str] = []
        self.line_of: dict[str, int] = {}

    # ------------------------------------------------------------------ errors
    def where(self, line: int, key: str) -> str:
        return f"{self.path}, line {line}, key '{key}'"

    def problem(self, line: int, key: str, text: str) -> None:
        self.problems.append(f"{self.where(line, key)}: {text}")

    def fail(self, line: int, key: str, text: str) -> OpenFASTFormatError:
        """A structural error: raise with the problems found so far."""
        self.problem(line, key, text)
        return OpenFASTFormatError("\n".join(self.problems) if len(self.problems) == 1 else
                                   f"{len(self.problems)} problems in {self.path}:\n  - "
                                   + "\n  - ".join(self.problems))

    def raise_problems(self) -> None:
        if len(self.problems) == 1:
            raise OpenFASTFormatError(self.problems[0])
        if self.problems:
            raise OpenFASTFormatError(f"{len(self.problems)} problems in {self.path}:\n  - "
                                      + "\n  - ".join(self.problems))

    # ------------------------------------------------------------------ lines
    def _next(self, key: str) -> tuple[int, list[str]]:
        """The next line that is not blank (number, tokens); raise at the end of the file."""
        while self.i < len(self.lines):
            self.i += 1
            tokens = _TOKEN.findall(self.lines[self.i - 1])
            if tokens:
                return self.i, tokens
        raise self.fail(len(self.lines), key, f"the file ends before '{key}'. Expected more lines in the "
                        f"{self.what}; compare the file with the documented layout.")

    def rule(self, name: str) -> None:
        """Skip a section rule (a line starting with ``---`` or ``===``) before section ``name``."""
        number, _ = self._next(name)
        text = self.lines[number - 1].strip()
        if not text.startswith(("--", "==")):
            raise self.fail(number, name, f"expected the section line of '{name}' (starting with '---'), got "
                            f"{text[:60]!r}. A line is missing or extra above; compare with the documented layout.")

    def skip(self, count: int, key: str) -> None:
        """Skip ``count`` lines (table headers), blank lines included, as OpenFAST does."""
        if self.i + count > len(self.lines):
            raise self.fail(len(self.lines), key, f"the file ends inside the header of '{key}'.")
        self.i += count

    def key(self, key: str, kind: str = "float", *, n: int = 1, check=None) -> Any:
        """Read ``<value(s)> <Key>`` and return the converted value (``n`` values for kind ``floats``)."""
        number, tokens = self._next(key)
        width = n if kind in ("floats", "strs") else 1
        if len(tokens) <= width or _canon(tokens[width].strip("\"'")) != _canon(key):
            found = tokens[width] if len(tokens) > width else "nothing"
            raise self.fail(number, key, f"expected '{key}' after {width} value(s) on this line, found {found!r}. "
                            "A line is missing, extra or out of order; compare with the documented layout.")
        self.line_of[key] = number
        values = [t.strip("\"'") for t in tokens[:width]]
        value, error = (tuple(values), None) if kind == "strs" else _convert(kind, values)
        if error is None and check is not None and value not in (None, "default") and not check[0](value):
            error = f"{check[1]}; got {' '.join(values)}"
        if error is not None:
            self.problem(number, key, f"{error}. Fix the value in that line.")
            return None
        return value

    def numbers(self, n: int, key: str) -> list[float]:
        """The first ``n`` numbers of the next line (a matrix row, a vector entry)."""
        number, tokens = self._next(key)
        self.line_of.setdefault(key, number)
        if len(tokens) < n:
            raise self.fail(number, key, f"expected {n} numbers, got {len(tokens)} ({' '.join(tokens)!r}).")
        out = [_real(t) for t in tokens[:n]]
        bad = [t for t, v in zip(tokens, out) if v is None]
        if bad:
            self.problem(number, key, f"expected {n} numbers, got {bad[0]!r}. Fix the value in that line.")
        return [0.0 if v is None else v for v in out]

    def table(self, count: int | None, key: str, n_min: int, n_max: int | None = None,
              strings: tuple[int, ...] = ()) -> tuple[list[str], list[list[Any]], list[int]]:
        """Two header lines, then ``count`` rows of ``n_min..n_max`` values.

        Returns (column names from the first header line, rows, line numbers). Columns in
        ``strings`` stay text; ``True``/``False`` read as 1/0 (HydroDyn's ``PropPot``).
        """
        if self.i + 2 > len(self.lines):
            raise self.fail(len(self.lines), key, "the file ends inside the header of this table.")
        header = [t.strip("\"'") for t in _TOKEN.findall(self.lines[self.i])]
        self.i += 2
        rows, lines = [], []
        for r in range(count or 0):
            number, tokens = self._next(key)
            n_max_ = n_max or n_min
            if not n_min <= len(tokens) or _real(tokens[0]) is None and 0 not in strings:
                raise self.fail(number, key, f"row {r + 1} of {count} of the table: expected {n_min}"
                                f"{'' if n_max_ == n_min else f'-{n_max_}'} values, got {len(tokens)} "
                                f"({self.lines[number - 1].strip()[:60]!r}). Check the count '{key}' and the rows.")
            row = []
            for j, token in enumerate(tokens[:n_max_]):
                value = _real(token)
                if j in strings and value is None:
                    row.append(token.strip("\"'"))  # text allowed here ("MCF", "DEFAULT")
                    continue
                if value is None and token.lower() in _BOOL:
                    value = float(_BOOL[token.lower()])
                if value is None:
                    self.problem(number, header[j] if j < len(header) else key,
                                 f"expected a number, got {token!r} (row {r + 1} of the '{key}' table). Fix it.")
                row.append(value)
            rows.append(row)
            lines.append(number)
        return header, rows, lines

    def outlist(self) -> list[str]:
        """Channel names up to ``END`` (quoted or bare, one or more per line)."""
        names: list[str] = []
        while self.i < len(self.lines):
            self.i += 1
            text = self.lines[self.i - 1].strip()
            if text[:3].upper() == "END":
                return names
            for token in _TOKEN.findall(text):
                if token == "-":
                    break
                names.append(token.strip("\"'"))
        raise self.fail(len(self.lines), "OutList", "the output channel list has no 'END' line. Add 'END' after "
                        "the last channel.")
