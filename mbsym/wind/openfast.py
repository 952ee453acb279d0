"""Read OpenFAST decks (main ``.fst``, ElastoDyn, tower and blade files).

:func:`read_openfast` returns :class:`~mbsym.wind.parameters.TurbineParameters`.
This is the only module that spells OpenFAST keys; :data:`KEY_MAP` documents
which attribute each key becomes (angles are converted from deg to rad, RotSpeed
from rpm to rad/s, percentages to fractions).

Files are read **by key**, not by line position: a line ``<value(s)> <Key> [-
description]`` defines ``Key`` (case-insensitive; ``PreCone(1)`` and
``PreCone1`` are the same key).  So both the OpenFAST v5 layout and older ones
are read: keys that only v5 has (PitchDOF, PtfmRefxt/yt, PBrIner, BlPIner,
HubIner_Teeter, PtfmXYIner/YZIner/XZIner, CompSeaSt, CompSoil, ...) default to
0/False, Gravity may sit in the ElastoDyn file (pre-v3 layouts), and tables are
read by their header names (the blade table with or without PitchAxis).  Keys
not listed in :data:`KEY_MAP` are kept, with their raw text, in the ``extra``
dicts.  As in ElastoDyn, the first two lines of each file are free text.

Every problem raises :class:`~mbsym.exceptions.OpenFASTFormatError`, naming the
file, the line and the key; all problems of one file are reported together.
The ElastoDyn input checks are applied (fractions 0 → 1 strictly increasing,
mass and stiffness > 0, damping in [0, 100] %, mode-shape coefficients summing
to 1 within 0.0015, angle ranges, ...).  openfast-io was evaluated and not used:
it reads by line position (an older layout or an extra PitchAxis column shifts
every value silently), returns bad numbers as strings and any non-"true" flag as
False, and reports no line numbers.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..exceptions import OpenFASTFormatError
from .parameters import (
    DOF_NAMES, BladeParameters, InitialConditions, SimulationSettings, TowerParameters,
    TurbineParameters,
)

__all__ = ["read_openfast", "KEY_MAP"]

_REQ = object()  # "no default: the key is required"
_DEG, _RPM, _PCT = math.pi / 180.0, math.pi / 30.0, 0.01
_POS = (lambda v: v > 0, "must be greater than 0")
_NONNEG = (lambda v: v >= 0, "must not be negative")
_PERCENT = (lambda v: 0 <= v <= 100, "must be between 0 and 100 % (inclusive)")
_ANG180 = (lambda v: -180 < v <= 180, "must be in (-180, 180] degrees")
_ANG360 = (lambda v: 0 <= v < 360, "must be in [0, 360) degrees")
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


_k = _Key
_ONE_TO_3 = (lambda v: v in (1, 2, 3), "must be 1, 2 or 3")
_AT_LEAST_1 = (lambda v: v >= 1, "must be at least 1")
_BELOW_90 = (lambda v: abs(v) < 90, "must be in (-90, 90) degrees")

# ----------------------------------------------------------------------------- mappings
_FST_KEYS = (
    _k("TMax", "total_time", check=_NONNEG), _k("DT", "time_step", check=_POS),
    _k("CompElast", "structural_model", "int"), _k("CompInflow", "inflow_model", "int"),
    _k("CompAero", "aerodynamics_model", "int"), _k("CompServo", "servo_model", "int"),
    _k("CompSeaSt", "sea_state_model", "int", default=0),
    _k("CompHydro", "hydrodynamics_model", "int"), _k("CompSub", "substructure_model", "int"),
    _k("CompMooring", "mooring_model", "int"), _k("CompIce", "ice_model", "int"),
    _k("CompSoil", "soil_model", "int", default=0),
    _k("Gravity", "gravity", default=None, check=_NONNEG),
    _k("AirDens", "air_density", default=None, check=_NONNEG),
    _k("WtrDens", "water_density", default=None, check=_NONNEG),
    _k("WtrDpth", "water_depth", default=None), _k("MSL2SWL", "msl_to_swl", default=None),
    _k("EDFile", "elastodyn_file", "str"),
    _k("DT_Out", "output_time_step", "float|default", check=_POS),
    _k("TStart", "output_start_time", default=0.0, check=_NONNEG),
    _k("Linearize", "linearize", "bool", default=False),
    _k("LinTimes", "linearization_times", "floats", default=()),
)
_IC = "initial_conditions."
_ED_KEYS = (
    _k("Method", "integration_method", "int",
       check=(lambda v: v in (1, 2, 3), "must be 1 (RK4), 2 (AB4) or 3 (ABM4)")),
    _k("DT", "structural_time_step", "float|default", check=_POS),
    *(_k(n, f"dofs.{n}", "bool", default=False if n == "PitchDOF" else _REQ) for n in DOF_NAMES),
    _k("OoPDefl", _IC + "blade_oop_tip_deflection"), _k("IPDefl", _IC + "blade_ip_tip_deflection"),
    _k("BlPitch(*)", _IC + "blade_pitch", scale=_DEG, check=_ANG180),
    _k("TeetDefl", _IC + "teeter_angle", scale=_DEG, check=_ANG180),
    _k("Azimuth", _IC + "azimuth", scale=_DEG, check=_ANG360),
    _k("RotSpeed", _IC + "rotor_speed", scale=_RPM, check=_NONNEG),
    _k("NacYaw", _IC + "nacelle_yaw", scale=_DEG, check=_ANG180),
    _k("TTDspFA", _IC + "tower_top_fa_displacement"),
    _k("TTDspSS", _IC + "tower_top_ss_displacement"),
    _k("PtfmSurge", _IC + "platform_surge"), _k("PtfmSway", _IC + "platform_sway"),
    _k("PtfmHeave", _IC + "platform_heave"), _k("PtfmRoll", _IC + "platform_roll", scale=_DEG),
    _k("PtfmPitch", _IC + "platform_pitch", scale=_DEG),
    _k("PtfmYaw", _IC + "platform_yaw", scale=_DEG),
    _k("NumBl", "number_of_blades", "int", check=_ONE_TO_3),
    _k("TipRad", "tip_radius", check=_NONNEG), _k("HubRad", "hub_radius", check=_NONNEG),
    _k("PreCone(*)", "precone", scale=_DEG, check=_BELOW_90),
    _k("HubCM", "hub_cm"), _k("UndSling", "undersling"),
    _k("Delta3", "delta3", scale=_DEG, check=_BELOW_90),
    _k("AzimB1Up", "azimuth_blade1_up", scale=_DEG, check=_ANG360), _k("OverHang", "overhang"),
    _k("ShftTilt", "shaft_tilt", scale=_DEG,
       check=(lambda v: abs(v) <= 90, "must be in [-90, 90] degrees")),
    _k("NacCMxn", "nacelle_cm[0]"), _k("NacCMyn", "nacelle_cm[1]"), _k("NacCMzn", "nacelle_cm[2]"),
    _k("Twr2Shft", "twr2shft", check=_NONNEG), _k("TowerHt", "tower_height", check=_POS),
    _k("TowerBsHt", "tower_base_height"), _k("PtfmCMxt", "platform_cm[0]"),
    _k("PtfmCMyt", "platform_cm[1]"), _k("PtfmCMzt", "platform_cm[2]"),
    _k("PtfmRefxt", "platform_reference[0]", default=0.0),
    _k("PtfmRefyt", "platform_reference[1]", default=0.0),
    _k("PtfmRefzt", "platform_reference[2]"), _k("TipMass(*)", "tip_mass", check=_NONNEG),
    _k("PBrIner(*)", "pitch_bearing_inertia", default=0.0, check=_NONNEG),
    _k("BlPIner(*)", "blade_pitch_inertia", default=0.0, check=_NONNEG),
    _k("HubMass", "hub_mass", check=_NONNEG), _k("HubIner", "hub_inertia", check=_NONNEG),
    _k("HubIner_Teeter", "hub_teeter_inertia", default=0.0, check=_NONNEG),
    _k("GenIner", "generator_inertia", check=_NONNEG), _k("NacMass", "nacelle_mass", check=_NONNEG),
    _k("NacYIner", "nacelle_yaw_inertia", check=_NONNEG),
    _k("YawBrMass", "yaw_bearing_mass", check=_NONNEG),
    _k("PtfmMass", "platform_mass", check=_NONNEG),
    *(_k(f"Ptfm{a}Iner", f"platform_{n}_inertia", check=_NONNEG)
      for a, n in (("R", "roll"), ("P", "pitch"), ("Y", "yaw"))),
    *(_k(f"Ptfm{a}Iner", f"platform_{a.lower()}_inertia", default=0.0) for a in ("XY", "YZ", "XZ")),
    _k("BldNodes", "n_blade_nodes", "int", check=_AT_LEAST_1),
    _k("TeetMod", "teeter_model", "int", check=(lambda v: v in (0, 1, 2), "must be 0, 1 or 2")),
    _k("TeetDmpP", "teeter_damper_position", scale=_DEG),
    _k("TeetDmp", "teeter_damping", check=_NONNEG),
    _k("TeetCDmp", "teeter_coulomb_damping", check=_NONNEG),
    _k("TeetSStP", "teeter_soft_stop_position", scale=_DEG),
    _k("TeetHStP", "teeter_hard_stop_position", scale=_DEG),
    _k("TeetSSSp", "teeter_soft_stop_stiffness", check=_NONNEG),
    _k("TeetHSSp", "teeter_hard_stop_stiffness", check=_NONNEG),
    _k("GBoxEff", "gearbox_efficiency", scale=_PCT,
       check=(lambda v: 0 < v <= 100, "must be in (0, 100] %")),
    _k("GBRatio", "gearbox_ratio", check=_POS),
    _k("DTTorSpr", "drivetrain_stiffness", check=_NONNEG),
    _k("DTTorDmp", "drivetrain_damping", check=_NONNEG),
    _k("Furling", "furling", "bool", default=False,
       check=(lambda v: not v, "must be False: mbsym does not model furling")),
    _k("TwrNodes", "n_tower_nodes", "int", check=_AT_LEAST_1),
)


def _modal_keys(prefix: str, attr: str, count: int, check: _Check) -> tuple[_Key, ...]:
    """Keys ``prefix(1..count)`` → ``attr[0..count-1]`` (damping in % or tuners)."""
    scale = _PCT if check is _PERCENT else None
    return tuple(_k(f"{prefix}({i + 1})", f"{attr}[{i}]", scale=scale, check=check)
                 for i in range(count))


def _shape_keys(*modes: tuple[str, str, int]) -> tuple[_Key, ...]:
    """Mode-shape coefficient keys ``name(2..6)`` → ``attr[mode][0..4]``."""
    return tuple(_k(f"{name}({j})", f"{attr}[{m}][{j - 2}]")
                 for name, attr, m in modes for j in range(2, 7))


_TOWER_SHAPES = (("TwFAM1Sh", "fa_mode_shapes", 0), ("TwFAM2Sh", "fa_mode_shapes", 1),
                 ("TwSSM1Sh", "ss_mode_shapes", 0), ("TwSSM2Sh", "ss_mode_shapes", 1))
_BLADE_SHAPES = (("BldFl1Sh", "flap_mode_shapes", 0), ("BldFl2Sh", "flap_mode_shapes", 1),
                 ("BldEdgSh", "edge_mode_shapes", 0))
_TOWER_KEYS = (
    *_modal_keys("TwrFADmp", "fa_damping_ratio", 2, _PERCENT),
    *_modal_keys("TwrSSDmp", "ss_damping_ratio", 2, _PERCENT),
    *_modal_keys("FAStTunr", "fa_stiffness_tuner", 2, _POS),
    *_modal_keys("SSStTunr", "ss_stiffness_tuner", 2, _POS),
    _k("AdjTwMa", "mass_factor", check=_POS), _k("AdjFASt", "fa_stiffness_factor", check=_POS),
    _k("AdjSSSt", "ss_stiffness_factor", check=_POS), *_shape_keys(*_TOWER_SHAPES),
)
_BLADE_KEYS = (
    *_modal_keys("BldFlDmp", "flap_damping_ratio", 2, _PERCENT),
    *_modal_keys("BldEdDmp", "edge_damping_ratio", 1, _PERCENT),
    *_modal_keys("FlStTunr", "flap_stiffness_tuner", 2, _POS),
    _k("AdjBlMs", "mass_factor", check=_POS), _k("AdjFlSt", "flap_stiffness_factor", check=_POS),
    _k("AdjEdSt", "edge_stiffness_factor", check=_POS), *_shape_keys(*_BLADE_SHAPES),
)


@dataclass(frozen=True)
class _TableSpec:
    """A table: row-count key, header names that start it, column → attribute (scale)."""

    name: str
    count_key: str
    starts: tuple[str, ...]  # lower-case first header names; () = header right after the
    # count key and columns read by position
    columns: tuple[tuple[str, str, float | None, bool], ...]  # name, attribute, scale, required


_TOWER_TABLE = _TableSpec("distributed tower properties", "NTwInpSt", ("htfract",), (
    ("HtFract", "station_fraction", None, True), ("TMassDen", "mass_density", None, True),
    ("TwFAStif", "fa_stiffness", None, True), ("TwSSStif", "ss_stiffness", None, True)))
_POINT_MASS_TABLE = _TableSpec("tower concentrated masses", "NTwCMass", (), (
    ("TwCMassHtFract", "point_mass_fraction", None, True), ("TwCMass", "point_mass", None, True)))
_BLADE_TABLE = _TableSpec("distributed blade properties", "NBlInpSt", ("blfract",), (
    ("BlFract", "station_fraction", None, True), ("PitchAxis", "pitch_axis", None, False),
    ("StrcTwst", "structural_twist", _DEG, True), ("BMassDen", "mass_density", None, True),
    ("FlpStff", "flap_stiffness", None, True), ("EdgStff", "edge_stiffness", None, True)))


def _key_map() -> dict[str, dict[str, str]]:
    def block(keys: tuple[_Key, ...], table: _TableSpec | None = None) -> dict[str, str]:
        out = {k.key: k.attr for k in keys}
        for col, attr, _, _ in (table.columns if table else ()):
            out[col] = f"{attr} (table column)"
        return out
    return {"fst": block(_FST_KEYS), "ElastoDyn": block(_ED_KEYS),
            "tower": block(_TOWER_KEYS, _TOWER_TABLE) | block((), _POINT_MASS_TABLE),
            "blade": block(_BLADE_KEYS, _BLADE_TABLE)}


#: OpenFAST key → attribute, per file kind.  ElastoDyn attributes are on
#: ``TurbineParameters`` (``"initial_conditions.rotor_speed"`` is nested, ``(*)``
#: marks one value per blade), tower/blade ones on ``TowerParameters`` /
#: ``BladeParameters``, fst ones on ``SimulationSettings``.
KEY_MAP: dict[str, dict[str, str]] = _key_map()

# ----------------------------------------------------------------------------- parsing
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


def _check_sum(deck: _Deck, name: str, coefficients: list[float | None]) -> None:
    if any(c is None for c in coefficients):
        return
    total = sum(coefficients)  # type: ignore[arg-type]
    if abs(total - 1.0) > 0.0015:
        first, last = deck.line_of(f"{name}(2)"), deck.line_of(f"{name}(6)")
        deck.problem(last, f"{name}(6)", f"the mode-shape coefficients {name}(2..6) on lines "
                     f"{first}-{last} sum to {total:.6g}; expected 1 within 0.0015 (ElastoDyn's "
                     "check). Fix the coefficients (e.g. divide each by their sum).")


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


def _check_fractions(deck: _Deck, spec: _TableSpec, fraction: np.ndarray) -> None:
    lines, col = deck.tables[spec.name].lines, spec.columns[0][0]
    if abs(fraction[0]) > 1e-6:
        deck.problem(lines[0], col, f"the first station must be at 0; got {fraction[0]:g}. "
                     "Start the table at 0.")
    if fraction.size > 1 and abs(fraction[-1] - 1.0) > 1e-6:
        deck.problem(lines[-1], col, f"the last station must be at 1; got {fraction[-1]:g}. "
                     "End the table at 1.")
    for j in range(1, fraction.size):
        if not fraction[j] > fraction[j - 1]:
            deck.problem(lines[j], col, f"stations must strictly increase; {fraction[j]:g} "
                         f"follows {fraction[j - 1]:g} (line {lines[j - 1]}). Fix the order.")


def _check_column(deck: _Deck, spec: _TableSpec, out: dict[str, Any], col: str,
                  ok: Callable[[float], bool], text: str) -> None:
    attr, scale = next((a, s) for c, a, s, _ in spec.columns if c == col)
    if out.get(attr) is None:
        return
    for j, value in enumerate(out[attr]):
        if not math.isnan(value) and not ok(value):
            shown = value / scale if scale else value
            deck.problem(deck.tables[spec.name].lines[j], col, f"{text}; got {shown:g} (row "
                         f"{j + 1} of the {spec.name} table). Fix it.")


def _read_distributed(path: Path, keys: tuple[_Key, ...], spec: _TableSpec,
                      positive: tuple[str, ...], shapes: tuple[tuple[str, str, int], ...], *,
                      point_masses: bool = False) -> dict[str, Any]:
    """Read a tower or blade file into constructor arguments; raise on problems."""
    deck = _Deck(path, (spec, _POINT_MASS_TABLE) if point_masses else (spec,))
    deck.value(_k(spec.count_key, "", "int", check=_AT_LEAST_1))
    out = _read_keys(deck, keys)
    _read_table_columns(deck, spec, out)
    fraction = out.get("station_fraction")
    if fraction is not None and fraction.size and not np.isnan(fraction).any():
        _check_fractions(deck, spec, fraction)
    for col in positive:
        _check_column(deck, spec, out, col, lambda v: v > 0, "must be greater than 0")
    if spec is _BLADE_TABLE:
        _check_column(deck, spec, out, "StrcTwst", lambda v: -math.pi < v <= math.pi + 1e-12,
                      "must be in (-180, 180] degrees")
    for name, attr, mode in shapes:
        _check_sum(deck, name, out[attr][mode])
    if point_masses and deck.value(_k("NTwCMass", "", "int", default=0, check=_NONNEG)):
        masses: dict[str, Any] = {}
        _read_table_columns(deck, _POINT_MASS_TABLE, masses)
        if masses.get("extra_columns"):
            deck.problem(deck.tables[_POINT_MASS_TABLE.name].header_line, "NTwCMass",
                         "the concentrated-mass table must have exactly 2 columns. Fix it.")
        out["point_mass_fraction"] = masses.get("point_mass_fraction")
        out["point_mass"] = masses.get("point_mass")
    deck.raise_problems()
    out["extra"] = deck.extra()
    return out


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


def _read_fst(fst: _Deck) -> dict[str, Any]:
    sim = _read_keys(fst, _FST_KEYS)
    n_lin = fst.value(_k("NLinTimes", "", "int", default=None))
    if sim["linearization_times"] and n_lin is not None:
        sim["linearization_times"] = sim["linearization_times"][:n_lin]
    if sim["structural_model"] not in (None, 1):
        fst.problem(fst.line_of("CompElast"), "CompElast", "only CompElast = 1 (ElastoDyn) is "
                    f"supported; got {sim['structural_model']}. Set it to 1.")
    mhk = fst.value(_k("MHK", "", "int", default=0))
    if mhk not in (None, 0):
        fst.problem(fst.line_of("MHK"), "MHK", f"MHK turbines are not supported; got {mhk}. "
                    "Set it to 0.")
    if sim["output_time_step"] == "default":
        sim["output_time_step"] = sim["time_step"]
    return sim


def _check_elastodyn(ed: _Deck, v: dict[str, Any]) -> None:
    """ElastoDyn's cross-key checks (deck units were already checked key by key)."""
    def fail(key: str, text: str) -> None:
        ed.problem(ed.line_of(key), key, text)
    try:
        if v["hub_radius"] >= v["tip_radius"]:
            fail("HubRad", "must be less than TipRad. Fix one of the two.")
        if v["tower_base_height"] >= v["tower_height"]:
            fail("TowerBsHt", "must be less than TowerHt. Fix one of the two.")
        for key, value in (("PtfmCMzt", v["platform_cm"][2]),
                           ("PtfmRefzt", v["platform_reference"][2])):
            if value > v["tower_base_height"]:
                fail(key, "must not be greater than TowerBsHt. Fix one of the two.")
        hub_height = v["tower_height"] + v["twr2shft"] + v["overhang"] * math.sin(v["shaft_tilt"])
        if hub_height <= v["tip_radius"]:
            fail("TipRad", "TowerHt + Twr2Shft + OverHang*SIN(ShftTilt) must be greater than "
                 "TipRad (the blades would hit the ground). Fix the geometry.")
        cm_x, cm_y = v["nacelle_cm"][0], v["nacelle_cm"][1]
        if v["nacelle_yaw_inertia"] < v["nacelle_mass"] * (cm_x**2 + cm_y**2):
            fail("NacYIner", "must not be less than NacMass*(NacCMxn^2 + NacCMyn^2). Fix it.")
    except TypeError:  # a value is None: already reported as a problem
        pass


def _read_elastodyn(ed: _Deck, sim: dict[str, Any]) -> dict[str, Any]:
    entry = ed.entries.get("numbl")
    n_blades = _convert("int", entry.values)[0] if entry else None
    n_blades = n_blades if n_blades in (1, 2, 3) else 3  # a bad NumBl is reported below
    v = _read_keys(ed, _ED_KEYS, n_blades)
    if sim["gravity"] is None:
        sim["gravity"] = ed.value(_k("Gravity", "", default=None, check=_NONNEG))
    if v["structural_time_step"] == "default":
        v["structural_time_step"] = sim["time_step"]
    for k in range(1, n_blades + 1):
        ed.value(_k(f"BldFile({k})", "", "str"))
    ed.value(_k("TwrFile", "", "str"))
    _check_elastodyn(ed, v)
    v["output_channels"] = tuple(ed.outlists[0]) if ed.outlists else ()
    v["node_output_channels"] = tuple(c for o in ed.outlists[1:] for c in o)
    return v


def read_openfast(path: str | Path) -> TurbineParameters:
    """Read an OpenFAST deck (``.fst`` + ElastoDyn, tower and blade files).

    Parameters
    ----------
    path : str or Path
        The main ``.fst`` file.  Files it names are taken relative to the naming
        file's directory, as OpenFAST does.

    Returns
    -------
    TurbineParameters
        Everything ElastoDyn uses, in SI units (see :data:`KEY_MAP`).

    Raises
    ------
    OpenFASTFormatError
        If a file is missing, a key is missing or malformed, or a value fails
        ElastoDyn's checks; the message names the file, line and key.

    Examples
    --------
    >>> from mbsym.wind import read_openfast
    >>> p = read_openfast("NREL5MW_Onshore_ElastoDynOnly.fst")  # doctest: +SKIP
    >>> round(p.tower_height, 1), p.dofs["TwFADOF1"]  # doctest: +SKIP
    (87.6, True)
    """
    fst_path = Path(path)
    if not fst_path.is_file():
        raise OpenFASTFormatError(f"OpenFAST main input file not found: tried "
                                  f"'{fst_path.absolute()}'. Check the path.")
    fst = _Deck(fst_path)
    sim = _read_fst(fst)
    fst.raise_problems()
    ed = _Deck(_resolve(fst, "EDFile", "ElastoDyn input file"))
    v = _read_elastodyn(ed, sim)
    if sim["gravity"] is None and not ed.problems:
        fst.problem(fst.last_line, "Gravity", "missing from both this file and the ElastoDyn "
                    "file. Add a line '9.80665  Gravity  - ...' to the environment section.")
        fst.raise_problems()
    ed.raise_problems()
    sources = {"fst": str(fst_path), "elastodyn": str(ed.path)}
    tower_path = _resolve(ed, "TwrFile", "tower file")
    sources["tower"] = str(tower_path)
    tower = TowerParameters(**_read_distributed(
        tower_path, _TOWER_KEYS, _TOWER_TABLE, ("TMassDen", "TwFAStif", "TwSSStif"),
        _TOWER_SHAPES, point_masses=True))
    blades: list[BladeParameters] = []
    cache: dict[Path, BladeParameters] = {}
    for k in range(1, v["number_of_blades"] + 1):
        blade_path = _resolve(ed, f"BldFile({k})", f"blade {k} file")
        sources[f"blade{k}"] = str(blade_path)
        if blade_path.resolve() not in cache:
            cache[blade_path.resolve()] = BladeParameters(**_read_distributed(
                blade_path, _BLADE_KEYS, _BLADE_TABLE, ("BMassDen", "FlpStff", "EdgStff"),
                _BLADE_SHAPES))
        blades.append(cache[blade_path.resolve()])
    sim["extra"] = fst.extra()
    ic = v.pop("initial_conditions")
    ic["blade_pitch"] = tuple(ic["blade_pitch"])
    for name in ("precone", "tip_mass", "pitch_bearing_inertia", "blade_pitch_inertia",
                 "nacelle_cm", "platform_cm", "platform_reference"):
        v[name] = tuple(v[name])
    return TurbineParameters(
        simulation=SimulationSettings(**sim), initial_conditions=InitialConditions(**ic),
        tower=tower, blades=tuple(blades), extra=ed.extra(), source_files=sources, **v)
