"""Read a MoorDyn input file: line types, points, lines, solver options, outputs.

MoorDyn (v2 layout, also v1's ``CONNECTION PROPERTIES``/``NODE PROPERTIES``) has sections
opened by rule lines; each table has a header of column names and a units line.  Read here:
``LINE TYPES`` (``Name Diam MassDen EA BA/-zeta [EI] Cd Ca CdAx CaAx``), ``POINTS``
(``ID Type X Y Z M V CdA CA``; Type ``Fixed``/``Vessel``/``Coupled``/``Free``, ``Body#``,
``Turbine#``), ``LINES`` (``ID LineType AttachA AttachB UnstrLen NumSegs Outputs``), the
options (``<value> <key>`` lines, also in file order with their line numbers in
:attr:`MoorDynInput.option_entries`; lines MoorDyn cannot read are refused here, what each option
does is :mod:`.moordyn_audit`'s) and the output channels up to ``END``. EA, BA/-zeta and EI stay
text when they are not numbers (MoorDyn's visco-elastic ``a|b`` or curve files); line-type columns
after the tenth (``Cl dF cF``, by position as MoorDyn reads them) are kept in
:attr:`MooringLineType.extra_columns`.  Sections mbsym
has no reader for (rods, bodies, failures, external loads) are kept by name in
:attr:`MoorDynInput.other_sections` with their row count, so the user of the data can
refuse them.  Numbers are SI as in the file (MoorDyn's own units).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ._format import _real
from ._sections import _find, _raise, _split, _table
from .moordyn_audit import option_format_problems

__all__ = ["MoorDynInput", "MooringLineType", "MooringPoint", "MooringLine", "read_moordyn"]


@dataclass(frozen=True)
class MooringLineType:
    """A line type: diameter [m], mass per length in air [kg/m], axial stiffness EA [N],
    internal damping (``BA`` [N s], or −ζ when negative), bending stiffness EI [N m²],
    transverse/axial drag and added-mass coefficients [-]; EA, BA, EI are text when the file gives
    a curve file or ``|``-separated values; ``extra_columns``: the columns after the tenth
    (``Cl``, ``dF``, ``cF``: vortex-induced vibration)."""

    name: str
    diameter: float
    mass_per_length: float
    axial_stiffness: float
    axial_damping: float
    bending_stiffness: float
    drag_transverse: float
    added_mass_transverse: float
    drag_axial: float
    added_mass_axial: float
    line: int
    extra_columns: tuple = ()


@dataclass(frozen=True)
class MooringPoint:
    """A point: id, attachment kind (``fixed``, ``vessel``/``coupled``, ``free``, ``body#``, ``turbine#``),
    position [m] (relative to the platform reference point for vessel points; z is ``"seabed"`` when
    the file says so: MoorDyn puts the point on its seabed), mass [kg],
    volume [m³], drag area CdA [m²] and added-mass coefficient [-]."""

    id: int
    kind: str
    position: tuple[float, float, float]
    mass: float
    volume: float
    drag_area: float
    added_mass: float
    line: int


@dataclass(frozen=True)
class MooringLine:
    """A line: id, type name, the point ids of its ends A and B, unstretched length [m],
    number of segments, output flags."""

    id: int
    line_type: str
    end_a: int
    end_b: int
    length: float
    n_segments: int
    outputs: str
    line: int


@dataclass(frozen=True)
class MoorDynInput:
    """A MoorDyn input file (see the module docstring)."""

    line_types: dict[str, MooringLineType]
    points: dict[int, MooringPoint]
    lines: dict[int, MooringLine]
    options: dict[str, float | str]
    outputs: tuple[str, ...]
    other_sections: dict[str, int]
    path: str
    option_lines: dict = field(default_factory=dict, compare=False)
    option_entries: tuple = field(default=(), compare=False)

    def fairlead(self, line: int) -> MooringPoint:
        """The vessel end of line ``line`` (the point attached to the platform)."""
        entry = self.lines[line]
        ends = [self.points[entry.end_a], self.points[entry.end_b]]
        return next(p for p in ends if p.kind in ("vessel", "coupled"))

    def anchor(self, line: int) -> MooringPoint:
        """The fixed end of line ``line``."""
        entry = self.lines[line]
        ends = [self.points[entry.end_a], self.points[entry.end_b]]
        return next(p for p in ends if p.kind in ("fixed", "anchor"))


_TYPE_COLUMNS = {"name": "name", "diam": "diameter", "massden": "mass_per_length", "ea": "axial_stiffness",
                 "ba/-zeta": "axial_damping", "ei": "bending_stiffness", "cd": "drag_transverse",
                 "ca": "added_mass_transverse", "cdax": "drag_axial", "caax": "added_mass_axial"}
_POINT_KINDS = ("fixed", "vessel", "coupled", "free", "anchor", "connect")


def _get(row: dict, *names: str, default=None):
    low = {k.lower(): v for k, v in row.items()}
    return next((low[n] for n in names if n in low), default)


def _types(p: Path, section, problems) -> dict:
    header, rows, lines = _table(p, section, ("name", "ea", "ba/-zeta", "ei"), problems)
    need = {"name", "diam", "massden", "ea", "cd", "ca", "cdax", "caax"} - {h.lower() for h in header}
    if need and header:
        problems.append(f"{p}, line {section.rows[0][0]}: the LINE TYPES header lacks {sorted(need)}; expected "
                        "'Name Diam MassDen EA BA/-zeta EI Cd Ca CdAx CaAx'.")
        return {}
    out = {}
    for row, line in zip(rows, lines):
        values = {attr: _get(row, col, default=0.0) for col, attr in _TYPE_COLUMNS.items()}
        for attr in ("axial_stiffness", "axial_damping", "bending_stiffness"):
            text = values[attr]
            if isinstance(text, str):
                values[attr] = text if _real(text) is None else _real(text)
        positional = [row[h] for h in header] + [t if _real(t) is None else _real(t) for t in row["_extra"]]
        extra = positional[10:]                       # MoorDyn reads the columns by position
        if len(extra) not in (0, 1, 3) or any(not isinstance(v, float) for v in extra):
            problems.append(f"{p}, line {line}: a line type has 10, 11 or 13 columns ('Name Diam MassDen EA "
                            f"BA/-zeta EI Cd Ca CdAx CaAx [Cl [dF cF]]'), all numbers after Name; got "
                            f"{10 + len(extra)}. Fix the row.")
        out[row[header[0]]] = MooringLineType(**values, line=line, extra_columns=tuple(extra))
    return out


def _kind(p: Path, token: str, line: int, problems) -> str:
    low = token.lower()
    if low in _POINT_KINDS or low.startswith(("body", "turbine")):
        return {"connect": "free", "anchor": "fixed"}.get(low, low)
    problems.append(f"{p}, line {line}, column 'Type': unknown point type {token!r}; expected Fixed, Vessel, "
                    "Coupled, Free, Body# or Turbine#.")
    return low


def _seabed_or_number(p: Path, token: str, line: int, problems) -> float | str | None:
    """Z of a point: a number, or ``"seabed"`` when it names the seabed (MoorDyn: any of SEABED, GROUND,
    FLOOR in it, upper-cased; the depth then comes from the depth option or the glue code)."""
    if _real(token) is not None:
        return _real(token)
    if any(word in token.upper() for word in ("SEABED", "GROUND", "FLOOR")):
        return "seabed"
    problems.append(f"{p}, line {line}, column 'Z': expected a number or 'seabed', got {token!r}. Fix it.")
    return None


def _points(p: Path, section, problems) -> dict:
    header, rows, lines = _table(p, section, ("type", "attachment", "z"), problems)
    out = {}
    for row, line in zip(rows, lines):
        ident = _get(row, "id", "node", "name")
        kind = _kind(p, _get(row, "type", "attachment", default=""), line, problems)
        pos = tuple(_get(row, a) for a in ("x", "y", "z"))
        if isinstance(pos[2], str):
            pos = pos[:2] + (_seabed_or_number(p, pos[2], line, problems),)
        if ident is None or None in pos:
            continue
        out[int(ident)] = MooringPoint(int(ident), kind, pos, _get(row, "m", default=0.0) or 0.0,
                                       _get(row, "v", default=0.0) or 0.0, _get(row, "cda", default=0.0) or 0.0,
                                       _get(row, "ca", default=0.0) or 0.0, line)
    return out


def _lines(p: Path, section, problems, types: dict, points: dict) -> dict:
    header, rows, lines = _table(p, section, ("linetype", "outputs", "flags"), problems)
    out = {}
    for row, line in zip(rows, lines):
        values = [_get(row, "id", "line"), _get(row, "attacha", "nodea", "anchor"),
                  _get(row, "attachb", "nodeb", "fairlead"), _get(row, "unstrlen"), _get(row, "numsegs")]
        if None in values:
            continue
        kind = _get(row, "linetype", default="")
        if kind not in types:
            problems.append(f"{p}, line {line}, column 'LineType': {kind!r} is not a line type of the LINE TYPES "
                            f"table ({sorted(types)}).")
        for end in values[1:3]:
            if int(end) not in points:
                problems.append(f"{p}, line {line}: attachment point {int(end)} is not in the POINTS table "
                                f"({sorted(points)}).")
        out[int(values[0])] = MooringLine(int(values[0]), kind, int(values[1]), int(values[2]), values[3],
                                          int(values[4]), _get(row, "outputs", default="-"), line)
    return out


def _options(section) -> tuple[dict, dict]:
    out, lines = {}, {}
    for number, tokens in section.rows if section else []:
        if len(tokens) >= 2:
            value = _real(tokens[0])
            out[tokens[1]] = tokens[0] if value is None else value
            lines[tokens[1]] = number
    return out, lines


def read_moordyn(path) -> MoorDynInput:
    """Read a MoorDyn input file (see the module docstring).

    Raises
    ------
    OpenFASTFormatError
        Missing file or section, malformed numbers, unknown point types, lines naming a
        type or point that does not exist, option lines MoorDyn cannot read; names the file,
        line and column.

    Examples
    --------
    >>> from mbsym.wind.deck.moordyn import read_moordyn
    >>> md = read_moordyn("IEA-15-240-RWT-UMaineSemi_MoorDyn.dat")  # doctest: +SKIP
    >>> md.lines[1].length, md.fairlead(1).position  # doctest: +SKIP
    (850.0, (-58.0, 0.0, -14.0))
    """
    p = Path(path)
    sections = _split(p, "MoorDyn input file", stop="END")
    problems: list[str] = []
    found = {key: _find(sections, *names) for key, names in (
        ("types", ("LINE TYPES", "LINE DICTIONARY")), ("points", ("POINTS", "CONNECTION", "NODE PROPERTIES")),
        ("lines", ("LINES", "LINE PROPERTIES")), ("options", ("OPTIONS",)), ("outputs", ("OUTPUT",)))}
    for key in ("types", "points", "lines"):
        if found[key] is None:
            problems.append(f"{p}: no '{key.upper()}' section (a rule line such as '---- LINE TYPES ----' followed "
                            "by the table). Add it.")
    _raise(problems, p)
    types = _types(p, found["types"], problems)
    points = _points(p, found["points"], problems)
    lines = _lines(p, found["lines"], problems, types, points)
    options, option_lines = _options(found["options"])
    rows = found["options"].rows if found["options"] else []
    problems += option_format_problems(p, rows)
    entries = tuple((n, words[1], words[0]) for n, words in rows if len(words) >= 2)
    outputs = tuple(t for _, tokens in (found["outputs"].rows if found["outputs"] else [])
                    for t in tokens if t.upper() != "END")
    known = {id(s) for s in found.values() if s is not None}
    other = {s.name: len(s.rows) for s in sections if id(s) not in known and s.rows}
    _raise(problems, p)
    return MoorDynInput(types, points, lines, options, outputs, other, str(p), option_lines, entries)
