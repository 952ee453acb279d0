"""Read AeroDyn 15 input: the main file, the blade files and the airfoil files.

:func:`read_aerodyn` returns :class:`AeroDynInput`: the options a steady
blade-element momentum (BEM) model needs (wake/BEM/skew model switches, Prandtl
tip and hub loss, tangential induction, drag in the induction, air density and
viscosity, airfoil-table columns), the blades (:class:`AeroDynBlade`) and the
airfoil polars (:class:`~mbsym.wind.deck.airfoils.AirfoilPolar`).  Keys are read
with the strict, line-numbered parser of :mod:`mbsym.wind.deck._format` (by key,
case-insensitive); the newer key names are used, with the older spellings
accepted where they mean the same (``Wake_Mod``/``WakeMod``, ``UA_Mod``/
``UAMod``/``AFAeroMod``, ``Skew_Mod``/``SkewMod``; the skew switch is kept as
written: its meaning changed between versions).  Keys not read are kept, with
their raw text, in ``extra``.

As AeroDyn does, a blade file is read up to its ``NumBlNds``-th table row; lines
after it are ignored (kept verbatim in the blade's ``extra``).  Angles are
converted from deg to rad.  Every problem raises
:class:`~mbsym.exceptions.OpenFASTFormatError`, naming the file, line and key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...exceptions import OpenFASTFormatError, DimensionError, ParameterError
from ._format import (
    _TOKEN, _canon, _Deck, _Key, _read_table_columns, _real, _resolve, _TableSpec,
)
from ._record import _readonly, _Record
from .airfoils import AirfoilPolar, _key_of, read_airfoil

__all__ = ["AeroDynBlade", "AeroDynInput", "read_aerodyn", "read_aerodyn_blade"]

_DEG = math.pi / 180.0
_BLADE_TABLE = _TableSpec("blade", "NumBlNds", ("blspn",), (
    ("BlSpn", "span", None, True), ("BlCrvAC", "curve_ac", None, True),
    ("BlSwpAC", "sweep_ac", None, True), ("BlCrvAng", "curve_angle", _DEG, True),
    ("BlTwist", "twist", _DEG, True), ("BlChord", "chord", None, True),
    ("BlAFID", "airfoil_id", None, True)))
_TOWER_TABLE = _TableSpec("tower", "NumTwrNds", ("twrelev",), (
    ("TwrElev", "tower_elevation", None, True), ("TwrDiam", "tower_diameter", None, True),
    ("TwrCd", "tower_drag", None, True), ("TwrTI", "tower_ti", None, False)))


#: The node-wise geometry of an aerodynamic blade (AeroDyn blade file columns, our BEM rotor).
BLADE_GEOMETRY = ("curve_ac", "sweep_ac", "curve_angle", "twist", "chord")


def freeze_blade_geometry(record, owner: str) -> np.ndarray:
    """Check and freeze (read-only arrays) ``record.span`` and the :data:`BLADE_GEOMETRY` columns.

    ``span`` strictly increasing from >= 0 with at least 2 nodes, every column one value per node,
    the chord positive; returns the span. Raises ParameterError naming ``owner``'s field.
    """
    span = _readonly(record.span, f"{owner}.span")
    if span.size < 2 or span[0] < 0 or np.any(np.diff(span) <= 0):
        raise ParameterError(f"{owner}.span must hold at least 2 strictly increasing distances >= 0 [m].")
    object.__setattr__(record, "span", span)
    for name in BLADE_GEOMETRY:
        values = _readonly(getattr(record, name), f"{owner}.{name}")
        if values.shape != span.shape:
            raise DimensionError(f"{owner}.{name} has {values.size} values; expected {span.size} (one per node).")
        object.__setattr__(record, name, values)
    if np.any(record.chord <= 0):
        raise ParameterError(f"{owner}.chord must be > 0 at every node.")
    return span


@dataclass(frozen=True, eq=False)
class AeroDynBlade(_Record):
    """Distributed aerodynamic properties of one blade (AeroDyn blade file).

    Attributes
    ----------
    span : ndarray, shape (n,)
        Distance of each node from the blade root along the pitch axis [m] (BlSpn),
        strictly increasing from >= 0.
    curve_ac, sweep_ac : ndarray, shape (n,)
        Out-of-plane (BlCrvAC, prebend) and in-plane (BlSwpAC) offsets of the
        aerodynamic centre from the pitch axis [m].
    curve_angle : ndarray, shape (n,)
        Angle from the pitch axis to a line tangent to the blade's out-of-plane
        curve [rad] (BlCrvAng).
    twist : ndarray, shape (n,)
        Aerodynamic twist [rad] (BlTwist; positive to feather, leading edge upwind).
    chord : ndarray, shape (n,)
        Chord length [m] (BlChord), > 0.
    airfoil_id : tuple of int
        1-based index into the AeroDyn airfoil list (BlAFID), one per node.
    extra_columns : dict of str to ndarray
        Further table columns (t_c, BlCb, ...), by header name.
    extra : dict of str to str
        Unread keys, and lines after the table (which AeroDyn ignores).
    source : str or None
        The file read (not compared).
    """

    span: np.ndarray
    curve_ac: np.ndarray
    sweep_ac: np.ndarray
    curve_angle: np.ndarray
    twist: np.ndarray
    chord: np.ndarray
    airfoil_id: tuple[int, ...]
    extra_columns: dict[str, np.ndarray] = field(default_factory=dict)
    extra: dict[str, str] = field(default_factory=dict)
    source: str | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        span = freeze_blade_geometry(self, "AeroDynBlade")
        ids = tuple(int(i) for i in self.airfoil_id)
        if len(ids) != span.size or min(ids) < 1:
            raise ParameterError(f"AeroDynBlade.airfoil_id must hold {span.size} indices >= 1.")
        object.__setattr__(self, "airfoil_id", ids)
        object.__setattr__(self, "extra_columns", {
            k: _readonly(v, f"AeroDynBlade.extra_columns[{k!r}]")
            for k, v in self.extra_columns.items()})


@dataclass(frozen=True, eq=False)
class AeroDynInput(_Record):
    """What an AeroDyn 15 deck says about rotor aerodynamics (SI units).

    Attributes
    ----------
    wake_model : int
        Wake_Mod (0 none, 1 BEMT, 2 DBEMT, 3 OLAF).
    bem_model : int
        BEM_Mod (1 legacy NoSweepPitchTwist, 2 polar); 1 if the file has no such key.
    skew_model : int or None
        Skew_Mod (or older SkewMod) as written.
    skew_redistribution : bool
        Whether AeroDyn redistributes the induction over the skewed disk (Pitt/Peters):
        Skew_Mod = 1 with SkewRedistr_Mod = 1 ("default"), or, in older files, SkewMod = 2.
    skew_redistribution_factor : float
        SkewRedistrFactor (older SkewModFactor); "default" = 15π/32.
    tip_loss, hub_loss, tangential_induction : bool
        TipLoss, HubLoss, TanInd.
    axial_drag, tangential_drag : bool
        AIDrag, TIDrag: whether drag enters the axial/tangential induction.
    unsteady_model : int
        UA_Mod (older UAMod / AFAeroMod) as written (0 = steady airfoil aerodynamics
        in current AeroDyn).
    air_density, kinematic_viscosity : float or None
        AirDens [kg/m^3], KinVisc [m^2/s]; None if "default" (taken from the ``.fst``).
    airfoil_table_mode : int
        AFTabMod: 1 the first table of each airfoil file; 3 the table for UserProp 0 (no airfoil control); 2
        (Reynolds-number interpolation) only with one table per file.
    airfoil_columns : tuple of int
        InCol_Alfa, InCol_Cl, InCol_Cd, InCol_Cm (1-based; Cm 0 = none).
    use_pitching_moment : bool
        UseBlCm.
    airfoil_files, blade_files : tuple of str
        AFNames and ADBlFile(k) as written (relative to the AeroDyn file).
    airfoils : tuple of AirfoilPolar
        The polars, in AFNames order (``airfoil_id`` 1 is ``airfoils[0]``).
    blades : tuple of AeroDynBlade
        One per blade read.
    tower_elevation, tower_diameter, tower_drag, tower_ti : ndarray
        The tower table (m, m, -, -): ``TwrElev``, ``TwrDiam``, ``TwrCd`` and ``TwrTI`` (zeros where the
        table has no such column) for :class:`~mbsym.wind.aero.tower.TowerAero`.
    extra : dict of str to str
        Every other key with its raw value text.
    source : str or None
        The AeroDyn main file (not compared).
    """

    wake_model: int
    bem_model: int
    skew_model: int | None
    skew_redistribution: bool
    skew_redistribution_factor: float
    tip_loss: bool
    hub_loss: bool
    tangential_induction: bool
    axial_drag: bool
    tangential_drag: bool
    unsteady_model: int
    air_density: float | None
    kinematic_viscosity: float | None
    airfoil_table_mode: int
    airfoil_columns: tuple[int, ...]
    use_pitching_moment: bool
    airfoil_files: tuple[str, ...]
    blade_files: tuple[str, ...]
    airfoils: tuple[AirfoilPolar, ...]
    blades: tuple[AeroDynBlade, ...]
    tower_elevation: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tower_diameter: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tower_drag: np.ndarray = field(default_factory=lambda: np.zeros(0))
    tower_ti: np.ndarray = field(default_factory=lambda: np.zeros(0))
    extra: dict[str, str] = field(default_factory=dict)
    source: str | None = field(default=None, compare=False)


# ----------------------------------------------------------------------------- decks
class _MainDeck(_Deck):
    """AeroDyn main file: the AFNames continuation lines are taken out before parsing."""

    def _parse(self, lines: list[str], specs: tuple) -> None:  # type: ignore[override]
        self.af_lines: list[tuple[int, str]] = []
        lines = [text.split("!")[0] if text.strip().lower().startswith("twrelev") else text
                 for text in lines]  # a trailing '! comment' on the tower table header
        keys = [_key_of(text) for text in lines]
        if "afnames" in keys and "numaffiles" in keys:
            count = _real(_TOKEN.findall(lines[keys.index("numaffiles")])[0])
            i = keys.index("afnames") + 1
            remaining = int(count) - 1 if count is not None and count >= 1 else 0
            while remaining > 0 and i < len(lines):
                text = lines[i].strip()
                if text and not text.startswith(("!", "#")):
                    if text.startswith(("--", "==")) or _key_of(text) is not None:
                        break  # fewer names than NumAFfiles: reported by the caller
                    self.af_lines.append((i + 1, _TOKEN.findall(text)[0].strip("\"'")))
                    lines[i] = ""
                    remaining -= 1
                i += 1
        super()._parse(lines, specs)


class _BladeDeck(_Deck):
    """AeroDyn blade file, cut after the NumBlNds-th table row (as AeroDyn reads it)."""

    def _parse(self, lines: list[str], specs: tuple) -> None:  # type: ignore[override]
        self.ignored: dict[str, str] = {}
        keys = [_key_of(text) for text in lines]
        if "numblnds" in keys:
            start = keys.index("numblnds")
            count = _real(_TOKEN.findall(lines[start])[0])
            header = next((i for i in range(start + 1, len(lines))
                           if lines[i].strip() and not lines[i].strip().startswith(("!", "#"))),
                          None)
            if count is not None and count >= 1 and header is not None:
                i, rows = header + 2, 0
                while i < len(lines) and rows < int(count):
                    rows += bool(lines[i].strip())
                    i += 1
                for j in range(i, len(lines)):
                    text = lines[j].strip()
                    if text and not text.startswith(("!", "#", "--", "==")):
                        self.ignored[f"(ignored after the table, line {j + 1})"] = text
                lines = lines[:i]
        super()._parse(lines, specs)


def _alias(deck: _Deck, *names: str) -> str:
    """The first of ``names`` present in the file (else the first, reported missing)."""
    return next((n for n in names if _canon(n) in deck.entries), names[0])


def _flag(deck: _Deck, key: str) -> Any:
    return deck.value(_Key(key, "", "bool"))


def read_aerodyn_blade(path: str | Path, *, n_airfoils: int | None = None) -> AeroDynBlade:
    """Read an AeroDyn 15 blade file.

    Parameters
    ----------
    path : str or Path
        The blade file.
    n_airfoils : int, optional
        Number of airfoil files of the AeroDyn deck; BlAFID is checked against it.

    Returns
    -------
    AeroDynBlade

    Raises
    ------
    OpenFASTFormatError
        If the file is missing, NumBlNds or the table is malformed, the span does not
        start at >= 0 and strictly increase, a chord is <= 0, or BlAFID is not an
        integer in [1, n_airfoils]; the message names the file and line.
    """
    path = Path(path)
    if not path.is_file():
        raise OpenFASTFormatError(f"AeroDyn blade file not found: tried '{path.absolute()}'. Check "
                                  "the ADBlFile entry of the AeroDyn file.")
    deck = _BladeDeck(path, (_BLADE_TABLE,))
    deck.value(_Key("NumBlNds", "", "int", check=(lambda v: v >= 2, "must be at least 2")))
    out: dict[str, Any] = {}
    _read_table_columns(deck, _BLADE_TABLE, out)
    table = deck.tables.get(_BLADE_TABLE.name)
    if table is not None and out.get("span") is not None and len(table.rows):
        _check_blade(deck, table.lines, out, n_airfoils)
    deck.raise_problems()
    out["airfoil_id"] = tuple(int(i) for i in out["airfoil_id"])
    return AeroDynBlade(**out, extra=deck.extra() | deck.ignored, source=str(path))


def _check_blade(deck: _Deck, lines: list[int], out: dict[str, Any], n_airfoils: int | None
                 ) -> None:
    span, chord, ids = out["span"], out["chord"], out["airfoil_id"]
    if np.isnan(span).any() or np.isnan(chord).any() or np.isnan(ids).any():
        return  # bad numbers already reported
    if span[0] < 0:
        deck.problem(lines[0], "BlSpn", f"must be >= 0; got {span[0]:g}. Fix it.")
    for j in range(1, span.size):
        if not span[j] > span[j - 1]:
            deck.problem(lines[j], "BlSpn", f"must strictly increase; {span[j]:g} follows "
                         f"{span[j - 1]:g} (line {lines[j - 1]}). Fix the order.")
    for j, value in enumerate(chord):
        if not value > 0:
            deck.problem(lines[j], "BlChord", f"must be > 0; got {value:g}. Fix it.")
    top = n_airfoils if n_airfoils is not None else math.inf
    for j, value in enumerate(ids):
        if value != int(value) or not 1 <= value <= top:
            deck.problem(lines[j], "BlAFID", f"must be an integer in [1, {top}] (an index into "
                         f"AFNames); got {value:g}. Fix it.")


_MAIN_KEYS = (("TipLoss", "tip_loss"), ("HubLoss", "hub_loss"), ("TanInd", "tangential_induction"),
              ("AIDrag", "axial_drag"), ("TIDrag", "tangential_drag"),
              ("UseBlCm", "use_pitching_moment"))
_COLUMNS = ("InCol_Alfa", "InCol_Cl", "InCol_Cd", "InCol_Cm")
_NONNEG = (lambda v: v >= 0, "must not be negative")


def _read_main(deck: _MainDeck, n_blades: int) -> dict[str, Any]:
    v: dict[str, Any] = {
        "wake_model": deck.value(_Key(_alias(deck, "Wake_Mod", "WakeMod"), "", "int",
                                      check=(lambda m: m in (0, 1, 2, 3), "must be 0, 1, 2 or 3"))),
        "bem_model": deck.value(_Key("BEM_Mod", "", "int", default=1,
                                     check=(lambda m: m in (1, 2), "must be 1 or 2"))),
        "skew_model": deck.value(_Key(_alias(deck, "Skew_Mod", "SkewMod"), "", "int",
                                      default=None)),
        "unsteady_model": deck.value(_Key(_alias(deck, "UA_Mod", "UAMod", "AFAeroMod"), "",
                                          "int")),
    }
    v |= _skew(deck, v["skew_model"])
    for key, name in _MAIN_KEYS:
        v[name] = _flag(deck, key)
    for key, name in (("AirDens", "air_density"), ("KinVisc", "kinematic_viscosity")):
        value = deck.value(_Key(key, "", "float|default", check=(lambda x: x > 0,
                                                                 "must be greater than 0")))
        v[name] = None if value == "default" else value
    v["airfoil_table_mode"] = deck.value(_Key("AFTabMod", "", "int", default=1,
                                              check=(lambda m: m in (1, 2, 3), "must be 1, 2 or 3")))
    v["airfoil_columns"] = tuple(deck.value(_Key(k, "", "int", check=_NONNEG)) for k in _COLUMNS)
    n_af = deck.value(_Key("NumAFfiles", "", "int", check=(lambda n: n >= 1, "must be at least 1")))
    first = deck.value(_Key("AFNames", "", "str"))
    names = ([first] if first is not None else []) + [name for _, name in deck.af_lines]
    if isinstance(n_af, int) and first is not None and len(names) != n_af:
        deck.problem(deck.line_of("AFNames"), "AFNames", f"NumAFfiles says {n_af} airfoil files, "
                     f"but {len(names)} names follow. Add one quoted file name per line.")
    v["airfoil_files"] = tuple(names)
    v["blade_files"] = tuple(deck.value(_Key(f"ADBlFile({k})", "", "str"))
                             for k in range(1, n_blades + 1))
    if _canon("NumTwrNds") in deck.entries and _TOWER_TABLE.name in deck.tables:
        tower: dict[str, Any] = {}
        deck.value(_Key("NumTwrNds", "", "int", check=_NONNEG))
        _read_table_columns(deck, _TOWER_TABLE, tower)
        v |= {k: tower[k] for k in ("tower_elevation", "tower_diameter", "tower_drag")}
        ti = tower.get("tower_ti")
        v["tower_ti"] = np.zeros_like(tower["tower_elevation"]) if ti is None and tower["tower_elevation"] is not None \
            else ti
    return v


def _skew(deck: _MainDeck, skew_model: int | None) -> dict[str, Any]:
    """Skewed-wake redistribution switch and factor (v4+ keys, or the older SkewMod ones)."""
    new = _canon("Skew_Mod") in deck.entries
    if new:
        mode = deck.value(_Key("SkewRedistr_Mod", "", "float|default", default="default"))
        on = skew_model == 1 and mode in ("default", 1)
    else:
        on = skew_model == 2  # older AeroDyn 15: SkewMod 2 = Pitt/Peters
    factor = deck.value(_Key(_alias(deck, "SkewRedistrFactor", "SkewModFactor"), "", "float|default",
                             default="default"))
    return {"skew_redistribution": bool(on),
            "skew_redistribution_factor": 15.0 * math.pi / 32.0 if factor in ("default", None)
            else float(factor)}


def read_aerodyn(path: str | Path, *, n_blades: int = 3) -> AeroDynInput:
    """Read an AeroDyn 15 main file with its blade and airfoil files.

    Parameters
    ----------
    path : str or Path
        The AeroDyn main input file (the ``.fst``'s AeroFile).
    n_blades : int, optional
        Number of blades (ElastoDyn's NumBl): ADBlFile(1..n_blades) are read.

    Returns
    -------
    AeroDynInput

    Raises
    ------
    OpenFASTFormatError
        If a file is missing or malformed (names file, line and key).

    Examples
    --------
    >>> from mbsym.wind.deck.aerodyn import read_aerodyn
    >>> ad = read_aerodyn("NRELOffshrBsline5MW_Onshore_AeroDyn15.dat")  # doctest: +SKIP
    >>> ad.tip_loss, ad.axial_drag, len(ad.airfoils), ad.blades[0].span[-1]  # doctest: +SKIP
    (True, False, 8, 61.4999)
    """
    if n_blades not in (1, 2, 3):
        raise ParameterError(f"n_blades must be 1, 2 or 3; got {n_blades!r}.")
    main_path = Path(path)
    if not main_path.is_file():
        raise OpenFASTFormatError(f"AeroDyn input file not found: tried "
                                  f"'{main_path.absolute()}'. Check the AeroFile entry of the .fst.")
    deck = _MainDeck(main_path, (_TOWER_TABLE,))
    v = _read_main(deck, n_blades)
    deck.raise_problems()
    airfoils = []
    user_prop = 0.0 if v["airfoil_table_mode"] == 3 else None      # AeroDyn's UserProp: 0 without airfoil control
    for j, name in enumerate(v["airfoil_files"]):
        line = deck.af_lines[j - 1][0] if j else deck.line_of("AFNames")
        airfoils.append(read_airfoil(_resolve_name(deck, name, line, "AFNames", "airfoil file"),
                                     columns=v["airfoil_columns"], user_prop=user_prop))
    several = [a.name for a in airfoils if a.n_tables > 1]
    if v["airfoil_table_mode"] == 2 and several:
        deck.problem(deck.line_of("AFTabMod"), "AFTabMod", f"2 interpolates the airfoil tables in Reynolds number; "
                     f"{len(several)} airfoil files have several ({', '.join(several[:3])}"
                     f"{', …' if len(several) > 3 else ''}) and mbsym reads one table per airfoil. Set AFTabMod = 1 "
                     "(the first table) or give one table per file.")
        deck.raise_problems()
    blades, cache = [], {}
    for k, name in enumerate(v["blade_files"], start=1):
        blade_path = _resolve(deck, f"ADBlFile({k})", f"blade {k} file").resolve()
        if blade_path not in cache:
            cache[blade_path] = read_aerodyn_blade(blade_path, n_airfoils=len(airfoils))
        blades.append(cache[blade_path])
    return AeroDynInput(**v, airfoils=tuple(airfoils), blades=tuple(blades), extra=deck.extra(),
                        source=str(main_path))


def _resolve_name(deck: _Deck, name: str, line: int, key: str, what: str) -> Path:
    path = Path(name.replace("\\", "/"))
    path = path if path.is_absolute() else deck.path.parent / path
    if not path.is_file():
        raise OpenFASTFormatError(f"{deck.where(line, key)}: {what} not found: tried '{path}'. Fix "
                                  f"the file name in that line (relative paths start at the "
                                  f"directory of {deck.path.name}).")
    return path
