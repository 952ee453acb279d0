"""Read OpenFAST decks (main ``.fst``, ElastoDyn, tower and blade files).

:func:`read_openfast` returns :class:`~mbsym.wind.deck.parameters.TurbineParameters`.
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
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ...exceptions import OpenFASTFormatError
from . import checks
from .budget import check_deck_memory
from ._format import (
    _REQ, _Check, _canon, _convert, _Deck, _Key, _read_keys, _read_table_columns, _resolve, _TableSpec,
)
from .parameters import (
    DOF_NAMES, BladeParameters, InitialConditions, SimulationSettings, TowerParameters,
    TurbineParameters,
)

__all__ = ["read_openfast", "KEY_MAP"]

_DEG, _RPM, _PCT = math.pi / 180.0, math.pi / 30.0, 0.01
_POS = (lambda v: v > 0, "must be greater than 0")
_NONNEG = (lambda v: v >= 0, "must not be negative")
_PERCENT = (lambda v: 0 <= v <= 100, "must be between 0 and 100 % (inclusive)")
_ANG180 = (lambda v: -180 < v <= 180, "must be in (-180, 180] degrees")
_ANG360 = (lambda v: 0 <= v < 360, "must be in [0, 360) degrees")
_k = _Key
_ONE_TO_3 = (lambda v: v in (1, 2, 3), "must be 1, 2 or 3")
_AT_LEAST_1 = (lambda v: v >= 1, "must be at least 1")
#: Most ElastoDyn analysis nodes per blade (BldNodes) or tower (TwrNodes) a deck may ask for. Measured on the
#: shared steady_14 deck: each tower node costs ~630 bytes and ~12 µs to build (1e6 nodes: 13 s, +630 MB; the
#: 1e8 of a mistyped deck would need ~63 GB), and the modal integrals converge with O(100) nodes (the shared
#: decks use 17-49). 100 000 nodes: ~63 MB and ~1 s.
MAX_ANALYSIS_NODES = 100_000
_NODES = (lambda v: 1 <= v <= MAX_ANALYSIS_NODES,
          f"must be at least 1 and at most {MAX_ANALYSIS_NODES} (each node costs ~630 bytes and ~12 µs to build; "
          "ElastoDyn decks use 10-100)")
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
    _k("InterpOrder", "interp_order", "int", default=1,
       check=(lambda v: v in (1, 2), "must be 1 (linear) or 2 (quadratic)")),
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
    _k("BldNodes", "n_blade_nodes", "int", check=_NODES),
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
    _k("TwrNodes", "n_tower_nodes", "int", check=_NODES),
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



#: Largest magnitude of a number in the ElastoDyn, tower and blade files: beyond it the
#: computations overflow (e.g. TowerHt 1e300 squared in the mode-shape curvatures).
MAX_MAGNITUDE = 1e30


def _check_magnitudes(deck: _Deck) -> None:
    """Report numbers too large to compute with (keys and table cells)."""
    for entry in deck.entries.values():
        values = _convert("floats", entry.values)[0] if entry.values else None
        if values and any(abs(v) > MAX_MAGNITUDE for v in values):
            deck.problem(entry.line, entry.key, f"{' '.join(entry.values)} is too large to compute with (|value| > "
                         f"{MAX_MAGNITUDE:g}); check the exponent.")
    for name, table in deck.tables.items():
        for line, row in zip(table.lines, table.rows):
            if any(v is not None and abs(v) > MAX_MAGNITUDE for v in row):
                deck.problem(line, name, f"a value of the {name} table is too large to compute with (|value| > "
                             f"{MAX_MAGNITUDE:g}); check the exponent.")


def _check_sum(deck: _Deck, name: str, coefficients: list[float | None]) -> None:
    if any(c is None for c in coefficients):
        return
    total = sum(coefficients)  # type: ignore[arg-type]
    if abs(total - 1.0) > 0.0015:
        first, last = deck.line_of(f"{name}(2)"), deck.line_of(f"{name}(6)")
        deck.problem(last, f"{name}(6)", f"the mode-shape coefficients {name}(2..6) on lines "
                     f"{first}-{last} sum to {total:.6g}; expected 1 within 0.0015 (ElastoDyn's "
                     "check). Fix the coefficients (e.g. divide each by their sum).")


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
    _check_magnitudes(deck)
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
        speed, radius = v["initial_conditions"]["rotor_speed"], v["tip_radius"]
        if speed * radius > checks.MAX_TIP_SPEED:
            fail("RotSpeed", f"the blade tip would move at {speed * radius:.4g} m/s (RotSpeed x TipRad), beyond the "
                 f"speed of sound ({checks.MAX_TIP_SPEED:g} m/s); at most "
                 f"{checks.max_rotor_speed_rpm(radius):.4g} rpm for TipRad {radius:g} m. Fix RotSpeed (in rpm).")
        cm_x, cm_y = v["nacelle_cm"][0], v["nacelle_cm"][1]
        if v["nacelle_yaw_inertia"] < v["nacelle_mass"] * (cm_x**2 + cm_y**2):
            fail("NacYIner", "must not be less than NacMass*(NacCMxn^2 + NacCMyn^2). Fix it.")
    except TypeError:  # a value is None: already reported as a problem
        pass


def _read_elastodyn(ed: _Deck, sim: dict[str, Any]) -> dict[str, Any]:
    entry = ed.entries.get("numbl")
    n_blades = _convert("int", entry.values)[0] if entry else None
    n_blades = n_blades if n_blades in (1, 2, 3) else 3  # a bad NumBl is reported below
    _check_magnitudes(ed)
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


#: source_files role -> (.fst key, SimulationSettings switch) of the modules named by the .fst
_MODULE_FILES = {"inflowwind": ("InflowFile", "inflow_model"),
                 "aerodyn": ("AeroFile", "aerodynamics_model"),
                 "servodyn": ("ServoFile", "servo_model")}


def _module_files(fst: _Deck, sim: dict[str, Any]) -> dict[str, str]:
    """Paths of the InflowWind/AeroDyn/ServoDyn files the .fst switches on (those that exist)."""
    out = {}
    for role, (key, switch) in _MODULE_FILES.items():
        entry = fst.entries.get(key.lower())
        if sim.get(switch) and entry is not None and entry.values:
            path = fst.path.parent / entry.values[0].replace("\\", "/")
            if path.is_file():
                out[role] = str(path)
    return out


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
    DeckMemoryError
        (an OpenFASTFormatError) The memory the deck implies (its node counts, tables, wind field;
        :func:`mbsym.wind.deck.budget.deck_memory_estimate` with ``run=False``) is above
        :func:`mbsym.simulate.monitor.memory_limit`; names the file, line and key that dominate.

    Warns
    -----
    ModelWarning
        Settings ElastoDyn ignores (TeetDOF on a rotor that is not two-bladed: turned off,
        as ElastoDyn does) or warns about, and platform DOFs nothing holds
        (:func:`mbsym.wind.deck.checks.deck_notes`). Modules the deck switches on are not
        checked here (reading is not modelling): see
        :func:`mbsym.wind.deck.checks.check_modules`.

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
    check_deck_memory(fst_path, run=False)     # before the tower, blade and module files are parsed or anything is built
    sources = {"fst": str(fst_path), "elastodyn": str(ed.path)}
    sources |= _module_files(fst, sim)
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
    sources.update(_module_files(fst, sim))
    v["dofs"], notes = checks.ignored_dofs(v["dofs"], v["number_of_blades"])
    ic = v.pop("initial_conditions")
    ic["blade_pitch"] = tuple(ic["blade_pitch"])
    for name in ("precone", "tip_mass", "pitch_bearing_inertia", "blade_pitch_inertia",
                 "nacelle_cm", "platform_cm", "platform_reference"):
        v[name] = tuple(v[name])
    turbine = TurbineParameters(
        simulation=SimulationSettings(**sim), initial_conditions=InitialConditions(**ic),
        tower=tower, blades=tuple(blades), extra=ed.extra(), source_files=sources, **v)
    for note in notes + checks.deck_notes(turbine):
        checks.warn(f"{fst_path.name}: {note}.", stacklevel=2)
    return turbine


def _module_files(fst: _Deck, sim: dict[str, Any]) -> dict[str, str]:
    """Paths of the input files of the modules the deck switches on (not read here), by module
    (:data:`mbsym.wind.deck.checks.MODULE_FILES`), resolved against the deck's directory."""
    out = {}
    for key, name, attr in checks.MODULE_FILES.values():
        entry = fst.entries.get(_canon(key))
        if sim.get(attr) and entry is not None and entry.values and entry.values[0].lower() != "unused":
            path = Path(entry.values[0].replace("\\", "/"))
            out[name] = str(path if path.is_absolute() else fst.path.parent / path)
    return out
