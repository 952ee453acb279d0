"""Every case deck in ../shared/openfast/cases reads, with the settings its README states.

Reference: ``../shared/openfast/README.md`` (case table and note 1): which DOFs are
on, the initial conditions, TMax, gravity, cone/tilt and the floating platform
values.  Any DOF not listed there is False.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from mbsym.wind import DOF_NAMES, read_openfast, tower_top_mass

OPENFAST = Path(__file__).resolve().parents[2].parent / "shared" / "openfast"

CASE_DECKS = sorted(OPENFAST.glob("cases/*/*.fst"))
DEG, RPM = math.pi / 180, math.pi / 30

EXPECTED = {  # case → (enabled DOFs, initial conditions, TMax of the time-domain run)
    "paper44_fa_gen": ({"TwFADOF1", "GenDOF"},
                       {"tower_top_fa_displacement": 1.0, "rotor_speed": 5 * RPM}, 60.0),
    "paper45_fa_ss_gen": ({"TwFADOF1", "TwSSDOF1", "GenDOF"},
                          {"tower_top_fa_displacement": 1.0, "tower_top_ss_displacement": 1.0,
                           "rotor_speed": 5 * RPM}, 60.0),
    "paper46_floating": ({"PtfmSgDOF", "PtfmPDOF", "TwFADOF1"},
                         {"platform_surge": 0.0, "platform_pitch": 2 * DEG,
                          "tower_top_fa_displacement": 1.0, "rotor_speed": 0.0}, 60.0),
    "blade_campbell": ({"FlapDOF1", "FlapDOF2", "EdgeDOF"}, {}, None),
    "platform_rpy_gen": ({"PtfmRDOF", "PtfmPDOF", "PtfmYDOF", "TwFADOF1", "TwSSDOF1", "GenDOF"},
                         {"platform_roll": -2 * DEG, "platform_pitch": 1.5 * DEG, "platform_yaw": -4 * DEG,
                          "tower_top_ss_displacement": 0.4, "rotor_speed": 8 * RPM}, 30.0),
    "blades_large_deflection": ({"FlapDOF1", "EdgeDOF", "GenDOF"},
                                {"blade_oop_tip_deflection": 3.0, "blade_ip_tip_deflection": -0.8,
                                 "rotor_speed": 9 * RPM}, 30.0),
}


def test_all_case_decks_found():
    if not OPENFAST.is_dir():
        pytest.skip("shared OpenFAST data absent")
    assert len(CASE_DECKS) >= 4 + 6  # 3 paper cases (+ lin, lin0) and 6 Campbell speeds


@pytest.mark.parametrize("fst", CASE_DECKS, ids=lambda p: p.stem)
def test_case_deck(fst):
    p = read_openfast(fst)
    case = fst.parent.name
    dofs, initial, t_max = EXPECTED[case]
    assert {n for n in DOF_NAMES if p.dofs[n]} == dofs
    ic = p.initial_conditions
    linearization = fst.stem.endswith(("_lin", "_lin0")) or case == "blade_campbell"
    for name, value in initial.items():
        if linearization and name == "rotor_speed":
            continue
        if fst.stem.endswith("_lin0"):
            value = 0.0  # README: lin0 sets every initial displacement to 0
        assert math.isclose(getattr(ic, name), value, abs_tol=1e-15), name
    assert ic.azimuth == 0.0 and ic.blade_pitch == (0.0,) * 3
    if linearization:
        assert p.simulation.linearize
        if case != "blade_campbell":
            assert ic.rotor_speed == 0.0  # README: linearization copies set RotSpeed=0
    else:
        assert not p.simulation.linearize and p.simulation.total_time == t_max
    assert p.simulation.time_step == 0.01 and p.simulation.structural_model == 1
    assert p.n_tower_nodes == 20 and p.n_blade_nodes == 17
    assert p.blades[0] == p.blades[2]


@pytest.mark.parametrize("fst", [f for f in CASE_DECKS if f.parent.name == "blade_campbell"],
                         ids=lambda p: p.stem)
def test_campbell_decks(fst):
    p = read_openfast(fst)
    rpm = int(re.search(r"rpm(\d+)", fst.stem).group(1))
    assert math.isclose(p.initial_conditions.rotor_speed, rpm * RPM, rel_tol=1e-15)
    assert p.simulation.gravity == 0.0
    assert p.precone == (0.0,) * 3 and p.shaft_tilt == 0.0


def test_floating_case_platform(base_params):
    fst = OPENFAST / "cases/paper46_floating/paper46_floating.fst"
    p = read_openfast(fst)
    assert p.platform_mass == 7.5e6
    assert p.platform_roll_inertia == p.platform_pitch_inertia == 4.2e9
    assert p.platform_yaw_inertia == 1.6e8
    assert p.platform_cm == (0.0, 0.0, -90.0) and p.platform_reference == (0.0, 0.0, 20.0)
    assert p.tower_base_height == 20.0 and p.tower_height == 87.6
    assert p.tower != base_params.tower  # offshore tower file
    assert p.source_files["tower"].endswith("NRELOffshrBsline5MW_Offshore_ElastoDyn_Tower.dat")
    assert math.isclose(p.tower_flexible_length, 67.6)
    assert tower_top_mass(p) == tower_top_mass(base_params)
