"""What mbsym does with every MoorDyn OPTIONS entry and line-type column (OpenFAST v5.0.0, MoorDyn v2.3.8).

MoorDyn reads its options as ``<value> <key>`` lines (the rest of a line is a comment); the key is
compared in upper case, so ``rhoW``, ``RHOW`` and ``rhow`` are one option, and a later line wins.
An unknown key is not an error for MoorDyn: it warns ("Unable to interpret input ... in OPTIONS
section") and goes on. The full list (``MD_Init`` in modules/moordyn/src/MoorDyn.f90) and what the
quasi-static mooring of :func:`~mbsym.wind.offshore.mooring.mooring_from_moordyn` does with it:

=============================  ==========================================================================
Option (aliases)               What mbsym does
=============================  ==========================================================================
g                              modelled: the lines' weight (overrides the .fst's ``Gravity``, as in MoorDyn)
rhoW (rho)                     modelled: buoyancy, drag, added mass (overrides SeaState's ``WtrDens``)
WtrDpth (depth, WaterDepth)    a number: the seabed depth (overrides SeaState's ``WtrDpth``); every anchor
                               must lie on it (the catenaries lay their resting part at the anchor's
                               depth), else refused. Letters in it name a bathymetry file: refused
WaterKin                       refused when given (waves and current on the lines, from SeaState with
                               ``SEASTATE`` or from a file); a number is a MoorDyn error
mu_kT, mu_kA                   refused when > 0 (seabed friction on moving lines); 0 (default) accepted
mc, cv (FricDamp)              accepted: they shape the friction of mu_kT/mu_kA, which is 0 or refused
kBot (kb), cBot (cb)           kBot: the resting nodes' sinking in the lumped lines at rest (the default
                               of MoorDyn decks; the continuous catenaries lie on a rigid seabed); cBot:
                               named in the ModelWarning; ``kBot <= 0`` (no seabed in MoorDyn) refused
dtM, tScheme, dtIC, TmaxIC,    accepted (noted in the ModelWarning): MoorDyn's own time integration and its
CdScaleIC, threshIC            dynamic relaxation to the initial equilibrium; quasi-static lines are in
                               equilibrium. ``tScheme`` other than RK2/RK4 is a MoorDyn error
writeLog, dtOut, OutSwitch,    accepted: log file, output interval, output file switch, console printing
disableOutTime
inertialF, inertialF_rampT     accepted: they act on coupled bodies and rods only, which are refused
anything else                  a ModelWarning naming file, line and key (MoorDyn warns and ignores it):
                               e.g. ``WaveKin``, ``Currents``, ``ICgenDynamic``, ``disableOutput`` of the
                               stand-alone C++ MoorDyn are not read by OpenFAST's MoorDyn
=============================  ==========================================================================

Line-type columns (MoorDyn reads 10, 11 or 13 by position: ``Name Diam MassDen EA BA/-zeta EI Cd Ca
CdAx CaAx [Cl [dF cF]]``): Diam, MassDen, EA, Cd, Ca, CdAx, CaAx are modelled; EA with ``|`` (visco-elastic)
or letters (a stiffness curve file) is refused; BA/-zeta (internal damping) and EI > 0 (bending stiffness)
are named in the ModelWarning; Cl > 0 (vortex-induced vibration) is refused, dF and cF act only with it.
Points: M, V, CdA of a vessel (coupled) point add weight, buoyancy, inertia and drag at the fairlead in
MoorDyn (``Point_DoRHS``): refused when not 0 (CA needs V); on fixed points they do nothing. A Z naming
the seabed (``seabed``, ``ground``, ``floor``) puts an anchor at MoorDyn's depth (modelled). The lines'
``Outputs`` flags only choose MoorDyn's output files.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

__all__ = ["MOORDYN_OPTIONS", "MoorDynEnvironment", "moordyn_environment", "moordyn_option_problems",
           "moordyn_options", "option_format_problems"]

#: Every option key OpenFAST v5's MoorDyn reads (upper case, as it compares them) → (canonical name, value kind).
MOORDYN_OPTIONS: dict[str, tuple[str, str]] = {
    "WRITELOG": ("writeLog", "int"), "DTM": ("dtM", "real"), "TSCHEME": ("tScheme", "text"),
    "G": ("g", "real"), "RHOW": ("rhoW", "real"), "RHO": ("rhoW", "real"),
    "WTRDPTH": ("WtrDpth", "text"), "DEPTH": ("WtrDpth", "text"), "WATERDEPTH": ("WtrDpth", "text"),
    "KBOT": ("kBot", "real"), "KB": ("kBot", "real"), "CBOT": ("cBot", "real"), "CB": ("cBot", "real"),
    "DTIC": ("dtIC", "real"), "TMAXIC": ("TmaxIC", "real"), "CDSCALEIC": ("CdScaleIC", "real"),
    "THRESHIC": ("threshIC", "real"), "WATERKIN": ("WaterKin", "text"), "DTOUT": ("dtOut", "real"),
    "MU_KT": ("mu_kT", "real"), "MU_KA": ("mu_kA", "real"), "MC": ("mc", "real"),
    "CV": ("cv", "real"), "FRICDAMP": ("cv", "real"), "INERTIALF": ("inertialF", "int"),
    "INERTIALF_RAMPT": ("inertialF_rampT", "real"), "OUTSWITCH": ("OutSwitch", "int"),
    "DISABLEOUTTIME": ("disableOutTime", "int")}
#: Options of MoorDyn's own integration and initial-condition relaxation (no effect on quasi-static lines).
NUMERICAL = ("dtM", "tScheme", "dtIC", "TmaxIC", "CdScaleIC", "threshIC")
#: MoorDyn's test for "a file name, not a number" (``setupBathymetry``, ``getCoefficientOrCurve``): any letter
#: but e/E (exponents).
_LETTERS = re.compile(r"[a-df-zA-DF-Z]")
_INT = re.compile(r"[+-]?\d+$")
_REAL = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")
#: An anchor this far [m] from MoorDyn's seabed is not on it.
SEABED_TOLERANCE = 0.01


def _unquote(text: str) -> str:
    return text.strip("\"'")


def _number(text: str) -> float:
    return float(text.replace("d", "e").replace("D", "E"))


def option_format_problems(path, entries) -> list[str]:
    """Option lines MoorDyn cannot read (it stops with an error): fewer than two words, a value of the wrong
    kind for a known key, ``tScheme`` other than RK2/RK4, a numeric ``WaterKin``.

    ``entries``: ``(line number, words)`` of the OPTIONS section's lines.
    """
    out = []
    for number, words in entries:
        if len(words) < 2:
            out.append(f"{path}, line {number}: an OPTIONS line needs '<value> <key>'; got {' '.join(words)!r}. "
                       "Give both (MoorDyn stops with 'Failed to read options').")
            continue
        value, key = _unquote(words[0]), words[1].upper()[:20]   # MoorDyn keeps 20 characters of the key
        name, kind = MOORDYN_OPTIONS.get(key, (None, None))
        if (kind == "int" and not _INT.match(value)) or (kind == "real" and not _REAL.match(value)):
            expected = "an integer" if kind == "int" else "a number"
            out.append(f"{path}, line {number}, option '{words[1]}': expected {expected}, got {value!r}. Fix it.")
        elif name == "tScheme" and value.upper() not in ("RK2", "RK4"):
            out.append(f"{path}, line {number}, option '{words[1]}': MoorDyn in OpenFAST knows only RK2 and RK4; "
                       f"got {value!r}.")
        elif name == "WaterKin" and not _LETTERS.search(value):
            out.append(f"{path}, line {number}, option '{words[1]}': MoorDyn takes 'SEASTATE' or a water-kinematics "
                       f"file name here, not the number {value!r}; remove the line for still water.")
    return out


def moordyn_options(md) -> dict[str, tuple[int, str, str]]:
    """The known options of a :class:`~mbsym.wind.deck.moordyn.MoorDynInput`: canonical name → (line, key as
    written, value as written, unquoted); aliases and case folded, the last line winning as in MoorDyn."""
    out = {}
    for number, key, value in md.option_entries:
        name = MOORDYN_OPTIONS.get(key.upper()[:20], (None,))[0]
        if name is not None:
            out[name] = (number, key, _unquote(value))
    return out


@dataclass(frozen=True)
class MoorDynEnvironment:
    """Water density [kg/m³], gravity [m/s²] and seabed depth [m] (None: not known) MoorDyn uses, and where
    each comes from (``"the .fst"`` or ``"<file>, line <n> (<key>)"``)."""

    water_density: float
    gravity: float
    water_depth: float | None
    sources: dict


def moordyn_environment(md, *, water_density: float, gravity: float,
                        water_depth: float | None = None) -> MoorDynEnvironment:
    """What MoorDyn uses for ρ, g and the depth: the file's ``rhoW``/``g``/``WtrDpth`` options, else the glue
    code's values (OpenFAST v5 ``FAST_Subs.f90`` passes the .fst's ``Gravity`` and SeaState's ``WtrDens`` and
    ``WtrDpth``; ``MD_Init`` sets them as defaults before reading the options). A bathymetry file keeps the
    given depth here (:func:`moordyn_option_problems` refuses it).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> md = SimpleNamespace(path="md.dat", option_entries=((30, "rho", "1030"),))
    >>> moordyn_environment(md, water_density=1025.0, gravity=9.81).water_density
    1030.0
    """
    opts = moordyn_options(md)
    values = {"water_density": water_density, "gravity": gravity, "water_depth": water_depth}
    sources = {k: "the .fst / SeaState" for k in values}
    for name, attr in (("rhoW", "water_density"), ("g", "gravity"), ("WtrDpth", "water_depth")):
        if name in opts and not _LETTERS.search(opts[name][2]):
            values[attr] = _number(opts[name][2])
            sources[attr] = f"{md.path}, line {opts[name][0]} ({opts[name][1]})"
    return MoorDynEnvironment(float(values["water_density"]), float(values["gravity"]),
                              None if values["water_depth"] is None else float(values["water_depth"]), sources)


def _option_problems(md, opts: dict) -> tuple[list[str], list[str]]:
    refused, notes = [], []

    def where(name):
        return f"{md.path}, line {opts[name][0]}, option '{opts[name][1]}'"

    if "WtrDpth" in opts and _LETTERS.search(opts["WtrDpth"][2]):
        refused.append(f"{where('WtrDpth')}: {opts['WtrDpth'][2]!r} names a bathymetry file (a seabed of varying "
                       "depth); mbsym's catenaries lie on a flat seabed at the anchors. Give the depth as a number.")
    if "WaterKin" in opts:
        refused.append(f"{where('WaterKin')}: {opts['WaterKin'][2]!r} puts waves and current on the mooring lines "
                       "(MoorDyn's setupWaterKin); mbsym's lines are in still water. Remove the line.")
    for name in ("mu_kT", "mu_kA"):
        if name in opts and _number(opts[name][2]) > 0:
            refused.append(f"{where(name)}: seabed friction {opts[name][2]} on moving lines is not modelled by the "
                           "quasi-static catenaries; set it to 0 (MoorDyn's default).")
    if "kBot" in opts and _number(opts["kBot"][2]) <= 0:
        refused.append(f"{where('kBot')}: a seabed stiffness {opts['kBot'][2]} lets MoorDyn's lines sink through "
                       "the seabed; mbsym lays them on a rigid seabed. Give a positive kBot (default 3e6 Pa/m).")
    numerical = [n for n in NUMERICAL if n in opts]
    if numerical:
        notes.append(f"MoorDyn's integration and initial-condition settings ({', '.join(numerical)}) do not apply "
                     "to quasi-static lines")
    for number, key, _ in md.option_entries:
        if key.upper()[:20] not in MOORDYN_OPTIONS:
            notes.append(f"option '{key}' (line {number}) is unknown to OpenFAST v5's MoorDyn, which warns and "
                         "ignores it; so does mbsym")
    return refused, notes


def _type_problems(md) -> tuple[list[str], list[str]]:
    refused, notes, stiff = [], [], []
    used = sorted({entry.line_type for entry in md.lines.values()})
    for name in used:
        kind = md.line_types[name]
        at = f"{md.path}, line {kind.line}, line type '{name}'"
        if isinstance(kind.axial_stiffness, str):
            what = "visco-elastic" if "|" in kind.axial_stiffness else "a tension-strain curve file"
            refused.append(f"{at}: EA {kind.axial_stiffness!r} is {what}; mbsym's catenaries take one constant "
                           "EA. Give a number.")
        extra = tuple(getattr(kind, "extra_columns", ()))
        if extra and isinstance(extra[0], float) and extra[0] > 0:
            refused.append(f"{at}: Cl = {extra[0]} switches on MoorDyn's vortex-induced vibration, not modelled; "
                           "set Cl to 0 or drop the Cl, dF, cF columns.")
        if isinstance(kind.bending_stiffness, str) or kind.bending_stiffness > 0:
            stiff.append(name)
    if stiff:
        notes.append(f"bending stiffness EI of line type(s) {', '.join(stiff)} (the catenaries are perfectly flexible)")
    for ident, point in sorted(md.points.items()):
        if point.kind in ("vessel", "coupled") and point.position[2] == "seabed":
            refused.append(f"{md.path}, line {point.line}: vessel point {ident} is placed on the seabed; a fairlead "
                           "needs its z relative to the platform reference point. Give a number.")
        elif point.kind in ("vessel", "coupled") and any(v != 0 for v in (point.mass, point.volume, point.drag_area)):
            refused.append(f"{md.path}, line {point.line}: vessel point {ident} has M = {point.mass}, V = "
                           f"{point.volume}, CdA = {point.drag_area}; MoorDyn adds their weight, buoyancy, inertia and "
                           "drag at the fairlead, which mbsym does not. Set them to 0 (or model them on the platform).")
    return refused, notes


def _seabed_problems(md, env: MoorDynEnvironment) -> list[str]:
    if env.water_depth is None:
        return []
    out = []
    for ident, point in sorted(md.points.items()):
        z = point.position[2]
        if point.kind == "fixed" and isinstance(z, (int, float)) and abs(z + env.water_depth) > SEABED_TOLERANCE:
            out.append(f"{md.path}, line {point.line}: anchor {ident} is at z = {z} m, but MoorDyn's seabed is at "
                       f"{-env.water_depth} m (depth from {env.sources['water_depth']}); mbsym's catenaries lay "
                       "their resting part at the anchor's depth. Put the anchor on the seabed.")
    return out


def moordyn_option_problems(md, env: MoorDynEnvironment | None = None) -> tuple[list[str], list[str]]:
    """What the quasi-static mooring refuses and what it notes about a MoorDyn deck (see the module docstring).

    Parameters
    ----------
    md : MoorDynInput
        The deck (:func:`~mbsym.wind.deck.moordyn.read_moordyn`).
    env : MoorDynEnvironment, optional
        The ρ, g and depth MoorDyn uses (:func:`moordyn_environment`); with a depth, every anchor must lie on
        the seabed.

    Returns
    -------
    refused : list of str
        One message per option, line type or point the model cannot honour (file, line, key, the fix).
    notes : list of str
        Clauses for the mooring's ModelWarning: numerical options accepted, unknown options ignored (as
        MoorDyn does), bending stiffness not modelled.
    """
    refused, notes = _option_problems(md, moordyn_options(md))
    more, extra = _type_problems(md)
    seabed = [] if env is None else _seabed_problems(md, env)
    return refused + more + seabed, notes + extra
