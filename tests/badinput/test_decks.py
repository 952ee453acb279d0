"""Mutated OpenFAST decks: each one is refused by ``mbsym simulate`` with one typed error line
naming the problem (file, line, key where it applies) and no output file left behind.

Expected messages come from ElastoDyn's input checks (docs/elastodyn_notes.md), mbsym's own
bounds (:mod:`mbsym.wind.deck.checks`: modules not modelled, supersonic blade tips; numbers
beyond 1e30) and the file layout. The deck is the shared paper44 case (../shared/openfast).
"""

from __future__ import annotations

import pytest

from .conftest import assert_refused, delete_key, set_key, set_table_cell

# (file, key or table cell, new value or None to delete the line, expected message regex)
CASES = [
    # ElastoDyn file: values out of range or malformed
    ("ed", "TowerHt", "1e300", r"line \d+, key 'TowerHt'.*too large"),           # was an OverflowError traceback
    ("ed", "TowerHt", "-5", r"TowerHt.*greater than 0"),
    ("ed", "TowerHt", "tall", r"TowerHt.*expected a number"),
    ("ed", "RotSpeed", "1e9", r"RotSpeed.*speed of sound"),
    ("ed", "RotSpeed", "-1", r"RotSpeed.*must not be negative"),
    ("ed", "NumBl", "4", r"NumBl.*1, 2 or 3"),
    ("ed", "TipRad", "1", r"HubRad.*less than TipRad"),
    ("ed", "PreCone(1)", "95", r"PreCone.*\(-90, 90\)"),
    ("ed", "ShftTilt", "100", r"ShftTilt.*\[-90, 90\]"),
    ("ed", "Azimuth", "400", r"Azimuth.*\[0, 360\)"),
    ("ed", "NacYaw", "200", r"NacYaw.*\(-180, 180\]"),
    ("ed", "BlPitch(1)", "270", r"BlPitch.*\(-180, 180\]"),
    ("ed", "NacMass", "-1", r"NacMass.*must not be negative"),
    ("ed", "HubMass", "nan", r"HubMass.*expected a number"),
    ("ed", "GBRatio", "0", r"GBRatio.*greater than 0"),
    ("ed", "GBoxEff", "0", r"GBoxEff.*\(0, 100\]"),
    ("ed", "DTTorSpr", "-1", r"DTTorSpr.*must not be negative"),
    ("ed", "TwrNodes", "0", r"TwrNodes.*at least 1"),
    ("ed", "BldNodes", "0", r"BldNodes.*at least 1"),
    ("ed", "Method", "7", r"Method.*1 \(RK4\)"),
    ("ed", "Furling", "True", r"Furling.*furling"),
    ("ed", "TeetMod", "5", r"TeetMod.*0, 1 or 2"),
    ("ed", "TowerBsHt", "100", r"TowerBsHt.*less than TowerHt"),
    ("ed", "NacYIner", "0", r"NacYIner.*NacMass"),
    ("ed", "TwFADOF1", "maybe", r"TwFADOF1.*True or False"),
    ("ed", "GenIner", None, r"GenIner"),                                          # missing key
    ("ed", "TwrFile", '"no_such_tower.dat"', r"tower file not found"),            # missing referenced file
    ("ed", "BldFile(1)", '"no_such_blade.dat"', r"blade 1 file not found"),
    ("ed", "HubIner", "1e31", r"HubIner.*too large"),
    # main .fst file
    ("fst", "CompAero", "2", r"CompAero = 2 \(AeroDyn\).*--structure-only"),       # ran as structure, exit 0
    ("fst", "CompServo", "1", r"CompServo = 1 \(ServoDyn\)"),
    ("fst", "CompHydro", "1", r"CompHydro = 1 \(HydroDyn\)"),
    ("fst", "CompInflow", "1", r"CompInflow = 1 \(InflowWind\)"),
    ("fst", "CompSub", "1", r"CompSub = 1 \(SubDyn\)"),
    ("fst", "CompMooring", "3", r"CompMooring = 3 \(MoorDyn\)"),
    ("fst", "CompIce", "1", r"CompIce = 1"),
    ("fst", "CompElast", "2", r"CompElast.*only CompElast = 1"),
    ("fst", "DT", "0", r"DT.*greater than 0"),
    ("fst", "Gravity", "-9.8", r"Gravity.*must not be negative"),
    ("fst", "EDFile", '"missing_ElastoDyn.dat"', r"ElastoDyn input file not found"),
    ("fst", "CompAero", "two", r"CompAero.*expected an integer"),
    # tower file
    ("tower", "AdjTwMa", "0", r"AdjTwMa.*greater than 0"),
    ("tower", "TwrFADmp(1)", "150", r"TwrFADmp.*between 0 and 100"),
    ("tower", "TwFAM1Sh(2)", "5.0", r"TwFAM1Sh.*sum to"),
    ("tower", (2, 1), "-10", r"TMassDen.*greater than 0"),                         # table cell
    ("tower", (3, 0), "0.1", r"HtFract.*strictly increase"),
    ("tower", (4, 2), "1e300", r"too large"),
    ("tower", (1, 3), "abc", r"Tower|tower|number"),
    # blade file
    ("blade", "AdjBlMs", "-1", r"AdjBlMs.*greater than 0"),
    ("blade", "BldFl1Sh(2)", "3.0", r"BldFl1Sh.*sum to"),
    ("blade", "BldFlDmp(1)", "-3", r"BldFlDmp.*between 0 and 100"),
    ("blade", (2, 2), "0", r"BMassDen.*greater than 0"),
    ("blade", (2, 1), "200", r"StrcTwst.*\(-180, 180\]"),
]


def _mutate(deck, which, key, value):
    path = {"ed": deck.ed, "fst": deck.fst, "tower": deck.tower, "blade": deck.blade}[which]
    if isinstance(key, tuple):
        set_table_cell(path, *key, value)
    elif value is None:
        delete_key(path, key)
    else:
        set_key(path, key, value)


@pytest.mark.parametrize("which, key, value, match", CASES, ids=[f"{c[0]}-{c[1]}={c[2]}" for c in CASES])
def test_mutated_deck_is_refused(deck, which, key, value, match):
    _mutate(deck, which, key, value)
    out = deck.dir / "out.csv"
    assert_refused(deck, ["simulate", deck.fst, "--tmax", "0.1", "--out", out, "--plot", deck.dir / "p.png"], match)
    assert not out.exists()


def test_case_count():
    """The suite's floor (issue 11: at least 60 decks, CLI argument sets and API calls together)."""
    from . import test_api, test_cli

    assert len(CASES) + len(test_cli.CASES) + len(test_api.CASES) >= 60
