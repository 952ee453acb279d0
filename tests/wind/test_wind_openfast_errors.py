"""Malformed decks raise OpenFASTFormatError naming file, line and key.

Each test copies the shared base deck to ``tmp_path``, mutates one thing and
checks the message (python-control style: every error path with
``pytest.raises(..., match=...)``).  Line numbers refer to the base deck files.
"""

from __future__ import annotations

import re

import pytest

from mbsym.exceptions import OpenFASTFormatError
from mbsym.wind import read_openfast

ED = "NREL5MW_ElastoDyn_Onshore.dat"
TOWER = "NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat"
BLADE = "NRELOffshrBsline5MW_Blade.dat"
FST = "NREL5MW_Onshore_ElastoDynOnly.fst"


def test_unmodified_copy_reads(deck, base_params):
    assert read_openfast(deck.fst) == base_params


def test_missing_key(deck, edit):
    edit(deck.ed, r"^87\.6 +TowerHt .*\n", "")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(ED)}, line 65, key 'TowerHt': missing.*"
                       r"after line 64"):
        read_openfast(deck.fst)


def test_bad_number(deck, edit):
    edit(deck.ed, r"^87\.6 ", "abc  ")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(ED)}, line 65, key 'TowerHt': expected a "
                       r"number, got 'abc'\. Fix the value in that line\."):
        read_openfast(deck.fst)


def test_wrong_type_for_flag(deck, edit):
    edit(deck.ed, r"^True( +FlapDOF1)", r"maybe\1")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(ED)}, line 8, key 'FlapDOF1': expected "
                       r"True or False, got 'maybe'"):
        read_openfast(deck.fst)


def test_integer_expected(deck, edit):
    edit(deck.ed, r"^3( +NumBl)", r"3.5\1")
    with pytest.raises(OpenFASTFormatError, match=r"line 45, key 'NumBl': expected an integer"):
        read_openfast(deck.fst)


def test_missing_tower_file(deck):
    (deck.tower).unlink()
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(ED)}, line 132, key 'TwrFile': tower file "
                       rf"not found: tried '{re.escape(str(deck.tower))}'"):
        read_openfast(deck.fst)


def test_missing_elastodyn_file(deck, edit):
    edit(deck.fst, r'^"NREL5MW_ElastoDyn_Onshore\.dat"', '"nowhere/ED.dat"')
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(FST)}, line 41, key 'EDFile': ElastoDyn "
                       r"input file not found: tried '.*nowhere/ED\.dat'"):
        read_openfast(deck.fst)


def test_missing_main_file(tmp_path):
    with pytest.raises(OpenFASTFormatError, match=r"main input file not found: tried '.*x\.fst'"):
        read_openfast(tmp_path / "x.fst")


def test_non_increasing_stations(deck, edit):
    edit(deck.tower, r"^2\.0000000E-01", "1.0000000E-01")  # line 22 repeats line 21
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(TOWER)}, line 22, key 'HtFract': stations "
                       r"must strictly increase"):
        read_openfast(deck.fst)


def test_stations_must_start_at_0_and_end_at_1(deck, edit):
    edit(deck.blade, r"^0\.0000000E\+00", "1.0000000E-03")
    edit(deck.blade, r"^1\.0000000E\+00", "9.9990000E-01")
    with pytest.raises(OpenFASTFormatError) as info:
        read_openfast(deck.fst)
    assert re.search(rf"{BLADE}, line 17, key 'BlFract': the first station must be at 0",
                     str(info.value))
    assert re.search(r"line 65, key 'BlFract': the last station must be at 1", str(info.value))


def test_mode_shape_coefficients_must_sum_to_1(deck, edit):
    edit(deck.blade, r"^     0\.0622 ", "     0.0652 ")  # BldFl1Sh(2): sum 1.003
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(BLADE)}, line 71, key 'BldFl1Sh\(6\)': the "
                       r"mode-shape coefficients BldFl1Sh\(2\.\.6\) on lines 67-71 sum to 1\.003"):
        read_openfast(deck.fst)


def test_coefficient_sum_within_elastodyn_tolerance_is_accepted(deck, edit):
    edit(deck.blade, r"^     0\.0622 ", "     0.0632 ")  # sum 1.001 < 1 + 0.0015
    read_openfast(deck.fst)


def test_non_positive_stiffness(deck, edit):
    edit(deck.tower, r"^(5\.0000000E-01  3\.9164100E\+03  )2\.9101100E\+11", r"\g<1>-2.9E+11")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(TOWER)}, line 25, key 'TwFAStif': must be "
                       r"greater than 0; got -2\.9e\+11 \(row 6"):
        read_openfast(deck.fst)


def test_damping_out_of_range(deck, edit):
    edit(deck.tower, r"^          1(   TwrSSDmp\(2\))", r"        120\1")
    with pytest.raises(OpenFASTFormatError, match=r"line 8, key 'TwrSSDmp\(2\)': must be between "
                       r"0 and 100 %"):
        read_openfast(deck.fst)


def test_bad_table_cell(deck, edit):
    edit(deck.blade, r"^(3\.2500000E-03  1\.3308000E\+01  )6\.7893500E\+02", r"\1x")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(BLADE)}, line 18, key 'BMassDen': expected "
                       r"a number, got 'x' \(row 2"):
        read_openfast(deck.fst)


def test_row_count_mismatch(deck, edit):
    edit(deck.tower, r"^ +11( +NTwInpSt)", r"         12\1")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(TOWER)}, line 4, key 'NTwInpSt': says 12 "
                       r"rows, but the distributed tower properties table .* has 11"):
        read_openfast(deck.fst)


def test_missing_table_column(deck, edit):
    edit(deck.blade, r"^( +BlFract +StrcTwst +BMassDen +FlpStff) +EdgStff", r"\1")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(BLADE)}, line 15, key 'EdgStff': column "
                       r"missing"):
        read_openfast(deck.fst)


def test_duplicate_key(deck, edit):
    edit(deck.ed, r"^(0 +TowerBsHt .*)$", r"\1\n1  TowerBsHt  - again")
    with pytest.raises(OpenFASTFormatError, match=r"line 67, key 'TowerBsHt': duplicate key "
                       r"\(also on line 66\)"):
        read_openfast(deck.fst)


def test_line_without_key(deck, edit):
    edit(deck.ed, r"^(0 +TowerBsHt .*)$", r"\1\n42")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(ED)}, line 67: no key name found in '42'"):
        read_openfast(deck.fst)


def test_elastodyn_cross_checks(deck, edit):
    edit(deck.ed, r"^0( +TowerBsHt)", r"90\1")
    with pytest.raises(OpenFASTFormatError, match=r"line 66, key 'TowerBsHt': must be less than "
                       r"TowerHt"):
        read_openfast(deck.fst)


def test_unsupported_features_are_rejected(deck, edit):
    edit(deck.fst, r"^1( +CompElast)", r"2\1")
    with pytest.raises(OpenFASTFormatError, match=r"line 18, key 'CompElast': only CompElast = 1"):
        read_openfast(deck.fst)


def test_furling_is_rejected(deck, edit):
    edit(deck.ed, r"^False( +Furling)", r"True\1")
    with pytest.raises(OpenFASTFormatError, match=r"line 128, key 'Furling': must be False"):
        read_openfast(deck.fst)


def test_all_problems_of_a_file_are_listed(deck, edit):
    edit(deck.ed, r"^87\.6 ", "abc  ")
    edit(deck.ed, r"^True( +FlapDOF1)", r"maybe\1")
    edit(deck.ed, r"^240000( +NacMass)", r"-1\1")
    with pytest.raises(OpenFASTFormatError, match=r"3 problems in .*") as info:
        read_openfast(deck.fst)
    message = str(info.value)
    for fragment in ("line 8, key 'FlapDOF1'", "line 65, key 'TowerHt'",
                     "line 87, key 'NacMass': must not be negative"):
        assert fragment in message


def test_gravity_missing_everywhere(deck, edit):
    edit(deck.fst, r"^9\.80665 +Gravity .*\n", "")
    with pytest.raises(OpenFASTFormatError, match=rf"{re.escape(FST)}, line \d+, key 'Gravity': missing "
                       r"from both"):
        read_openfast(deck.fst)


@pytest.mark.parametrize("key, line", [("TwrNodes", 131), ("BldNodes", 98)])
def test_absurd_node_counts_are_refused_before_any_allocation(deck, edit, key, line):
    """A mistyped node count (issue: TwrNodes = 100000000 grew to 23.7 GB) is refused by the reader, before
    anything is built, with file, line and key (limit: MAX_ANALYSIS_NODES)."""
    edit(deck.ed, rf"^\d+( +{key})", r"100000000\1")
    with pytest.raises(OpenFASTFormatError, match=rf"line {line}, key '{key}': must be at least 1 and at most 100000"):
        read_openfast(deck.fst)
