"""Readers of the floating deck: HydroDyn, SeaState, WAMIT (.hst, .1, .3), MoorDyn, MAP++ (issue 20).

References
----------
- Every number is read by hand from the shared IEA 15 MW / VolturnUS-S deck
  (``../shared/openfast/floating``, the ``rosco`` 2.10.6 wheel's files); the file and line are named
  next to each check. Exact values: the readers convert text to float once (tolerance 0, or 1e-12
  relative where a unit is converted).
- Redimensionalization: HydroDyn's scaling (``WAMIT.f90``: ρ g L² for restoring translation terms, ρ L³
  for added mass, ρ L³ ω for damping, ρ g L² / ρ g L³ for excitation forces / moments) applied by hand
  to the file's numbers with ρ = 1025 kg/m³, g = 9.80665 m/s², L = 1 m (the deck's WAMITULEN), and the
  length scale checked by L = 2 against the same numbers times 2^k.
- Bad input: mutated copies of the deck files → :class:`OpenFASTFormatError` naming file, line and key.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError

from .conftest import FLOATING, SEMI

ROOT = SEMI / "HydroData" / "IEA-15-240-RWT-UMaineSemi"
RHO, G = 1025.0, 9.80665

pytestmark = pytest.mark.skipif(not SEMI.is_dir(), reason=f"shared floating deck not found at {SEMI}")


@pytest.fixture(scope="module")
def wamit():
    from mbsym.wind.deck.wamit import read_wamit

    return read_wamit(ROOT)


def _copy(tmp_path: Path, name: str) -> Path:
    target = tmp_path / name
    shutil.copy(SEMI / name, target)
    target.chmod(0o644)
    return target


def _replace(path: Path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8", errors="replace")
    assert text.count(old) == 1, (old, text.count(old))
    path.write_text(text.replace(old, new))


# ----------------------------------------------------------------------------- HydroDyn
def test_hydrodyn_platform_and_additional_loads():
    from mbsym.wind.deck.hydrodyn import read_hydrodyn

    hd = read_hydrodyn(SEMI / "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat")
    assert (hd.potential_model, hd.excitation_model, hd.radiation_model) == (1, 1, 1)   # lines 5, 6, 13
    assert hd.radiation_time_max == 60.0 and hd.radiation_time_step == "default"       # lines 14, 15
    assert hd.displaced_volume == (20206.34889,)                                       # line 24
    assert hd.wamit_length == (1.0,) and hd.reference_z == (0.0,)                      # lines 19, 22
    assert hd.potential_files[0] == SEMI / "HydroData" / "IEA-15-240-RWT-UMaineSemi"   # line 18, resolved
    assert hd.second_order == {"DiffQTF": 12}                                          # line 31
    assert np.array_equal(hd.add_force, np.zeros(6)) and not hd.add_stiffness.any()   # lines 34-45
    assert hd.add_quadratic_damping.shape == (6, 6)
    assert hd.add_quadratic_damping[0, 0] == 9.23e5 and hd.add_quadratic_damping[0, 4] == -8.92e6  # line 52
    assert hd.add_quadratic_damping[3, 1] == 8.92e6 and hd.add_quadratic_damping[5, 5] == 4.80e10  # lines 55, 57
    assert hd.lines["AddBQuad"] == 52 and hd.lines["PtfmVol0"] == 24
    assert not hd.has_morison_members and len(hd.tables["axial_coefficients"]) == 1    # lines 104, 66
    assert hd.tables["axial_coefficients"].rows[0][:4] == (1.0, 0.0, 0.0, 1.0)
    assert hd.outputs[0] == "B1WvsFxi" and len(hd.outputs) == 18                       # lines 129-146


def test_hydrodyn_case_file_differs_as_the_readme_says():
    """fl_decay_a's HydroDyn: DiffQTF 0 (README: first-order only) and HydroFxi… added to the outputs."""
    from mbsym.wind.deck.hydrodyn import read_hydrodyn

    hd = read_hydrodyn(FLOATING / "cases" / "fl_decay_a" / "fl_decay_a_HydroDyn.dat")
    assert hd.second_order == {} and hd.outputs[:6] == ("HydroFxi", "HydroFyi", "HydroFzi", "HydroMxi",
                                                        "HydroMyi", "HydroMzi")
    assert hd.potential_files[0].resolve() == ROOT.resolve()


def test_hydrodyn_morison_member_table_is_read(tmp_path):
    """A deck with joints, a property set and a member: the tables are kept as written."""
    from mbsym.wind.deck.hydrodyn import read_hydrodyn

    path = _copy(tmp_path, "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat")
    _replace(path, "0                      NJoints", "2                      NJoints")
    _replace(path, "    (-)         (m)         (m)         (m)         (-)      (switch)  \n",
             "    (-)         (m)         (m)         (m)         (-)      (switch)  \n"
             "1 0 0 -20 1 0\n2 0 0 10 1 0\n")
    _replace(path, "0           NPropSetsCyl", "1           NPropSetsCyl")
    _replace(path, " PropSetID     PropD     PropThck  \n    (-)         (m)         (m)    \n---------------------- RECT",
             " PropSetID     PropD     PropThck  \n    (-)         (m)         (m)    \n1 10.0 0.05\n"
             "---------------------- RECT")
    _replace(path, "0           NMembers", "1           NMembers")
    _replace(path, "(switch)   (switch)  (flag)   \n", "(switch)   (switch)  (flag)   \n1 1 2 1 1 1 0 1 1 1 TRUE\n")
    hd = read_hydrodyn(path)
    assert hd.has_morison_members
    assert hd.tables["joints"].rows == ((1.0, 0.0, 0.0, -20.0, 1.0, 0.0), (2.0, 0.0, 0.0, 10.0, 1.0, 0.0))
    assert hd.tables["cylinder_properties"].rows == ((1.0, 10.0, 0.05),)
    assert hd.tables["members"].rows[0][-1] == 1.0 and hd.tables["members"].columns[0] == "MemberID"


@pytest.mark.parametrize("old, new, line, key", [
    ("9.23E+05\t0.00E+00\t0.00E+00\t0.00E+00\t-8.92E+06", "9.23E+05\tabc\t0.00E+00\t0.00E+00\t-8.92E+06", 52, "AddBQuad"),
    ("   20206.34889   PtfmVol0", "   20206.34889   PtfmVolume", 24, "PtfmVol0"),
    ("             1   PotMod ", "             7   PotMod ", 5, "PotMod"),
    ('     "DEFAULT"   RdtnDT ', "           0.0   RdtnDT ", 15, "RdtnDT"),
])
def test_hydrodyn_errors_name_file_line_key(tmp_path, old, new, line, key):
    from mbsym.wind.deck.hydrodyn import read_hydrodyn

    path = _copy(tmp_path, "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat")
    _replace(path, old, new)
    with pytest.raises(OpenFASTFormatError, match=rf"{path.name}, line {line}, key '{key}'"):
        read_hydrodyn(path)


def test_hydrodyn_time_step_of_the_radiation_is_checked_with_potential_flow_only(tmp_path):
    """OpenFAST (HydroDyn_Input.f90) checks ``RdtnDT > 0`` only with ``PotMod = 1``: the ROSCO wheel's monopile
    (PotMod 0) has 0.0 there, which was refused."""
    from mbsym.wind.deck.hydrodyn import read_hydrodyn

    path = _copy(tmp_path, "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat")
    _replace(path, '     "DEFAULT"   RdtnDT ', "           0.0   RdtnDT ")
    _replace(path, "             1   PotMod ", "             0   PotMod ")
    hd = read_hydrodyn(path)
    assert hd.potential_model == 0 and hd.radiation_time_step == 0.0


def test_hydrodyn_missing_file():
    from mbsym.wind.deck.hydrodyn import read_hydrodyn

    with pytest.raises(OpenFASTFormatError, match="HydroDyn input file not found"):
        read_hydrodyn(SEMI / "nope.dat")


# ----------------------------------------------------------------------------- SeaState
def test_seastate_waves_and_points():
    from mbsym.wind.deck.seastate import read_seastate

    sea = read_seastate(SEMI / "IEA-15-240-RWT-UMaineSemi_SeaState.dat")
    assert sea.water_density == "default" and sea.water_depth == "default"       # lines 5-6
    assert sea.resolved(1025.0, 200.0) == {"water_density": 1025.0, "water_depth": 200.0, "msl_to_swl": 0.0}
    assert sea.wave_model == 2 and sea.wave_model_name == "JONSWAP/Pierson-Moskowitz"  # line 16
    assert (sea.wave_height, sea.peak_period) == (1.10, 8.52)                     # lines 21-22
    # WavePkShp DEFAULT (line 23): Tp/sqrt(Hs) = 8.12 >= 5 -> gamma = 1 (SeaState's IEC rule)
    assert sea.peak_shape == 1.0
    assert sea.low_cutoff == 0.111527 and sea.high_cutoff == 3.2                  # lines 24-25
    assert sea.seeds == (-561580799, "RANLUX")                                    # lines 31-32
    assert sea.current_model == 0 and sea.current_subsurface_direction == "default"  # lines 49, 51
    assert sea.elevation_points == ((0.0, 0.0),)                                  # lines 64-66
    assert sea.kinematics_points == ((5.0, 5.0, -10.0), (-5.0, -5.0, -15.0))       # lines 67-70
    assert sea.outputs == ("Wave1Elev",) and sea.lines["WaveMod"] == 16


def test_seastate_still_water_case_and_peak_shape_rule():
    from mbsym.wind.deck.seastate import default_peak_shape, read_seastate

    sea = read_seastate(FLOATING / "cases" / "fl_decay_a" / "fl_decay_a_SeaState.dat")
    assert sea.wave_model == 0 and sea.wave_model_name == "still water" and sea.elevation_file is None
    # IEC 61400-3 (SeaState Waves.f90): 5 below Tp/sqrt(Hs) = 3.6, 1 above 5, exp(5.75 - 1.15 r) between
    assert default_peak_shape(2, 4.0, 7.0) == 5.0 and default_peak_shape(2, 1.0, 5.0) == 1.0
    assert math.isclose(default_peak_shape(2, 4.0, 8.0), math.exp(5.75 - 1.15 * 4.0), rel_tol=1e-15)
    assert default_peak_shape(1, 4.0, 8.0) == 1.0


@pytest.mark.parametrize("new, expected", [("1P45", (10, math.radians(45.0))), ("5", (5, 0.0))])
def test_seastate_regular_phase_and_external_elevation(tmp_path, new, expected):
    from mbsym.wind.deck.seastate import read_seastate

    path = _copy(tmp_path, "IEA-15-240-RWT-UMaineSemi_SeaState.dat")
    _replace(path, "           2     WaveMod", f"           {new}     WaveMod")
    sea = read_seastate(path)
    assert (sea.wave_model, sea.wave_phase) == pytest.approx(expected, rel=1e-15)
    if new == "5":
        assert sea.elevation_file == tmp_path / "none.Elev"   # WvKinFile "none" (line 34) + ".Elev"


@pytest.mark.parametrize("old, new, line, key", [
    ("           2     WaveMod", "           9     WaveMod", 16, "WaveMod"),
    ("        DEFAULT  WavePkShp", "            9.0  WavePkShp", 23, "WavePkShp"),
    ("           1.10  WaveHs", "           1.10  WaveHeight", 21, "WaveHs"),
])
def test_seastate_errors_name_file_line_key(tmp_path, old, new, line, key):
    from mbsym.wind.deck.seastate import read_seastate

    path = _copy(tmp_path, "IEA-15-240-RWT-UMaineSemi_SeaState.dat")
    _replace(path, old, new)
    with pytest.raises(OpenFASTFormatError, match=rf"{path.name}, line {line}, key '{key}'"):
        read_seastate(path)


# ----------------------------------------------------------------------------- WAMIT
def test_wamit_raw_numbers(wamit):
    assert wamit.hst.shape == (6, 6)
    assert wamit.hst[2, 2] == 4.430486e2 and wamit.hst[4, 4] == 2.182166e5       # .hst lines 15, 29
    assert wamit.hst[2, 4] == -4.012296e-1                                         # .hst line 17
    assert list(wamit.periods[:3]) == [-1.0, 0.0, 1.256637e2]                      # .1 lines 1, 19, 37
    assert len(wamit.periods) == 102
    assert wamit.added_mass[0, 2, 2] == 2.627505e4 and wamit.added_mass[1, 2, 2] == 2.421631e4  # .1 lines 8, 26
    assert wamit.damping[0].sum() == 0 and wamit.damping[1].sum() == 0             # limits: no damping
    assert wamit.damping[2, 2, 2] == 2.408925e2 and wamit.added_mass[2, 0, 4] == -1.173755e5  # lines 44, 39
    assert wamit.excitation.shape == (100, 37, 6)
    assert wamit.excitation[0, 0, 0] == complex(1.211069e-1, -3.698876e1)           # .3 line 1


def test_wamit_redimensionalized_as_hydrodyn(wamit):
    dim = wamit.redimensionalize(RHO, G, 1.0)
    assert dim.restoring[2, 2] == pytest.approx(4.430486e2 * RHO * G, rel=1e-12)
    assert dim.added_mass_infinite[2, 2] == pytest.approx(2.421631e4 * RHO, rel=1e-12)
    assert dim.added_mass_zero[2, 2] == pytest.approx(2.627505e4 * RHO, rel=1e-12)
    # lowest frequency first: T = 125.6637 s, omega = 0.05 rad/s; B = B~ rho omega
    assert dim.frequencies[0] == pytest.approx(2 * math.pi / 1.256637e2, rel=1e-12)
    assert dim.damping[0, 2, 2] == pytest.approx(2.408925e2 * RHO * dim.frequencies[0], rel=1e-12)
    # .3 line 4327/4331: T = 6.283185 s, heading 0: surge force and pitch moment per metre of wave amplitude
    k = int(np.argmin(abs(dim.excitation_frequencies - 1.0)))
    h = int(np.argmin(abs(dim.headings)))
    assert dim.excitation[k, h, 0] == pytest.approx(complex(5.021147e2, -1.143290e2) * RHO * G, rel=1e-12)
    assert dim.excitation[k, h, 4] == pytest.approx(complex(-2.346050e3, -2.515832e3) * RHO * G, rel=1e-12)
    # the length scale: L = 2 multiplies a restoring term by L^(2 + rotations), added mass by L^(3 + rotations)
    two = wamit.redimensionalize(RHO, G, 2.0)
    assert two.restoring[2, 4] == pytest.approx(dim.restoring[2, 4] * 2 ** 3, rel=1e-12)
    assert two.restoring[4, 4] == pytest.approx(dim.restoring[4, 4] * 2 ** 4, rel=1e-12)
    assert two.added_mass_infinite[0, 4] == pytest.approx(dim.added_mass_infinite[0, 4] * 2 ** 4, rel=1e-12)
    assert two.excitation[k, h, 4] == pytest.approx(dim.excitation[k, h, 4] * 2 ** 3, rel=1e-12)


def test_wamit_bad_rows(tmp_path):
    from mbsym.wind.deck.wamit import read_wamit_1, read_wamit_hst

    hst = tmp_path / "x.hst"
    hst.write_text("1 1 0.0\n3 3 4.4e2 extra\n")
    with pytest.raises(OpenFASTFormatError, match=r"x.hst, line 2: expected 3 numbers"):
        read_wamit_hst(hst)
    one = tmp_path / "x.1"
    one.write_text("-1 3 3 2.6e4\n10.0 3 3 2.6e4\n")
    with pytest.raises(OpenFASTFormatError, match=r"x.1, line 2: a finite period"):
        read_wamit_1(one)
    with pytest.raises(OpenFASTFormatError, match="WAMIT .* file not found"):
        read_wamit_hst(tmp_path / "none.hst")


# ----------------------------------------------------------------------------- mooring
def test_moordyn_tables():
    from mbsym.wind.deck.moordyn import read_moordyn

    md = read_moordyn(SEMI / "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat")
    main = md.line_types["main"]                                                  # line 7
    assert (main.diameter, main.mass_per_length, main.axial_stiffness) == (0.333, 685.0, 3.27e9)
    assert main.axial_damping == -1.0 and (main.drag_transverse, main.added_mass_transverse) == (2.0, 0.82)
    assert md.points[2].kind == "fixed" and md.points[2].position == (-837.6, 0.0, -200.0)   # line 12
    assert md.points[3].kind == "vessel" and md.points[3].position == (29.0, 50.229, -14.0)  # line 13
    assert md.lines[1].length == 850.0 and md.lines[1].n_segments == 50                      # line 20
    assert md.fairlead(1).id == 1 and md.anchor(3).id == 6
    assert md.options["kbot"] == 3.0e6 and md.options["TmaxIC"] == 60.0                      # lines 25, 28
    assert md.outputs[:3] == ("FairTen1", "FairTen2", "FairTen3") and md.other_sections == {}


def test_moordyn_unknown_line_type(tmp_path):
    from mbsym.wind.deck.moordyn import read_moordyn

    path = _copy(tmp_path, "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat")
    _replace(path, "2     main       4", "2     chain      4")
    with pytest.raises(OpenFASTFormatError, match=r"line 21, column 'LineType': 'chain' is not a line type"):
        read_moordyn(path)


def test_map_tables_and_repeat():
    from mbsym.wind.deck.mapplusplus import read_map

    mp = read_map(SEMI / "IEA-15-240-RWT-UMaineSemi_MAP.dat")
    main = mp.line_types["main"]                                                  # line 4
    assert (main.diameter, main.mass_per_length, main.axial_stiffness, main.seabed_friction) == (0.333, 685.0,
                                                                                                 3.27e9, 1.0)
    assert mp.nodes[1].kind == "fix" and mp.nodes[1].z_at_seabed                  # line 8: Z = depth
    assert mp.nodes[2].position == (-58.0, 0.0, -14.0)                            # line 9
    assert mp.lines[1].length == 850.0 and (mp.lines[1].anchor, mp.lines[1].fairlead) == (1, 2)  # line 13
    assert np.degrees(mp.repeat_angles) == pytest.approx([120.0, 240.0], rel=1e-15)   # line 19
    copies = mp.repeated_positions(1, 200.0)
    assert copies[0] == pytest.approx([-837.8, 0.0, -200.0], abs=0)
    # rotated by 120 deg: (-837.8 cos 120, -837.8 sin 120) = (418.9, -725.556)
    assert copies[1] == pytest.approx([418.9, -837.8 * math.sin(math.radians(120)), -200.0], rel=1e-12)


def test_map_bad_node(tmp_path):
    from mbsym.wind.deck.mapplusplus import read_map

    path = _copy(tmp_path, "IEA-15-240-RWT-UMaineSemi_MAP.dat")
    _replace(path, "2   Vessel   -58.000", "2   Boat     -58.000")
    with pytest.raises(OpenFASTFormatError, match=r"line 9, column 'Type': 'Boat'"):
        read_map(path)


def test_wamit_ss_bad_counts(tmp_path):
    from mbsym.wind.deck.wamit import read_wamit_ss

    good = (SEMI / "HydroData" / "IEA-15-240-RWT-UMaineSemi.ss").read_text()
    (tmp_path / "x.ss").write_text(good.replace("14 14  6 10 10  6", "14 14  6 10 10  7", 1))
    with pytest.raises(OpenFASTFormatError, match=r"x.ss, line 3: 60 states, but the states per DOF"):
        read_wamit_ss(tmp_path / "x.ss")
    lines = good.splitlines()
    lines[7] = " ".join(lines[7].split()[:-1])            # a row of A one number short
    (tmp_path / "y.ss").write_text("\n".join(lines))
    with pytest.raises(OpenFASTFormatError, match=r"y.ss, line 8: expected 60 numbers, got 59"):
        read_wamit_ss(tmp_path / "y.ss")
