"""AeroDyn 15 input reading: main file, blade file, airfoil polars; typed errors.

References: the NREL 5 MW AeroDyn deck of the shared OpenFAST runs
(``shared/openfast/aero/openfast_inputs/deck``; blade data published in Jonkman et al.
2009, NREL/TP-500-38060, Table 2-1) and thin-airfoil theory for the lift slope.
"""

from __future__ import annotations

import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError
from mbsym.wind import read_openfast
from mbsym.wind.deck.aerodyn import read_aerodyn, read_aerodyn_blade
from mbsym.wind.deck.airfoils import read_airfoil

from .conftest import AERO, AERODYN_MAIN, DECK, need

BLADE = "NRELOffshrBsline5MW_AeroDyn_blade.dat"


@pytest.fixture(scope="module")
def ad():
    return read_aerodyn(need(AERODYN_MAIN))


@pytest.fixture
def deck_copy(tmp_path: Path) -> Path:
    """A writable copy of the AeroDyn deck (main, blade, airfoils)."""
    need(DECK)
    for name in (AERODYN_MAIN.name, BLADE):
        shutil.copy(DECK / name, tmp_path / name)
    shutil.copytree(DECK / "Airfoils", tmp_path / "Airfoils")
    for path in tmp_path.rglob("*"):
        path.chmod(0o755 if path.is_dir() else 0o644)
    return tmp_path


def edit(path: Path, old: str, new: str, count: int = 1) -> None:
    text, n = re.subn(old, new, path.read_text(encoding="latin-1"), count=count, flags=re.M)
    assert n == count, f"mutation {old!r} applied {n} times to {path.name}"
    path.write_text(text, encoding="latin-1")


# ----------------------------------------------------------------------------- values
def test_main_options_of_the_reference_deck(ad):
    # As the shared README states for the OpenFAST runs: BEMT, tip/hub loss, tangential
    # induction on, drag excluded from the induction, steady airfoils, rho = 1.225.
    assert (ad.wake_model, ad.bem_model, ad.skew_model, ad.unsteady_model) == (1, 1, 1, 0)
    assert ad.tip_loss and ad.hub_loss and ad.tangential_induction
    assert not ad.axial_drag and not ad.tangential_drag
    assert ad.air_density == 1.225 and ad.kinematic_viscosity == 1.464e-5
    assert ad.airfoil_columns == (1, 2, 3, 4) and ad.use_pitching_moment
    assert [a.name for a in ad.airfoils] == ["Cylinder1", "Cylinder2", "DU40_A17", "DU35_A17",
                                             "DU30_A17", "DU25_A17", "DU21_A17", "NACA64_A17"]
    assert ad.skew_redistribution and abs(ad.skew_redistribution_factor - 15 * math.pi / 32) < 1e-15
    assert "SkewMomCorr" in ad.extra  # keys not modelled are kept verbatim
    assert ad.tower_elevation[-1] == 87.6


def test_blade_matches_the_published_nrel5mw_blade(ad):
    # NREL/TP-500-38060 Table 2-1: 17 aerodynamic stations, root chord 3.542 m, twist
    # 13.308 deg at the root, max chord 4.652 m; the AeroDyn deck adds root and tip nodes.
    blade = ad.blades[0]
    assert ad.blades[0] is ad.blades[1] is ad.blades[2]  # same file, read once
    assert blade.span.size == 19 and blade.span[0] == 0.0 and blade.span[-1] == 61.4999
    assert blade.chord[0] == 3.542 and blade.chord.max() == 4.652
    assert abs(blade.twist[0] - math.radians(13.308)) < 1e-15
    assert blade.airfoil_id[:4] == (1, 1, 1, 2) and blade.airfoil_id[-1] == 8
    # AeroDyn reads NumBlNds rows; the 20th row of this file is ignored, but kept.
    ignored = [v for k, v in blade.extra.items() if k.startswith("(ignored")]
    assert len(ignored) == 1 and ignored[0].startswith("6.1500000E+01")


def test_polars_follow_thin_airfoil_theory(ad):
    # Lift slope of the outboard airfoils in the attached-flow range, 0..5 deg, is
    # close to 2 pi / rad (thin-airfoil theory; these thick DU airfoils with stall-delay
    # corrections reach 1.2 x 2 pi, so the band is 0.8-1.25 x 2 pi).
    for polar in ad.airfoils[4:]:
        cl0, cl5 = polar.coefficients(np.radians([0.0, 5.0]))[0]
        slope = (cl5 - cl0) / math.radians(5.0)
        assert 0.8 * 2 * math.pi < slope < 1.25 * 2 * math.pi, polar.name
        assert np.all(polar.cd > 0)
    # The cylinders: no lift, constant drag (0.5 and 0.35), as written.
    assert np.all(ad.airfoils[0].cl == 0) and np.all(ad.airfoils[0].cd == 0.5)


def test_coefficients_interpolate_linearly_and_wrap(ad):
    polar = ad.airfoils[7]
    a0, a1 = polar.alpha[60], polar.alpha[61]
    mid = polar.coefficients(np.array([0.5 * (a0 + a1)]))[0][0]
    assert mid == pytest.approx(0.5 * (polar.cl[60] + polar.cl[61]), abs=1e-15)
    wrapped = polar.coefficients(np.array([a0 + 2 * math.pi]))[0][0]
    assert wrapped == pytest.approx(polar.cl[60], abs=1e-12)


def test_read_openfast_names_the_module_files():
    fst = need(AERO / "openfast_inputs" / "steady_12" / "steady_12.fst")
    params = read_openfast(fst)
    assert Path(params.source_files["aerodyn"]).resolve() == AERODYN_MAIN.resolve()
    assert Path(params.source_files["servodyn"]).name == "NRELOffshrBsline5MW_Onshore_ServoDyn.dat"
    assert Path(params.source_files["inflowwind"]).name == "steady_12_IfW.dat"
    assert params.simulation.aerodynamics_model == 2


# ----------------------------------------------------------------------------- errors
@pytest.mark.parametrize("old, new, message", [
    (r"^1\.0250000E\+01", "1.0250000E+00", r"line 11, key 'BlSpn': must strictly increase"),
    (r"4\.5570000E\+00", "-4.557", r"line 11, key 'BlChord': must be > 0"),
    (r"(1\.3308000E\+01  4\.5570000E\+00 +)3", r"\g<1>9", r"line 11, key 'BlAFID': must be an "
                                                          r"integer in \[1, 8\]"),
    (r"^ +19   NumBlNds", "         25   NumBlNds", r"key 'NumBlNds': says 25 rows"),
    (r" BlTwist ", " BlTwst ", r"key 'BlTwist': column missing"),
])
def test_bad_blade_file(deck_copy, old, new, message):
    path = deck_copy / BLADE
    edit(path, old, new)
    with pytest.raises(OpenFASTFormatError, match=message) as info:
        read_aerodyn_blade(path, n_airfoils=8)
    assert str(path) in str(info.value)


@pytest.mark.parametrize("old, new, message", [
    (r"^ +-5\.00 +-0\.1[0-9]+", "    -5.00   x.y", r"line \d+: expected a number, got 'x.y'"),
    (r"^ +-5\.00 ", "     -7.00 ", r"must strictly increase; -7 deg follows -5\.5 deg"),
    (r"^ +142   NumAlf", "        150   NumAlf", r"key 'NumAlf': says 150 rows, but only 142"),
    (r"^ +0\.75   Re ", "      -0.75   Re ", r"key 'Re': must not be negative"),
    (r"^ +-180\.00 .*\n", "", r"spans \[-175, 180\] deg; it must span \[-180, 180\] deg"),
])
def test_bad_airfoil_file(deck_copy, old, new, message):
    path = deck_copy / "Airfoils" / "DU21_A17.dat"
    edit(path, old, new)
    if "NumAlf" in new or "-180" in old:  # keep the count consistent where the table shrinks
        if "-180" in old:
            edit(path, r"^ +142   NumAlf", "        141   NumAlf")
    with pytest.raises(OpenFASTFormatError, match=message) as info:
        read_airfoil(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize("old, new, message", [
    (r'^"Airfoils/NACA64_A17\.dat"\n', "", r"key 'AFNames': NumAFfiles says 8 airfoil files, "
                                           r"but 7 names follow"),
    (r"^ +1   Wake_Mod ", "          7   Wake_Mod ", r"key 'Wake_Mod': must be 0, 1, 2 or 3"),
    (r"^True +TipLoss ", "Maybe         TipLoss ", r"key 'TipLoss': expected True or False"),
    (r"^.*AIDrag .*\n", "", r"key 'AIDrag': missing"),
    (r'"Airfoils/DU25_A17\.dat"', '"Airfoils/DU26_A17.dat"', r"line 66, key 'AFNames': airfoil "
                                                               r"file not found"),
    (r'"NRELOffshrBsline5MW_AeroDyn_blade\.dat"    ADBlFile\(2\)', '"nope.dat"    ADBlFile(2)',
     r"key 'ADBlFile\(2\)': blade 2 file not found"),
])
def test_bad_aerodyn_main_file(deck_copy, old, new, message):
    path = deck_copy / AERODYN_MAIN.name
    edit(path, old, new)
    with pytest.raises(OpenFASTFormatError, match=message) as info:
        read_aerodyn(path)
    assert str(path) in str(info.value)


def test_missing_files_are_named(tmp_path):
    with pytest.raises(OpenFASTFormatError, match="AeroDyn input file not found"):
        read_aerodyn(tmp_path / "absent.dat")
    with pytest.raises(OpenFASTFormatError, match="airfoil file not found"):
        read_airfoil(tmp_path / "absent.dat")
    with pytest.raises(OpenFASTFormatError, match="AeroDyn blade file not found"):
        read_aerodyn_blade(tmp_path / "absent.dat")


def _flap_airfoil(path: Path) -> Path:
    """DU21_A17 as three tables for flap settings UserProp -10, 0, 10 (Cl shifted by -0.2, 0, +0.2)."""
    lines = (path / "Airfoils" / "DU21_A17.dat").read_text().splitlines()
    start = next(i for i, t in enumerate(lines) if re.search(r"\bRe\b", t))
    head, table = lines[:start], lines[start:]
    numalf = next(i for i, t in enumerate(table) if "NumAlf" in t)
    blocks = []
    for prop, shift in ((-10, -0.2), (0, 0.0), (10, 0.2)):
        block = [re.sub(r"^\s*\S+(\s+UserProp)", f"{prop}\\1", t) for t in table]
        rows = [t.split() for t in block[numalf + 1:] if t.strip() and not t.strip().startswith("!")]
        block[numalf + 1:] = [" ".join([r[0], f"{float(r[1]) + shift:.6f}", *r[2:]]) for r in rows]
        blocks += block
    text = "\n".join(head + blocks).replace("1   NumTabs", "3   NumTabs")
    out = path / "Airfoils" / "FLAP.dat"
    out.write_text(text + "\n")
    return out


def test_airfoil_table_for_the_user_property(deck_copy):
    """AFTabMod = 3: the table whose UserProp is the airfoil input (0 without ServoDyn's airfoil control);
    AFTabMod = 1 the first; a value between tables (AeroDyn blends them) is refused with the file and line."""
    flap = _flap_airfoil(deck_copy)
    base = read_airfoil(deck_copy / "Airfoils" / "DU21_A17.dat")
    first, middle = read_airfoil(flap), read_airfoil(flap, user_prop=0.0)
    assert (first.n_tables, first.table, middle.table) == (3, 0, 1)
    np.testing.assert_allclose(first.cl, base.cl - 0.2, atol=1e-6)
    np.testing.assert_allclose(middle.cl, base.cl, atol=1e-6)
    assert read_airfoil(flap, user_prop=10.0).cl[70] == pytest.approx(base.cl[70] + 0.2, abs=1e-6)
    with pytest.raises(OpenFASTFormatError, match=r"FLAP.dat, line \d+, key 'UserProp': AFTabMod = 3.*at the "
                                                  r"airfoil input 5"):
        read_airfoil(flap, user_prop=5.0)


def test_aerodyn_deck_reads_the_table_its_mode_asks(deck_copy):
    flap = _flap_airfoil(deck_copy)
    main_file = deck_copy / AERODYN_MAIN.name
    main = main_file.read_text()
    main = re.sub(r'"Airfoils/DU21_A17\.dat"', f'"Airfoils/{flap.name}"', main, count=1)
    for mode, table in ((1, 0), (3, 1)):
        main_file.write_text(re.sub(r"^\s*\S+(\s+AFTabMod\b)", f"{mode}\\1", main, count=1, flags=re.M))
        ad = read_aerodyn(main_file)
        assert [a.table for a in ad.airfoils if a.name == "FLAP"] == [table]
    main_file.write_text(re.sub(r"^\s*\S+(\s+AFTabMod\b)", r"2\1", main, count=1, flags=re.M))
    with pytest.raises(OpenFASTFormatError, match="AFTabMod.*Reynolds number.*FLAP"):
        read_aerodyn(main_file)
