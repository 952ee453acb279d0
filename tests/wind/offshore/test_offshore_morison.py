"""Viscous drag on potential-flow Morison members (mbsym.wind.offshore.morison; issue 20, item 2).

References, each independent of the code under test:
- closed forms of the drag ``½ ρ C_d D |v_n| v_n`` on a cylinder in uniform relative flow (its resultant and its
  moment about the reference point), of the wet length of a member crossing the still-water line, of the end
  plate's ``¼ ρ C_{d,ax} A v²`` (``AxFDMod`` 0) and its one-sided ``½ ρ C_{d,ax} A v²`` (1), of the axial drag of a
  tapered member; only the flow across a member drags it;
- an invariant: the drag dissipates (``−q̇ᵀF ≥ 0``) for any platform velocity;
- OpenFAST v5.0.0 free decays of the shared ``fl_decay_a`` (surge 10 m, heave 1.5 m, pitch 4°, still water, 300 s)
  with the deck's ``AddBQuad`` set to zero and drag-only members added (:func:`write_deck`; tests/data/
  openfast_morison/README.md): ``columns`` (the VolturnUS-S's four columns, heave-plate end drag) and ``braces``
  (plus a tapered centre column, three inclined braces with member-based coefficients, one-sided end drag) and
  ``growth`` (the columns with marine growth and depth-based coefficients on the outer ones).
  Measured ε: surge, heave, pitch 0.3–0.5 %, against 3–6 % with the members left out: bound 1.5 %.
"""

from __future__ import annotations

import csv
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ParameterError
from mbsym.wind.deck.hydrodyn import read_hydrodyn
from mbsym.wind.offshore.morison import morison_drag, morison_problems

from .conftest import FLOATING

CASE = FLOATING / "cases" / "fl_decay_a"
DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_morison"
RHO = 1025.0
needs_deck = pytest.mark.skipif(not CASE.is_dir(), reason=f"shared floating deck not found at {CASE}")

_R, _A, _B = 51.75, 25.875, 44.81681          # VolturnUS-S outer columns (Allen et al. 2020, Table 3)
_COLUMNS = [(0, 0, -20), (0, 0, 15), (-_R, 0, -20), (-_R, 0, 15), (_A, _B, -20), (_A, _B, 15), (_A, -_B, -20),
            (_A, -_B, 15)]
_BRACES = [(-5, 0, -12), (-46.75, 0, -6), (2.5, 4.33, -12), (23.375, 40.49, -6), (2.5, -4.33, -12),
           (23.375, -40.49, -6)]


#: Strip-theory members (``PropPot = FALSE``) added to the shared ``fl_decay_a`` (the ``none`` deck of
#: test_offshore_morison.write_deck): joints (x, y, z) [m] with axial coefficient set 2, property sets (D [m]), members.
STRIP_JOINTS = [(-30, 20, -25), (30, 20, -25), (10, -35, -30), (10, 25, -18), (-20, -20, -35), (-20, -20, -15)]
STRIP_SECTION = {
    "NAxCoef": ["1  0.00 0.00 1.00 0 0.00 1.00", "2  0.00 1.00 1.00 0 0.00 1.00"],
    "NJoints": [f"{n + 1}  {x} {y} {z}  2  0" for n, (x, y, z) in enumerate(STRIP_JOINTS)],
    "NPropSetsCyl": ["1  3.0  0.05", "2  2.0  0.05", "3  4.0  0.05"],
    "NMembers": ["1  1  2  1  1  1  0  2.0  1  1  FALSE", "2  3  4  1  2  1  0  2.0  1  1  FALSE",
                 "3  5  6  3  3  1  0  1.0  1  1  FALSE"],
}
#: ``piercing``: the ``strip`` members and two more through the still-water level (a vertical column, D 6 m, and an
#: inclined tapered member, D 2.5 → 2 m).
PIERCING_JOINTS = [(25, -25, -18), (25, -25, 10), (-35, -5, -12), (-30, 5, 10)]
PIERCING_SECTION = {
    "NAxCoef": STRIP_SECTION["NAxCoef"],
    "NJoints": STRIP_SECTION["NJoints"] + [f"{n + 7}  {x} {y} {z}  2  0"
                                           for n, (x, y, z) in enumerate(PIERCING_JOINTS)],
    "NPropSetsCyl": STRIP_SECTION["NPropSetsCyl"] + ["4  6.0  0.05", "5  2.5  0.05", "6  2.0  0.05"],
    "NMembers": STRIP_SECTION["NMembers"] + ["4  7  8  4  4  1  0  1.0  1  1  FALSE",
                                             "5  9  10  5  6  1  0  1.0  1  1  FALSE"],
}
#: ``morison_only``: no potential flow (``PotMod`` 0); the VolturnUS-S as strip-theory members: the centre column
#: (D 10 m) and three outer columns (D 12.5 m, 51.75 m out), z −20 to +15 m, and three pontoons of the rectangles'
#: area (D 10.55 m, centre at z −14.725 m) between the columns' walls; end plates with axial C_a 1 (set 2).
_PONTOON_Z, _PONTOON_D = -14.725, 10.55
MORISON_ONLY_SECTION = {
    "NAxCoef": ["1  0.00 0.00 1.00 0 0.00 1.00", "2  0.00 1.00 1.00 0 0.00 1.00"],
    "NJoints": [f"{n + 1}  {x} {y} {z}  2  0" for n, (x, y, z) in enumerate(
        [(0, 0, -20), (0, 0, 15), (-51.75, 0, -20), (-51.75, 0, 15), (25.875, 44.81681, -20), (25.875, 44.81681, 15),
         (25.875, -44.81681, -20), (25.875, -44.81681, 15)]
        + [(c * r, s * r, _PONTOON_Z) for c, s in ((-1.0, 0.0), (0.5, 0.8660254), (0.5, -0.8660254))
           for r in (5.0, 45.5)])],
    "NPropSetsCyl": ["1  10.0  0.05", "2  12.5  0.05", f"3  {_PONTOON_D}  0.05"],
    "NMembers": [f"{m + 1}  {2 * m + 1}  {2 * m + 2}  {min(m, 1) + 1}  {min(m, 1) + 1}  1  0  1.0  1  1  FALSE"
                 for m in range(4)]
    + [f"{m + 1}  {2 * m + 1}  {2 * m + 2}  3  3  1  0  2.0  1  1  FALSE" for m in range(4, 7)],
}
#: ``morison_only``'s coefficients: drag C_d 0.6, C_a = C_p = 1, axial C_a = C_p = 1, C_b = 1.
MORISON_ONLY_COEFFICIENTS = "0.6 0.6 1.0 1.0 1.0 1.0 0.0 0.0 1.0 1.0 1.0 1.0 1.0 1.0"
#: SimplCd … SimplCbMG: no drag; C_a = C_p = 1, axial C_a = C_p = 1, C_b = 1.
STRIP_COEFFICIENTS = "0.0 0.0 1.0 1.0 1.0 1.0 0.0 0.0 1.0 1.0 1.0 1.0 1.0 1.0"
#: AddF0's heave force: about the members' buoyancy (ρ g ΣV: 9.8 MN, with the ``piercing`` ones 15.6 MN), so the
#: platform floats near its draft.
STRIP_PRELOAD = {"strip": -9.84e6, "piercing": -1.56e7, "strip_growth": -9.84e6, "strip_growth_uniform": -9.84e6}
#: ``strip_growth``: the ``strip`` members with marine growth 0.3 m at z = −10 m to 0.2 m at −40 m (1400 kg/m³);
#: ``strip_growth_uniform``: 0.25 m at both (the decay: OpenFAST v5.0.0's own growth inertia goes wrong where the
#: thickness varies along a member, docs/offshore.md §2c).
STRIP_GROWTH = {"strip_growth": ["-10.0 0.3 1400", "-40.0 0.2 1400"],
                "strip_growth_uniform": ["-10.0 0.25 1400", "-40.0 0.25 1400"]}


def _member_section(variant: str) -> dict[str, list[str]]:
    """Rows of the Morison tables of a variant (the count key → its rows; ``none``: the deck's, no members)."""
    if variant == "none":
        return {}
    if variant == "morison_only":
        return {key: list(rows) for key, rows in MORISON_ONLY_SECTION.items()}
    if variant in STRIP_PRELOAD:
        rows = {key: list(rows) for key, rows in (PIERCING_SECTION if variant == "piercing" else STRIP_SECTION).items()}
        return rows | ({"NMGDepths": list(STRIP_GROWTH[variant])} if variant in STRIP_GROWTH else {})
    if variant == "growth":                      # columns; outer ones depth-based; marine growth from 0 to -20 m
        rows = _member_section("columns")
        rows["NMembers"] = [r if r.startswith("1 ") else r.replace("  1.0  1  0  TRUE", "  1.0  2  0  TRUE")
                            for r in rows["NMembers"]]
        rows["NCoefDpthCyl"] = ["15.0 0.5 0.8 0 0 0 0 0 0 0 0 0 0 0 0", "-20.0 1.0 1.2 0 0 0 0 0 0 0 0 0 0 0 0"]
        rows["NMGDepths"] = ["0.0 0.3 1100", "-20.0 0.1 1100"]
        return rows
    braces = variant == "braces"
    joints = _COLUMNS + (_BRACES if braces else [])
    top = 3 if braces else 1                                      # the centre column's top property set
    members = [f"{m + 1}  {2 * m + 1}  {2 * m + 2}  {1 if m == 0 else 2}  {top if m == 0 else 2}  1  0  "
               "1.0  1  0  TRUE" for m in range(4)]
    members += [f"{m}  {2 * m - 1}  {2 * m}  4  4  1  0  2.0  3  0  TRUE" for m in (5, 6, 7)] if braces else []
    coefficients = [f"{m} 1.0 0.6 1.0 0.6 0 0 0 0 0 0 0 0 0.5 0.5 0.5 0.5 0 0 0 0 0 0 0 0 0 0 0 0" for m in (5, 6, 7)]
    return {
        "NAxCoef": ["1  0.00 0.00 1.00 0 0.00 1.00", f"2  4.8 0.00 1.00 {1 if braces else 0} 0.00 1.00"],
        "NJoints": [f"{n + 1}  {x} {y} {z}  {2 if n < 8 and z < 0 else 1}  0" for n, (x, y, z) in enumerate(joints)],
        "NPropSetsCyl": ["1  10.0  0.05", "2  12.5  0.05"] + (["3  8.0  0.05", "4  2.0  0.02"] if braces else []),
        "NCoefMembersCyl": coefficients if braces else [],
        "NMembers": members,
    }


def write_deck(root: Path, variant: str) -> Path:
    """A copy of the shared ``fl_decay_a`` with ``AddBQuad`` = 0 and drag-only members (``columns``, ``braces`` or
    ``growth``; ``none``: no members) or strip-theory members (``strip``: submerged; ``piercing``: two more through
    the surface; ``strip_growth``/``strip_growth_uniform``: with marine growth; ``morison_only``: ``PotMod`` 0;
    test_offshore_strip_theory.py);
    the OpenFAST references were run on decks written by this function (their
    README)."""
    for folder in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi"):
        shutil.copytree(FLOATING / folder, root / folder, ignore=shutil.ignore_patterns("linearizations"))
    case = root / "cases" / "fl_decay_a"
    shutil.copytree(CASE, case)
    path = case / "fl_decay_a_HydroDyn.dat"
    lines = path.read_text().splitlines()
    k = next(j for j, line in enumerate(lines) if "AddBQuad" in line)
    for j in range(k, k + 6):
        lines[j] = "0 0 0 0 0 0 " + " ".join(lines[j].split()[6:])
    for key, rows in _member_section(variant).items():
        k = next(j for j, line in enumerate(lines) if line.split()[1:2] == [key])
        lines[k] = f"{len(rows)}   {key}   - " + " ".join(lines[k].split()[3:])
        if key == "NAxCoef":
            del lines[k + 3]
        lines[k + 3:k + 3] = rows
    if variant == "none":
        path.write_text("\n".join(lines) + "\n")
        return case / "fl_decay_a.fst"
    k = next(j for j, line in enumerate(lines) if line.split()[:1] == ["SimplCd"])
    axial = "1.0 1.0" if variant == "braces" else "0.0 0.0"
    mg = "0.8" if variant == "growth" else "0.6"
    strip = variant in STRIP_PRELOAD
    lines[k + 2] = STRIP_COEFFICIENTS if strip else f"0.6 {mg} 0.0 0.0 0.0 0.0 {axial} 0.0 0.0 0.0 0.0 0.0 0.0"
    if variant == "morison_only":
        lines[k + 2] = MORISON_ONLY_COEFFICIENTS
        k = next(j for j, line in enumerate(lines) if line.split()[1:2] == ["PotMod"])
        lines[k] = "0   PotMod   - strip theory only (morison_only)"
    if strip:
        k = next(j for j, line in enumerate(lines) if "AddF0" in line)
        lines[k + 2] = f"{STRIP_PRELOAD[variant]:.6e}"
    path.write_text("\n".join(lines) + "\n")
    return case / "fl_decay_a.fst"


#: SeaState edits of the waves variant: JONSWAP (the deck's seeds), a kinematics grid over the columns (10 m
#: apart), first-order kinematics only.
WAVE_EDITS = {"WaveMod": "2", "WaveHs": "4.0", "WaveTp": "10.0", "X_HalfWidth": "60", "Y_HalfWidth": "60", "NX": "7",
              "NY": "7", "WvDiffQTF": "False", "WvSumQTF": "False"}


def wave_deck(fst: Path) -> Path:
    """``fst`` (a :func:`write_deck` case) in the waves of :data:`WAVE_EDITS`."""
    import re

    path = fst.parent / "fl_decay_a_SeaState.dat"
    text = path.read_text()
    for key, value in WAVE_EDITS.items():
        text, n = re.subn(rf"^\s*\S+(\s+{key}\b)", lambda m, v=value: f"{v:>12}{m.group(1)}", text, count=1,
                          flags=re.M)
        assert n == 1, key
    path.write_text(text)
    return fst


@pytest.fixture(scope="module")
def decks(tmp_path_factory):
    if not CASE.is_dir():
        pytest.skip(f"shared floating deck not found at {CASE}")
    return {v: write_deck(tmp_path_factory.mktemp(v), v) for v in ("columns", "braces", "growth", "none")}


def _drag(fst: Path):
    return morison_drag(read_hydrodyn(fst.parent / "fl_decay_a_HydroDyn.dat"), water_density=RHO,
                        water_depth=200.0)


def test_columns_in_uniform_flow_match_the_closed_forms(decks):
    """Surge at 1 m/s: ½ ρ C_d D over the 20 m wet length of each column, its moment at the centroid (−10 m);
    heave: the four bottom plates, ¼ ρ C_ax (π/4)(10² + 3·12.5²) v² (AxFDMod 0)."""
    drag = _drag(decks["columns"])
    assert drag.length.sum() == pytest.approx(80.0, abs=1e-12)
    f = drag.load(np.zeros(6), [1.0, 0, 0, 0, 0, 0])
    expected = 0.5 * RHO * 0.6 * (10.0 + 3 * 12.5) * 20.0
    assert f[0] == pytest.approx(-expected, rel=1e-9) and f[4] == pytest.approx(10.0 * expected, rel=1e-9)
    assert np.abs(f[[1, 2, 3, 5]]).max() < 1e-6 * expected
    f = drag.load(np.zeros(6), [0, 0, -0.5, 0, 0, 0])
    assert f[2] == pytest.approx(0.25 * RHO * 4.8 * math.pi / 4 * (100.0 + 3 * 156.25) * 0.25, rel=1e-9)
    yawing = drag.load(np.zeros(6), [0, 0, 0, 0, 0, 0.01])          # outer columns move across their axes
    assert yawing[5] == pytest.approx(-3 * 0.5 * RHO * 0.6 * 12.5 * 20.0 * (0.01 * _R) ** 2 * _R, rel=1e-6)


def _subset(drag, nodes, plates: bool):
    from mbsym.wind.offshore.morison import MorisonDrag

    ends = slice(None) if plates else slice(0, 0)
    return MorisonDrag(drag.points[nodes], drag.axis[nodes], drag.length[nodes], drag.offset[nodes],
                       drag.drag[nodes], drag.taper[nodes], drag.end_points[ends], drag.end_normals[ends],
                       drag.end_drag[ends], drag.end_one_sided[ends], RHO)


def test_braces_taper_and_one_sided_plates(decks):
    """An inclined brace drags only across its axis, with C_d from MemberCd1 = 1.0 to MemberCd2 = 0.6 along it;
    the tapered centre column (D 10 → 8 m) adds ½ ρ C_ax π R |dR/dl| v_a² per length along its axis; AxFDMod 1
    plates drag only while the flow leaves them (the platform rising), ½ ρ C_ax A v²."""
    drag = _drag(decks["braces"])
    start, end = np.array(_BRACES[0]), np.array(_BRACES[1])
    length = float(np.linalg.norm(end - start))
    k = (end - start) / length
    brace = np.flatnonzero(np.isclose(drag.axis @ k, 1.0))
    s = (drag.points[brace] - start) @ k / length
    assert brace.size == math.ceil(length / 2.0) + 1
    assert np.allclose(drag.drag[brace], 2.0 * (1.0 - 0.4 * s), atol=1e-12)
    one = _subset(drag, brace, plates=False)
    assert np.abs(one.load(np.zeros(6), np.r_[-0.7 * k, 0, 0, 0])).max() < 1e-3        # along the axis: nothing
    across = np.cross(k, [0.0, 1.0, 0.0])
    f = one.load(np.zeros(6), np.r_[0.3 * across, 0, 0, 0])
    cd_mean = float(np.sum(drag.drag[brace] * drag.length[brace]))                    # ∫ C_d D dl
    assert f[:3] @ across == pytest.approx(-0.5 * RHO * cd_mean * 0.09, rel=1e-6)
    centre = np.flatnonzero(np.isclose(drag.axis[:, 2], 1.0) & (np.abs(drag.points[:, 0]) < 1e-9))
    radius = 5.0 - (drag.points[centre, 2] + 20.0) / 35.0
    assert np.allclose(drag.taper[centre], math.pi * radius / 35.0)
    columns = _subset(drag, np.flatnonzero(np.isclose(drag.axis[:, 2], 1.0)), plates=True)
    sinking, rising = (columns.load(np.zeros(6), [0, 0, w, 0, 0, 0])[2] for w in (-0.5, 0.5))
    plates = 0.5 * RHO * 4.8 * math.pi / 4 * (100.0 + 3 * 156.25) * 0.25
    taper = 0.5 * RHO * float(np.sum(drag.taper[centre] * drag.length[centre])) * 0.25
    assert sinking == pytest.approx(taper, rel=1e-6)                              # the flow enters the plates
    assert rising == pytest.approx(-plates - taper, rel=1e-6)


def test_wet_length_of_a_member_through_the_surface():
    """A column from −20.5 to 14.5 m in 1 m elements: 20.5 m wet (the crossing element's wet half to its wet node),
    as HydroDyn's SubRatio; a member wholly above water carries nothing."""
    from mbsym.wind.offshore.morison import _strips

    coefficients = lambda s, z, mg: (np.full(s.size, 0.6), np.zeros(s.size))          # noqa: E731
    strips = _strips(np.array([0, 0, -20.5]), np.array([0, 0, 14.5]), np.zeros(3), 5.0, 5.0, 1.0, coefficients, [])
    assert strips["length"].sum() == pytest.approx(20.5, abs=1e-12)
    assert strips["points"][-1][2] == pytest.approx(-0.5) and strips["length"][-1] == pytest.approx(1.0)
    assert strips["offset"][-1] == pytest.approx(0.0, abs=1e-12)        # half an element below, the wet half above
    dry = _strips(np.array([0, 0, 1.0]), np.array([0, 0, 5.0]), np.zeros(3), 5.0, 5.0, 1.0, coefficients, [])
    assert dry["length"].size == 0


@needs_deck
def test_unmodelled_member_settings_are_named(decks):
    hd = read_hydrodyn(decks["braces"].parent / "fl_decay_a_HydroDyn.dat")
    assert morison_problems(hd) == []
    text = (decks["braces"].parent / "fl_decay_a_HydroDyn.dat").read_text()
    broken = decks["braces"].parent / "broken_HydroDyn.dat"
    broken.write_text(text.replace("4  4  1  0  2.0  3  0  TRUE", "4  4  2  0  2.0  3  0  FALSE"))
    problems = morison_problems(read_hydrodyn(broken))
    assert any("MSecGeom = 2" in p for p in problems)     # PropPot = FALSE: test_offshore_strip_theory.py
    growth = (decks["growth"].parent / "fl_decay_a_HydroDyn.dat").read_text()
    short = decks["braces"].parent / "short_HydroDyn.dat"
    short.write_text(growth.replace("15.0 0.5 0.8", "10.0 0.5 0.8"))
    assert any("lie outside the depth-based table's -20 … 10 m" in p for p in morison_problems(read_hydrodyn(short)))
    bad = decks["braces"].parent / "bad_HydroDyn.dat"
    bad.write_text(text.replace("5  9  10  4  4", "5  9  99  4  4"))
    with pytest.raises(ParameterError, match="joint 99"):
        morison_drag(read_hydrodyn(bad), water_density=RHO)


def test_drag_dissipates(decks):
    """−q̇ᵀF ≥ 0 for random platform velocities at random positions (the drag never feeds energy)."""
    drag = _drag(decks["braces"])
    rng = np.random.default_rng(7)
    for _ in range(50):
        q = rng.normal(0, [3, 3, 1, 0.05, 0.05, 0.05])
        qd = rng.normal(0, [1, 1, 0.5, 0.02, 0.02, 0.02])
        assert -qd @ drag.load(q, qd) >= -1e-6


def _reference(name: str) -> dict[str, np.ndarray]:
    with (DATA / f"{name}.csv").open() as fh:
        rows = list(csv.reader(fh))
    data = np.array(rows[1:], dtype=float)
    return {h.split("_[")[0]: data[:, k] for k, h in enumerate(rows[0])}     # "PtfmSurge_[m]"


def test_marine_growth_and_depth_coefficients_as_hydrodyn_reads_them():
    """HydroDyn's tables read from the first row down (SetNodeMG, SetDepthBasedCoefs_Cyl): linear between rows;
    marine growth zero outside its table; a member reaching outside the depth-based table is refused (HydroDyn's
    fatal error); a node with growth drags with the ``…MG`` coefficient over its diameter plus twice the growth."""
    from mbsym.wind.offshore.morison import _depth_value, _strips, marine_growth

    growth = [(0.0, 0.3, 1100.0), (-20.0, 0.1, 1100.0)]
    assert marine_growth(growth, -5.0) == pytest.approx(0.25) and marine_growth(growth, 1.0) == 0.0
    assert marine_growth(growth, -20.5) == 0.0
    depth = [(0.0, 0.5, 0.8), (-20.0, 1.0, 1.2)]
    assert _depth_value(depth, -5.0, 1) == pytest.approx(0.625) and _depth_value(depth, -20.0, 2) == 1.2
    coefficients = lambda s, z, mg: (np.where(mg, 0.8, 0.6), np.zeros(s.size))        # noqa: E731
    strips = _strips(np.array([0, 0, -30.0]), np.array([0, 0, 10.0]), np.zeros(3), 5.0, 5.0, 1.0, coefficients,
                     growth)
    z = strips["points"][:, 2]
    expected = np.where((z >= -20.0) & (z <= 0.0), 0.8 * 2 * (5.0 + np.array([marine_growth(growth, v) for v in z])),
                        0.6 * 10.0)
    assert np.allclose(strips["drag"], expected)


@needs_deck
@pytest.mark.parametrize("variant", ["columns", "braces", "growth"])
def test_decay_with_members_matches_openfast(decks, variant, tmp_path):
    """300 s of the decay (``mbsym simulate``, quasi-static lines) against OpenFAST's with the same members:
    ε ≤ 1.5 % on surge, heave and pitch (module docstring); without the members' drag ε > 2.5 %."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import error_metrics, read_csv

    ref = _reference(variant)
    out = tmp_path / "run.csv"
    fast = ["--mooring-lines", "quasi-static"]       # the members on the fast rung (MoorDyn's moving lines: §3c)
    assert main(["simulate", str(decks[variant]), "--tmax", "300", *fast, "--out", str(out)]) == 0
    run = read_csv(out)
    for channel in ("PtfmSurge", "PtfmHeave", "PtfmPitch"):
        eps, _ = error_metrics(run.time, run.channel(channel), ref["Time"], ref[channel])
        assert eps <= 0.015, (channel, eps)
    assert main(["simulate", str(decks["none"]), "--tmax", "300", *fast, "--out", str(out)]) == 0
    run = read_csv(out)
    eps, _ = error_metrics(run.time, run.channel("PtfmSurge"), ref["Time"], ref["PtfmSurge"])
    assert eps > 0.025
