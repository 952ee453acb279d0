"""Read an OpenFAST SubDyn input file (SubDyn v1.01 layout of OpenFAST v5): the bottom-fixed frame.

SubDyn reads its file line by line in a fixed order (``SD_Input`` of ``SubDyn.f90``) and so does
:func:`read_subdyn` (:class:`~mbsym.wind.deck._lines._Lines`): simulation control (``SDdeltaT``,
``IntMethod``, ``SttcSolve``), the FEM and Craig–Bampton options (``FEMMod``, ``NDiv``, ``Nmodes``,
``JDampings``, ``GuyanDampMod``, ``RayleighDamp``, ``GuyanDampSize`` and its matrix), the rigid-body
position (floating structures only), the joints, base reaction joints, interface joints, members, the
six property tables (circular, rectangular, arbitrary beams, cables, rigid links, springs), cosine
matrices, concentrated masses, and the output options and channels.

Units are SI as in the file, except ``JDampings`` (% → fraction), ``MSpin`` and the rigid-body
angles (deg → rad). A file with a 4-column joint table is read as SubDyn's legacy layout (all joints
cantilever; no cable, rigid-link and spring tables), as SubDyn does.

What mbsym builds is what OpenFAST's SubDyn builds for a bottom-fixed structure with circular beams
(``MType`` ``1c``) on cantilever joints, all six DOFs locked at each reaction joint, one transition
piece (any number of interface joints tied to it) and ``FEMMod`` 1 (Euler–Bernoulli) or 3
(Timoshenko). Anything else the file asks for — SSI files, free or partially free reaction DOFs (and
hence floating structures), universal/pin/ball joints, rectangular, arbitrary-section, cable,
rigid-link or spring members, more than one transition piece — raises
:class:`~mbsym.exceptions.UnsupportedFeatureError` naming the file, line and key; a malformed file raises
:class:`~mbsym.exceptions.OpenFASTFormatError`. Property tables no member uses are read and kept, as
SubDyn reads and then ignores them; the output options only concern SubDyn's own files.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ...exceptions import OpenFASTFormatError, UnsupportedFeatureError
from ._format import _BOOL, _canon, _convert, _real
from ._lines import _Lines

__all__ = ["SubDynSettings", "SubDynJoint", "SubDynMember", "CircularSection", "ConcentratedMass", "read_subdyn"]

_DEG = math.pi / 180.0
_MEMBER_TYPES = {"1c": "1c", "1": "1c", "1r": "1r", "-1": "1r", "2": "2", "3": "3", "4": "4", "5": "5"}
_TYPE_NAMES = {"1r": "rectangular beam", "2": "cable", "3": "rigid link", "4": "arbitrary-section beam",
               "5": "spring"}
# (count key names, table attribute, columns per row (allowed counts)) of the property tables, in file order
_PROPERTY_TABLES = ((("NPropSets", "NPropSetsCyl", "NPropSetsBC"), "circular", (6,)),
                    (("NPropSets", "NPropSetsRec", "NPropSetsBR"), "rectangular", (7,)),
                    (("NXPropSets", "NPropSetsX"), "arbitrary", (11,)),
                    (("NCablePropSets", "NPropSetsC"), "cable", (4, 5)),
                    (("NRigidPropSets", "NPropSetsR"), "rigid", (2,)),
                    (("NSpringPropSets", "NPropSetsS"), "spring", (22,)))


@dataclass(frozen=True)
class SubDynJoint:
    """A joint: ID, position [m] (SubDyn's global frame, z up from MSL), type (1 cantilever, 2 universal,
    3 pin, 4 ball), joint direction [-] and stiffness [N m/rad] (non-cantilever joints only), file line."""

    id: int
    position: tuple[float, float, float]
    joint_type: int
    direction: tuple[float, float, float]
    stiffness: float
    line: int


@dataclass(frozen=True)
class SubDynMember:
    """A member: ID, joint IDs at ends 1 and 2, property-set IDs at ends 1 and 2, type (``"1c"`` circular
    beam, ``"1r"`` rectangular beam, ``"2"`` cable, ``"3"`` rigid link, ``"4"`` arbitrary beam,
    ``"5"`` spring), spin about its axis [rad] (beams) or cosine-matrix ID (springs), file line."""

    id: int
    joint1: int
    joint2: int
    prop1: int
    prop2: int
    member_type: str
    spin: float
    cosm_id: int | None
    line: int


@dataclass(frozen=True)
class CircularSection:
    """A circular (pipe) section: ID, Young's modulus E [Pa], shear modulus G [Pa], density [kg/m³],
    outer diameter [m], wall thickness [m] (0: solid), file line."""

    id: int
    young: float
    shear: float
    density: float
    diameter: float
    thickness: float
    line: int


@dataclass(frozen=True)
class ConcentratedMass:
    """A concentrated mass at a joint: mass [kg], inertia about its centre of mass in SubDyn's global
    axes (Jxx, Jyy, Jzz, Jxy, Jxz, Jyz) [kg m²] — the products are the tensor's off-diagonal entries
    as SubDyn adds them (``JMXY`` … of the file) — and the centre-of-mass offset from the joint [m]."""

    joint: int
    mass: float
    inertia: tuple[float, float, float, float, float, float]
    offset: tuple[float, float, float]
    line: int


@dataclass(frozen=True, eq=False)
class SubDynSettings:
    """SubDyn settings (see the module docstring). ``mode_damping`` are the ``Nmodes`` modal damping
    ratios as fractions (SubDyn's fill rule applied: the last value given repeats); ``n_modes`` < 0
    means "all modes" (full FEM). ``property_tables`` holds the rows of the rectangular, arbitrary,
    cable, rigid and spring tables (tuples of floats), ``cosine_matrices`` the COSM rows. ``lines``
    maps each key to its line number (for error messages)."""

    path: str
    time_step: float | str
    integration_method: int
    static_improvement: bool
    fem_model: int
    n_divisions: int
    n_modes: int
    mode_damping: tuple[float, ...]
    guyan_damping_model: int
    rayleigh_damping: tuple[float, float]
    guyan_damping_matrix: np.ndarray
    rigid_body_position: tuple[float, ...]
    joints: tuple[SubDynJoint, ...]
    reactions: tuple[int, ...]
    interfaces: tuple[int, ...]
    members: tuple[SubDynMember, ...]
    circular_sections: tuple[CircularSection, ...]
    property_tables: dict[str, tuple[tuple[float, ...], ...]]
    cosine_matrices: tuple[tuple[float, ...], ...]
    concentrated_masses: tuple[ConcentratedMass, ...]
    options: dict[str, Any]
    member_outputs: tuple[tuple[int, ...], ...]
    outputs: tuple[str, ...]
    lines: dict[str, int] = field(default_factory=dict)

    def joint(self, joint_id: int) -> SubDynJoint:
        """The joint with ID ``joint_id``."""
        return next(j for j in self.joints if j.id == joint_id)

    def section(self, prop_id: int) -> CircularSection:
        """The circular section with ID ``prop_id``."""
        return next(s for s in self.circular_sections if s.id == prop_id)


# ---------------------------------------------------------------------------------------------- line helpers
def _key(f: _Lines, names, kind: str = "float", check=None) -> Any:
    """``<value> <Key>`` where the key may be spelled as any of ``names`` (SubDyn ignores the name)."""
    names = (names,) if isinstance(names, str) else tuple(names)
    number, tokens = f._next(names[0])
    found = tokens[1].strip("\"'") if len(tokens) > 1 else "nothing"
    if _canon(found) not in {_canon(n) for n in names}:
        raise f.fail(number, names[0], f"expected '{names[0]}' after one value on this line, found {found!r}. A "
                     "line is missing, extra or out of order; compare with SubDyn's documented layout.")
    f.line_of[names[0]] = number
    value, error = _convert(kind, [tokens[0].strip("\"'")])
    if error is None and check is not None and value != "default" and not check[0](value):
        error = f"{check[1]}; got {tokens[0]}"
    if error is not None:
        f.problem(number, names[0], f"{error}. Fix the value in that line.")
        return None
    return value


def _values_then_key(f: _Lines, key: str) -> tuple[int, list[float]]:
    """A line of numbers followed by ``key`` (``JDampings``, ``RayleighDamp``); returns (line, numbers)."""
    number, tokens = f._next(key)
    j = next((j for j, t in enumerate(tokens) if _real(t) is None), len(tokens))
    if j == len(tokens) or _canon(tokens[j]).rstrip("s") != _canon(key).rstrip("s") or j == 0:
        raise f.fail(number, key, f"expected numbers then '{key}' on this line, got {' '.join(tokens)[:60]!r}. "
                     "A line is missing, extra or out of order; compare with SubDyn's documented layout.")
    f.line_of[key] = number
    return number, [_real(t) for t in tokens[:j]]


def _rows(f: _Lines, count: int | None, key: str, widths: tuple[int, ...]):
    """Two header lines, then ``count`` rows of one of ``widths`` numbers (optional trailing text).

    Returns (rows of floats, line numbers, trailing text of each row)."""
    f.skip(2, key)
    rows, lines, texts = [], [], []
    for r in range(count or 0):
        number, tokens = f._next(key)
        j = next((j for j, t in enumerate(tokens) if _real(t) is None), len(tokens))
        n = max((w for w in widths if w <= j), default=None)
        if n is None or (j > n and j not in widths):
            raise f.fail(number, key, f"row {r + 1} of {count}: expected {' or '.join(map(str, widths))} numbers, "
                         f"got {j} ({' '.join(tokens)[:70]!r}). Check the count '{key}' and the rows.")
        rows.append(tuple(_real(t) for t in tokens[:n]))
        lines.append(number)
        texts.append([t.strip("\"'") for t in tokens[n:]])
    return rows, lines, texts


def _int(value: float) -> int | None:
    return int(value) if value is not None and float(value).is_integer() else None


# ---------------------------------------------------------------------------------------------- sections
def _control(f: _Lines, out: dict) -> None:
    f.rule("SIMULATION CONTROL")
    _key(f, "Echo", "bool")
    out["time_step"] = _key(f, "SDdeltaT", "float|default", check=(lambda v: v > 0, "must be greater than 0"))
    out["integration_method"] = _key(f, "IntMethod", "int", check=(lambda v: 1 <= v <= 4, "must be 1, 2, 3 or 4"))
    number, tokens = f._next("SttcSolve")
    if len(tokens) < 2 or _canon(tokens[1]) != "sttcsolve":
        raise f.fail(number, "SttcSolve", f"expected 'SttcSolve' after one value, found {tokens[1:2]}.")
    f.line_of["SttcSolve"] = number
    text = tokens[0].lower()
    if text in _BOOL or text in ("0", "1"):
        out["static_improvement"] = _BOOL.get(text, text == "1")
    else:
        f.problem(number, "SttcSolve", f"expected True/False or 0/1, got {tokens[0]!r}. Fix the value in that line.")
        out["static_improvement"] = False


def _fem(f: _Lines, out: dict) -> None:
    f.rule("FEA and CRAIG-BAMPTON PARAMETERS")
    out["fem_model"] = _key(f, "FEMMod", "int", check=(lambda v: v in (1, 3), "must be 1 (Euler-Bernoulli) or 3 "
                                                       "(Timoshenko); SubDyn implements no other"))
    out["n_divisions"] = _key(f, "NDiv", "int", check=(lambda v: v >= 1, "must be a positive integer"))
    n_modes = _key(f, "Nmodes", "int")
    out["n_modes"] = 0 if n_modes is None else n_modes
    if n_modes is None or n_modes == 0:
        f._next("JDampings")  # a comment line for SubDyn when Nmodes = 0
        out["mode_damping"] = ()
    else:
        number, values = _values_then_key(f, "JDampings")
        wanted = n_modes if n_modes > 0 else 1
        if len(values) > wanted:
            f.problem(number, "JDampings", f"{len(values)} values for Nmodes = {n_modes}; SubDyn reads {wanted}. "
                      "Remove the extra values.")
        values = (values + [values[-1]] * wanted)[:wanted]  # SubDyn repeats the last value given
        out["mode_damping"] = tuple(v / 100.0 for v in values)
    number, tokens = f._next("GuyanDampMod")
    if len(tokens) < 2 or _canon(tokens[1]) != "guyandampmod" or _int(_real(tokens[0])) is None:
        raise f.fail(number, "GuyanDampMod", f"expected '<0, 1 or 2>  GuyanDampMod', got {' '.join(tokens)[:60]!r}. "
                     "The legacy layout without the Guyan damping lines is not read: add GuyanDampMod, "
                     "RayleighDamp, GuyanDampSize and the matrix rows (SubDyn v1.01 layout).")
    f.line_of["GuyanDampMod"] = number
    out["guyan_damping_model"] = _int(_real(tokens[0]))
    if out["guyan_damping_model"] not in (0, 1, 2):
        f.problem(number, "GuyanDampMod", f"must be 0 (none), 1 (Rayleigh) or 2 (6x6 matrix); got {tokens[0]}.")
    number, values = _values_then_key(f, "RayleighDamp")
    if len(values) != 2:
        f.problem(number, "RayleighDamp", f"expected 2 values (mass and stiffness coefficients), got {len(values)}.")
    out["rayleigh_damping"] = tuple((values + [0.0, 0.0])[:2])
    size = _key(f, "GuyanDampSize", "int", check=(lambda v: v >= 0, "must not be negative")) or 0
    matrix = np.array([f.numbers(size, "GuyanDampMat") for _ in range(size)]).reshape(size, size)
    if size != 6 and out["guyan_damping_model"] == 2:
        f.problem(f.line_of["GuyanDampSize"], "GuyanDampSize", f"is {size}; a bottom-fixed structure with one "
                  "transition piece needs a 6x6 Guyan damping matrix (SubDyn refuses other sizes). Set it to 6.")
    out["guyan_damping_matrix"] = matrix
    f.rule("INITIAL RIGID-BODY POSITION")
    f.skip(2, "RBSurge")
    values = f.numbers(6, "RBSurge")
    out["rigid_body_position"] = tuple(values[:3]) + tuple(v * _DEG for v in values[3:])


def _joints(f: _Lines, out: dict, unsupported: list) -> bool:
    f.rule("STRUCTURE JOINTS")
    n = _key(f, "NJoints", "int", check=(lambda v: v >= 2, "must be at least 2"))
    rows, lines, _ = _rows(f, n, "NJoints", (4, 9))
    legacy = bool(rows) and len(rows[0]) == 4
    joints = []
    for row, line in zip(rows, lines):
        if len(row) != len(rows[0]):
            f.problem(line, "NJoints", f"joint row has {len(row)} numbers but the first row {len(rows[0])}. "
                      "Give every joint 9 columns (or 4 in the legacy layout).")
            continue
        kind = 1 if legacy else _int(row[4])
        joint = SubDynJoint(_int(row[0]), tuple(row[1:4]), kind, (0.0, 0.0, 0.0) if legacy else tuple(row[5:8]),
                            0.0 if legacy else row[8], line)
        if joint.id is None or kind not in (1, 2, 3, 4):
            f.problem(line, "JointID", "JointID must be an integer and JointType 1, 2, 3 or 4. Fix the row.")
        elif kind != 1:
            unsupported.append((line, "JointType", f"joint {joint.id} is a {('universal', 'pin', 'ball')[kind - 2]} "
                                "joint; mbsym builds cantilever joints (JointType 1) only. Use 1."))
        elif joint.stiffness > 0:
            f.problem(line, "JointStiff", f"joint {joint.id} is cantilever but JointStiff = {joint.stiffness}; SubDyn "
                      "refuses additional stiffness at cantilever joints. Set it to 0.")
        joints.append(joint)
    out["joints"] = tuple(joints)
    return legacy


def _reactions(f: _Lines, out: dict, unsupported: list) -> None:
    f.rule("BASE REACTION JOINTS")
    n = _key(f, "NReact", "int", check=(lambda v: v >= 0, "must not be negative"))
    rows, lines, texts = _rows(f, n, "NReact", (1, 7))
    if n == 0:
        unsupported.append((f.line_of["NReact"], "NReact", "no reaction joint: a floating structure. mbsym builds "
                            "bottom-fixed SubDyn structures only (all six DOFs locked at each reaction joint)."))
    out["reactions"] = tuple(_int(r[0]) for r in rows)
    for row, line, text in zip(rows, lines, texts):
        flags = [_int(v) for v in row[1:]]
        if any(v not in (0, 1) for v in flags):
            f.problem(line, "RctTDXss", f"reaction flags must be 1 (locked) or 0 (free); got {row[1:]}.")
        elif 0 in flags:
            unsupported.append((line, "RctTDXss", f"reaction joint {_int(row[0])} has free DOFs {row[1:]}; mbsym "
                                "builds bottom-fixed structures with all six DOFs locked (1 1 1 1 1 1)."))
        if text and text[0] not in ("", "-"):
            unsupported.append((line, "SSIfile", f"reaction joint {_int(row[0])} names the SSI file {text[0]!r}; "
                                "soil-structure interaction matrices are not modelled. Remove the file name."))


def _interfaces(f: _Lines, out: dict, unsupported: list) -> None:
    f.rule("INTERFACE JOINTS")
    n = _key(f, "NInterf", "int", check=(lambda v: v >= 1, "must be at least 1"))
    rows, lines, _ = _rows(f, n, "NInterf", (8,))
    out["interfaces"] = tuple(_int(r[0]) for r in rows)
    tps = {_int(r[1]) for r in rows}
    for row, line in zip(rows, lines):
        if any(_int(v) != 1 for v in row[2:]):
            f.problem(line, "ItfTDXss", "all six interface DOF flags must be 1 (locked to the transition piece): "
                      f"SubDyn implements no other; got {row[2:]}.")
    if rows and (len(tps) > 1 or not tps <= {0, 1}):
        unsupported.append((lines[0], "TPID", f"the interface joints name transition pieces {sorted(tps)}; mbsym "
                            "builds one transition piece (all TPID 1)."))


def _members(f: _Lines, out: dict, unsupported: list) -> None:
    f.rule("MEMBERS")
    n = _key(f, "NMembers", "int", check=(lambda v: v >= 1, "must be at least 1"))
    f.skip(2, "NMembers")
    members = []
    for r in range(n or 0):
        number, tokens = f._next("NMembers")
        kind = _MEMBER_TYPES.get(tokens[5].lower()) if len(tokens) >= 7 else None
        ints = [_int(_real(t)) for t in tokens[:5]]
        if kind is None or None in ints:
            raise f.fail(number, "NMembers", f"member row {r + 1} of {n}: expected 'MemberID MJointID1 MJointID2 "
                         "MPropSetID1 MPropSetID2 MType MSpin/COSMID' (MType 1c, 1r, 2, 3, 4 or 5), got "
                         f"{' '.join(tokens)[:70]!r}.")
        last = _real(tokens[6])
        if last is None or (kind == "5" and _int(last) is None):
            f.problem(number, "MSpin", f"member {ints[0]}: expected a number (MSpin [deg], or COSMID for springs), "
                      f"got {tokens[6]!r}.")
            last = 0.0
        spin = last * _DEG if kind in ("1c", "1r", "4") else 0.0
        members.append(SubDynMember(*ints, kind, spin, _int(last) if kind == "5" else None, number))
        if kind != "1c":
            unsupported.append((number, "MType", f"member {ints[0]} is a {_TYPE_NAMES[kind]} (MType {tokens[5]}); "
                                "mbsym builds circular beams (MType 1c) only."))
    out["members"] = tuple(members)


def _properties(f: _Lines, out: dict, legacy: bool) -> None:
    tables = {}
    rules = iter(("CIRCULAR BEAM CROSS-SECTION PROPERTIES", "RECTANGULAR BEAM CROSS-SECTION PROPERTIES",
                  "ARBITRARY BEAM CROSS-SECTION PROPERTIES", "CABLE PROPERTIES", "RIGID LINK PROPERTIES",
                  "SPRING ELEMENT PROPERTIES"))
    for names, name, widths in _PROPERTY_TABLES[:3] if legacy else _PROPERTY_TABLES:
        f.rule(next(rules))
        count = _key(f, names, "int", check=(lambda v: v >= 0, "must not be negative"))
        f.line_of.setdefault(f"table:{name}", f.line_of[names[0]])
        rows, lines, _ = _rows(f, count, names[0], widths)
        tables[name] = (rows, lines)
    rows, lines = tables.pop("circular")
    out["circular_sections"] = tuple(CircularSection(_int(r[0]), *r[1:], line) for r, line in zip(rows, lines))
    out["property_tables"] = {k: tuple(v[0]) for k, v in tables.items()}
    f.rule("MEMBER COSINE MATRICES")
    count = _key(f, "NCOSMs", "int", check=(lambda v: v >= 0, "must not be negative"))
    out["cosine_matrices"] = tuple(_rows(f, count, "NCOSMs", (10,))[0])


def _masses(f: _Lines, out: dict) -> None:
    f.rule("JOINT ADDITIONAL CONCENTRATED MASSES")
    count = _key(f, "NCmass", "int", check=(lambda v: v >= 0, "must not be negative"))
    rows, lines, _ = _rows(f, count, "NCmass", (5, 11))
    masses = []
    for row, line in zip(rows, lines):
        full = tuple(row) + (0.0,) * (11 - len(row))  # 5 columns: SubDyn's legacy form, no products, no offset
        masses.append(ConcentratedMass(_int(full[0]), full[1], tuple(full[2:8]), tuple(full[8:11]), line))
        if masses[-1].joint is None or masses[-1].joint <= 0:
            f.problem(line, "CMJointID", f"invalid joint ID {full[0]}.")
        if full[1] < 0:
            f.problem(line, "JMass", f"negative mass {full[1]} kg.")
    out["concentrated_masses"] = tuple(masses)


def _outputs(f: _Lines, out: dict) -> None:
    f.rule("OUTPUT: SUMMARY & OUTFILE")
    options = {"SumPrint": _key(f, "SumPrint", "bool")}
    keep = f.i
    _, tokens = f._next("OutCBModes")
    f.i = keep
    if len(tokens) > 1 and _canon(tokens[1]) == "outcbmodes":  # optional in SubDyn (legacy files lack them)
        options["OutCBModes"] = _key(f, "OutCBModes", "int")
        options["OutFEMModes"] = _key(f, "OutFEMModes", "int")
    for key, kind in (("OutCOSM", "bool"), ("OutAll", "bool"), ("OutSwtch", "int"), ("TabDelim", "bool"),
                      ("OutDec", "int"), ("OutFmt", "str"), ("OutSFmt", "str")):
        options[key] = _key(f, key, kind, check=(lambda v: v in (1, 2, 3), "must be 1, 2 or 3")
                            if key == "OutSwtch" else None)
    out["options"] = options
    f.rule("MEMBER OUTPUT LIST")
    count = _key(f, "NMOutputs", "int", check=(lambda v: 0 <= v <= 99, "must be 0 to 99")) or 0
    f.skip(2, "NMOutputs")
    rows = []
    for _ in range(count):
        number, tokens = f._next("NMOutputs")
        values = [_int(_real(t)) for t in tokens]
        k = values[1] if len(values) > 1 and values[1] is not None else -1
        if not 1 <= k <= 9 or len(values) < 2 + k or None in values[:2 + k]:
            raise f.fail(number, "NMOutputs", f"expected 'MemberID NOutCnt NodeCnt...' with 1 <= NOutCnt <= 9 node "
                         f"numbers, got {' '.join(tokens)[:60]!r}.")
        rows.append(tuple(values[:2 + k]))
    out["member_outputs"] = tuple(rows)
    f.rule("SSOutList")
    out["outputs"] = tuple(name for item in f.outlist() for name in re.split(r"[,\s]+", item) if name)


def _cross_check(f: _Lines, out: dict, unsupported: list) -> None:
    """IDs that must exist and be unique, as SubDyn checks them (file line of the referring row)."""
    joints = {}
    for joint in out["joints"]:
        if joint.id in joints:
            f.problem(joint.line, "JointID", f"joint ID {joint.id} also on line {joints[joint.id].line}. "
                      "Make IDs unique.")
        joints.setdefault(joint.id, joint)
    sections = {}
    for section in out["circular_sections"]:
        if section.id in sections:
            f.problem(section.line, "PropSetID", f"property set {section.id} defined twice. Make IDs unique.")
        sections.setdefault(section.id, section)
    where = f.line_of
    for key, ids in (("NReact", out["reactions"]), ("NInterf", out["interfaces"])):
        for joint in ids:
            if joint not in joints:
                f.problem(where[key], key, f"joint {joint} is not in the joint table ({sorted(joints)}).")
    both = set(out["reactions"]) & set(out["interfaces"])
    if both:
        f.problem(where["NInterf"], "NInterf", f"joints {sorted(both)} are both reaction and interface joints.")
    used, seen = set(), {}
    for member in out["members"]:
        if member.id in seen:
            f.problem(member.line, "MemberID", f"member ID {member.id} also on line {seen[member.id]}.")
        seen.setdefault(member.id, member.line)
        for joint in (member.joint1, member.joint2):
            if joint not in joints:
                f.problem(member.line, "MJointID1", f"member {member.id} names joint {joint}, not in the joint table.")
        used |= {member.joint1, member.joint2}
        if member.joint1 == member.joint2:
            f.problem(member.line, "MJointID2", f"member {member.id} starts and ends at joint {member.joint1}.")
        elif member.joint1 in joints and member.joint2 in joints and \
                math.dist(joints[member.joint1].position, joints[member.joint2].position) == 0.0:
            f.problem(member.line, "MJointID2", f"member {member.id} has zero length (its joints coincide).")
        if member.member_type != "1c":
            continue
        props = [sections.get(member.prop1), sections.get(member.prop2)]
        for pid, prop in zip((member.prop1, member.prop2), props):
            if prop is None:
                f.problem(member.line, "MPropSetID1", f"member {member.id} names property set {pid}, not in the "
                          f"circular cross-section table ({sorted(sections)}).")
        if None not in props and any(not math.isclose(getattr(props[0], a), getattr(props[1], a), rel_tol=1e-9)
                                     for a in ("young", "shear", "density")):
            f.problem(member.line, "MPropSetID2", f"member {member.id}: E, G and density differ between property sets "
                      f"{member.prop1} and {member.prop2}; SubDyn requires the same material at both ends.")
    for joint in joints.values():
        if joint.id not in used:
            f.problem(joint.line, "JointID", f"joint {joint.id} belongs to no member. Remove it or connect it.")
    for mass in out["concentrated_masses"]:
        if mass.joint is not None and mass.joint not in joints:
            f.problem(mass.line, "CMJointID", f"concentrated mass at joint {mass.joint}, not in the joint table.")
    for row in out["member_outputs"]:
        if row[0] not in seen or any(not 1 <= k <= out["n_divisions"] + 1 for k in row[2:]):
            f.problem(where["NMOutputs"], "NMOutputs", f"member output {row}: the member must exist and the node "
                      f"numbers be 1 to NDiv + 1 = {out['n_divisions'] + 1} (SubDyn refuses others).")


def read_subdyn(path: str | Path) -> SubDynSettings:
    """Read a SubDyn input file (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The SubDyn ``.dat`` file.

    Returns
    -------
    SubDynSettings

    Raises
    ------
    OpenFASTFormatError
        Missing file, a line out of order (the expected key and the one found), a malformed number or
        switch, a table row with the wrong number of columns, an ID that does not exist or is not
        unique; names the file, line and key.
    UnsupportedFeatureError
        The file asks for what mbsym does not build (module docstring); names the file, line and key.

    Examples
    --------
    >>> from mbsym.wind.deck.subdyn import read_subdyn
    >>> sd = read_subdyn("IEA-15-240-RWT-Monopile_SubDyn.dat")  # doctest: +SKIP
    >>> sd.fem_model, len(sd.joints), sd.interfaces, sd.concentrated_masses[0].mass  # doctest: +SKIP
    (3, 19, (19,), 100000.0)
    """
    f = _Lines(Path(path), "SubDyn input file")
    out: dict[str, Any] = {}
    unsupported: list[tuple[int, str, str]] = []
    _control(f, out)
    _fem(f, out)
    legacy = _joints(f, out, unsupported)
    _reactions(f, out, unsupported)
    _interfaces(f, out, unsupported)
    _members(f, out, unsupported)
    _properties(f, out, legacy)
    _masses(f, out)
    _outputs(f, out)
    f.raise_problems()
    _cross_check(f, out, unsupported)
    f.raise_problems()
    if unsupported:
        text = [f"{f.path}, line {line}, key '{key}': {what}" for line, key, what in unsupported]
        many = f"{len(text)} unsupported SubDyn options in {f.path}:\n  - " + "\n  - ".join(text)
        raise UnsupportedFeatureError(text[0] if len(text) == 1 else many)
    return SubDynSettings(**out, path=str(f.path), lines=dict(f.line_of))


def _format_error(settings: SubDynSettings, key: str, text: str) -> OpenFASTFormatError:
    """An :class:`OpenFASTFormatError` naming the settings' file and the line of ``key`` (for later checks)."""
    return OpenFASTFormatError(f"{settings.path}, line {settings.lines.get(key, '?')}, key '{key}': {text}")
