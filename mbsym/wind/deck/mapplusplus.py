"""Read a MAP++ input file: line dictionary, node properties, line properties, solver options.

MAP++ (``CompMooring = 1``) describes a quasi-static mooring in four sections:

- ``LINE DICTIONARY``: ``LineType Diam MassDenInAir EA CB CIntDamp Ca Cdn Cdt`` (CB is the
  seabed friction coefficient);
- ``NODE PROPERTIES``: ``Node Type X Y Z M B FX FY FZ`` (Type ``fix``, ``vessel`` or
  ``connect``); a value may be ``depth`` (Z of an anchor: the sea floor) and a leading ``#``
  marks a value MAP++ solves for (an initial guess) — both kept as written in
  :class:`MapNode` (``free`` names the ``#`` columns);
- ``LINE PROPERTIES``: ``Line LineType UnstrLen NodeAnch NodeFair Flags``;
- ``SOLVER OPTIONS``: one option per line (``outer_tol 1e-5``, ``repeat 120 240`` …).

``repeat a b …`` copies every line and node rotated about z by each angle: see
:attr:`MapInput.repeat_angles` and :meth:`MapInput.repeated_positions`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._format import _real
from ._sections import _find, _raise, _split, _table

__all__ = ["MapInput", "MapLineType", "MapNode", "MapLine", "read_map"]


@dataclass(frozen=True)
class MapLineType:
    """A line type: diameter [m], mass per length in air [kg/m], EA [N], seabed friction
    coefficient CB [-], internal damping [Pa s], added-mass and drag coefficients [-]."""

    name: str
    diameter: float
    mass_per_length: float
    axial_stiffness: float
    seabed_friction: float
    internal_damping: float
    added_mass: float
    drag_normal: float
    drag_tangential: float
    line: int


@dataclass(frozen=True)
class MapNode:
    """A node: id, kind (``fix``, ``vessel``, ``connect``), position [m] (``z_at_seabed``: Z
    was ``depth``), point mass [kg], displaced volume [m³], applied force [N], and ``free``:
    the columns written with ``#`` (solved for by MAP++, the value an initial guess)."""

    id: int
    kind: str
    position: tuple[float, float, float]
    z_at_seabed: bool
    mass: float
    volume: float
    force: tuple[float, float, float]
    free: tuple[str, ...]
    line: int


@dataclass(frozen=True)
class MapLine:
    """A line: id, type name, unstretched length [m], anchor and fairlead node ids, flags."""

    id: int
    line_type: str
    length: float
    anchor: int
    fairlead: int
    flags: tuple[str, ...]
    line: int


@dataclass(frozen=True)
class MapInput:
    """A MAP++ input file (see the module docstring)."""

    line_types: dict[str, MapLineType]
    nodes: dict[int, MapNode]
    lines: dict[int, MapLine]
    options: tuple[tuple[str, tuple[str, ...]], ...]
    path: str
    option_lines: dict = field(default_factory=dict, compare=False)

    @property
    def repeat_angles(self) -> tuple[float, ...]:
        """Angles [rad] of the ``repeat`` option (copies of the whole system rotated about z)."""
        return tuple(math.radians(float(a)) for name, args in self.options if name.lower() == "repeat" for a in args)

    def node_position(self, node: int, water_depth: float) -> np.ndarray:
        """Position [m] of ``node``, ``depth`` resolved to −``water_depth``."""
        n = self.nodes[node]
        return np.array([n.position[0], n.position[1], -water_depth if n.z_at_seabed else n.position[2]])

    def repeated_positions(self, node: int, water_depth: float) -> list[np.ndarray]:
        """The node's position and its copies rotated by each repeat angle (MAP++'s ``repeat``)."""
        base = self.node_position(node, water_depth)
        out = [base]
        for a in self.repeat_angles:
            c, s = math.cos(a), math.sin(a)
            out.append(np.array([c * base[0] - s * base[1], s * base[0] + c * base[1], base[2]]))
        return out


def _value(token: str) -> tuple[float | None, bool]:
    """(number, free) of a node value: ``#-58`` → (−58, True); ``#`` alone → (0, True)."""
    free = token.startswith("#")
    text = token[1:] if free else token
    if free and not text:
        return 0.0, True
    return _real(text), free


def _nodes(p: Path, section, problems) -> dict:
    text_cols = ("type", "x", "y", "z", "m", "b", "fx", "fy", "fz")
    header, rows, lines = _table(p, section, text_cols, problems)
    out = {}
    for row, line in zip(rows, lines):
        low = {k.lower(): v for k, v in row.items()}
        ident = low.get("node")
        kind = str(low.get("type", "")).lower()
        if kind not in ("fix", "vessel", "connect"):
            problems.append(f"{p}, line {line}, column 'Type': {low.get('type')!r}; expected fix, vessel or connect.")
        values, free, seabed = {}, [], False
        for col in text_cols[1:]:
            token = str(low.get(col, "0"))
            if col == "z" and token.lower() == "depth":
                values[col], seabed = 0.0, True
                continue
            number, is_free = _value(token)
            if number is None:
                problems.append(f"{p}, line {line}, column '{col.upper()}': expected a number, '#<number>' or "
                                f"(Z only) 'depth'; got {token!r}.")
                number = 0.0
            values[col] = number
            if is_free:
                free.append(col.upper())
        if ident is None:
            continue
        out[int(ident)] = MapNode(int(ident), kind, (values["x"], values["y"], values["z"]), seabed, values["m"],
                                  values["b"], (values["fx"], values["fy"], values["fz"]), tuple(free), line)
    return out


def _types(p: Path, section, problems) -> dict:
    _, rows, lines = _table(p, section, ("linetype",), problems)
    cols = ("diam", "massdeninair", "ea", "cb", "cintdamp", "ca", "cdn", "cdt")
    out = {}
    for row, line in zip(rows, lines):
        low = {k.lower(): v for k, v in row.items()}
        missing = [c for c in cols if c not in low]
        if missing:
            problems.append(f"{p}, line {section.rows[0][0]}: the LINE DICTIONARY header lacks {missing}.")
            return {}
        out[low["linetype"]] = MapLineType(low["linetype"], *(low[c] for c in cols), line=line)
    return out


def _lines(p: Path, section, problems, types, nodes) -> dict:
    _, rows, lines = _table(p, section, ("linetype", "flags"), problems)
    out = {}
    for row, line in zip(rows, lines):
        low = {k.lower(): v for k, v in row.items()}
        values = [low.get(c) for c in ("line", "unstrlen", "nodeanch", "nodefair")]
        if None in values:
            continue
        if low.get("linetype") not in types:
            problems.append(f"{p}, line {line}, column 'LineType': {low.get('linetype')!r} is not in the LINE "
                            f"DICTIONARY ({sorted(types)}).")
        for node in values[2:]:
            if int(node) not in nodes:
                problems.append(f"{p}, line {line}: node {int(node)} is not in NODE PROPERTIES ({sorted(nodes)}).")
        flags = tuple(t for t in [low.get("flags", "")] + list(row["_extra"]) if t)
        out[int(values[0])] = MapLine(int(values[0]), low.get("linetype"), values[1], int(values[2]),
                                      int(values[3]), flags, line)
    return out


def read_map(path) -> MapInput:
    """Read a MAP++ input file (see the module docstring).

    Raises
    ------
    OpenFASTFormatError
        Missing file or section, malformed numbers, unknown node kinds, lines naming a type
        or node that does not exist; names the file, line and column.

    Examples
    --------
    >>> from mbsym.wind.deck.mapplusplus import read_map
    >>> mp = read_map("IEA-15-240-RWT-UMaineSemi_MAP.dat")  # doctest: +SKIP
    >>> mp.lines[1].length, [round(math.degrees(a)) for a in mp.repeat_angles]  # doctest: +SKIP
    (850.0, [120, 240])
    """
    p = Path(path)
    sections = _split(p, "MAP++ input file", title_lines=0)
    problems: list[str] = []
    found = {k: _find(sections, n) for k, n in (("types", "LINE DICTIONARY"), ("nodes", "NODE PROPERTIES"),
                                                ("lines", "LINE PROPERTIES"), ("options", "SOLVER OPTIONS"))}
    for key in ("types", "nodes", "lines"):
        if found[key] is None:
            problems.append(f"{p}: no '{key}' section (LINE DICTIONARY, NODE PROPERTIES, LINE PROPERTIES). Add it.")
    _raise(problems, p)
    types = _types(p, found["types"], problems)
    nodes = _nodes(p, found["nodes"], problems)
    lines = _lines(p, found["lines"], problems, types, nodes)
    options, option_lines = [], {}
    rows = found["options"].rows[2:] if found["options"] else []
    for number, tokens in rows:
        options.append((tokens[0], tuple(tokens[1:])))
        option_lines[tokens[0]] = number
    for name, args in options:
        if name.lower() == "repeat" and any(_real(a) is None for a in args):
            problems.append(f"{p}, line {option_lines[name]}, option 'repeat': expected angles in deg, got {args}.")
    _raise(problems, p)
    return MapInput(types, nodes, lines, tuple(options), str(p), option_lines)
