"""Older deck layouts, key spellings, extra keys and number formats.

The reference is the shared v5 base deck: a deck rewritten in an older layout
(no v5-only keys, Gravity in the ElastoDyn file, a PitchAxis column in the blade
table) describes the same turbine and must give the same parameters.
"""

from __future__ import annotations

import math
import re

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mbsym.wind import read_openfast

V5_ONLY = ("PitchDOF", "PtfmRefxt", "PtfmRefyt", r"PBrIner\(\d\)", r"BlPIner\(\d\)",
           "HubIner_Teeter", "PtfmXYIner", "PtfmYZIner", "PtfmXZIner", "YawFrctMod", "M_CSmax",
           "M_FCSmax", "M_MCSmax", "M_CD", "M_FCD", "M_MCD", "sig_v", "sig_v2", "OmgCut")


def _older_layout(deck, edit) -> None:
    for key in V5_ONLY:
        edit(deck.ed, rf"^\S+ +{key} .*\n", "", count=3 if "(" in key else 1)
    edit(deck.ed, r"^-+ YAW-FRICTION -+\n", "")
    edit(deck.fst, r"^9\.80665 +Gravity .*\n", "")
    edit(deck.ed, r"^(3 +Method .*)$", r"\1\n9.80665   Gravity   - Gravitational acceleration")
    text = (deck.blade).read_text().splitlines()
    text[14] = "    BlFract      PitchAxis      StrcTwst      BMassDen      FlpStff      EdgStff"
    text[15] = "      (-)          (-)          (deg)          (kg/m)          (Nm^2)    (Nm^2)"
    for j in range(16, 65):
        first, rest = text[j].split(maxsplit=1)
        text[j] = f"{first}  2.5000000E-01  {rest}"
    (deck.blade).write_text("\n".join(text) + "\n")


def test_older_layout_gives_the_same_turbine(deck, edit, base_params):
    _older_layout(deck, edit)
    old = read_openfast(deck.fst)
    assert old.blades[0].pitch_axis is not None and np.all(old.blades[0].pitch_axis == 0.25)
    assert base_params.blades[0].pitch_axis is None
    a, b = old.to_dict(), base_params.to_dict()
    for d in (a, b):
        d["simulation"].pop("extra"), d.pop("extra"), d.pop("source_files")
        for blade in d["blades"]:
            blade.pop("pitch_axis")
    assert a == b
    assert "YawFrctMod" in base_params.extra and "YawFrctMod" not in old.extra


def test_key_spellings_and_extra_keys(deck, edit, base_params):
    edit(deck.ed, r"PreCone\(1\)", "PRECONE1")
    edit(deck.ed, r"^(0 +TowerBsHt .*)$", r'\1\n"hello world"   MyNewKey   - not an ElastoDyn key')
    p = read_openfast(deck.fst)
    assert p.precone == base_params.precone
    assert p.extra["MyNewKey"] == "hello world"


def test_two_bladed_deck_keeps_unused_third_blade_values(deck, edit):
    edit(deck.ed, r"^3( +NumBl)", r"2\1")
    p = read_openfast(deck.fst)
    assert p.number_of_blades == 2 and len(p.blades) == len(p.precone) == 2
    assert p.extra["PreCone(3)"] == "-2.5" and "BldFile(3)" in p.extra


def test_default_time_steps_resolve(deck, edit):
    edit(deck.fst, r"^0\.02( +DT_Out)", r'"default"\1')
    p = read_openfast(deck.fst)
    assert p.simulation.output_time_step == p.simulation.time_step == 0.01
    assert p.structural_time_step == 0.01  # ElastoDyn DT "default"


def _fortran(value: float, style: int) -> str:
    text = f"{value:.17e}" if style < 2 else repr(value)
    return text.replace("e", "D") if style == 1 else text


@settings(derandomize=True, database=None, deadline=None, max_examples=25,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(value=st.floats(min_value=1.0, max_value=1e4, allow_nan=False), style=st.integers(0, 2))
def test_numbers_read_back_exactly(deck, value, style):
    # Property: any finite height written as E, Fortran D or plain repr is read back exactly.
    text = (deck.ed).read_text()
    text = re.sub(r"^\S+( +TowerHt )", lambda m: _fortran(value + 100.0, style) + m.group(1),
                  text, count=1, flags=re.M)
    (deck.ed).write_text(text)
    assert read_openfast(deck.fst).tower_height == value + 100.0


def test_angles_and_speeds_are_converted(base_params):
    assert math.isclose(base_params.precone[0], math.radians(-2.5), rel_tol=1e-15)
    assert math.isclose(base_params.initial_conditions.rotor_speed, 10 * 2 * math.pi / 60,
                        rel_tol=1e-15)
    assert math.isclose(base_params.blades[0].structural_twist[0], math.radians(13.308),
                        rel_tol=1e-15)
    assert base_params.tower.fa_damping_ratio.tolist() == [0.01, 0.01]
    assert base_params.gearbox_efficiency == 1.0


def test_tower_concentrated_masses(deck, edit):
    # Optional section of recent ElastoDyn tower files; read by position like ElastoDyn does.
    with deck.tower.open("a") as f:
        f.write("---------------------- TOWER CONCENTRATED MASSES ----------\n"
                "          2   NTwCMass    - Number of tower concentrated masses (-)\n"
                "  HtFract     TwCMass\n     (-)        (kg)\n   0.5   1000.0\n   1.0   20.0\n")
    p = read_openfast(deck.fst)
    assert p.tower.point_mass_fraction.tolist() == [0.5, 1.0]
    assert p.tower.point_mass.tolist() == [1000.0, 20.0]
    assert p.tower.extra_columns == {}
