"""Sectioned mooring input files (private): MoorDyn and MAP++.

Both files are a title, then sections opened by a rule line naming them
(``---- LINE TYPES ----``); a table section has a header line of column names, a units
line and rows until the next rule.  :func:`_split` returns the sections with their line
numbers; :func:`_table` reads one as named columns, converting the numeric ones and
naming file, line and column of every problem.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ...exceptions import OpenFASTFormatError
from ._format import _real


@dataclass
class _Section:
    name: str            # upper-case words of the rule line
    line: int            # line number of the rule
    rows: list           # (line number, tokens) of every non-blank line after it


def _split(path: Path, what: str, stop: str | None = None, title_lines: int = 2) -> list[_Section]:
    """The sections of a sectioned file; reading ends after a line starting with ``stop`` (``END``).

    The first ``title_lines`` lines are free text (MoorDyn: 2, the first itself a rule; MAP++: 0).
    """
    if not path.is_file():
        raise OpenFASTFormatError(f"{what} not found: tried '{path.absolute()}'. Check the file name in the .fst.")
    sections: list[_Section] = []
    for number, text in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), start=1):
        stripped = text.strip()
        if number <= title_lines:
            continue  # title lines (MoorDyn's first is itself a rule)
        if stripped.startswith(("--", "==")):
            words = re.findall(r"[A-Za-z][A-Za-z0-9\-]*", stripped)
            sections.append(_Section(" ".join(words).upper(), number, []))
            continue
        if not stripped:
            continue
        if sections:
            sections[-1].rows.append((number, stripped.split()))
            if stop and stripped.upper().startswith(stop):
                break
    return sections


def _find(sections: list[_Section], *names: str) -> _Section | None:
    """The first section whose name contains one of ``names`` (upper case)."""
    return next((s for s in sections if any(n in s.name for n in names)), None)


def _table(path: Path, section: _Section, text_columns: tuple[str, ...],
           problems: list[str]) -> tuple[list[str], list[dict], list[int]]:
    """Rows of a table section as dicts column → value (numbers, or text for ``text_columns``)."""
    if len(section.rows) < 2:
        problems.append(f"{path}, line {section.line}: the '{section.name}' section needs a header line of column "
                        "names and a units line. Add them.")
        return [], [], []
    header = [h for h in section.rows[0][1]]
    out, lines = [], []
    for number, tokens in section.rows[2:]:
        if len(tokens) < len(header):
            # MoorDyn allows a trailing optional column (e.g. 'Outputs' or MAP++'s 'Flags') to be empty
            tokens = tokens + [""] * (len(header) - len(tokens))
        row = {}
        for name, token in zip(header, tokens):
            if name.lower() in text_columns:
                row[name] = token
                continue
            value = _real(token)
            if value is None:
                problems.append(f"{path}, line {number}, column '{name}': expected a number, got {token!r}. Fix it.")
            row[name] = value
        row["_extra"] = tokens[len(header):]
        out.append(row)
        lines.append(number)
    return header, out, lines


def _raise(problems: list[str], path: Path) -> None:
    if len(problems) == 1:
        raise OpenFASTFormatError(problems[0])
    if problems:
        raise OpenFASTFormatError(f"{len(problems)} problems in {path}:\n  - " + "\n  - ".join(problems))
