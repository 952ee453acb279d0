"""MoorDyn's OPTIONS section, line-type and point columns: each modelled, accepted or refused by name.

References
----------
- OpenFAST v5.0.0 MoorDyn (``MD_Init`` in modules/moordyn/src/MoorDyn.f90): the option keys and aliases,
  compared in upper case; an unknown key is a warning; ``rhoW``/``g``/``WtrDpth`` in the file override the
  glue code's values.
- The closed-form elastic catenary with a frictionless resting part (fairlead forces H, V; wet weight
  w = (m - ρ A) g per length; V < w L): l = L - V/w + (H/w) asinh(V/H) + H L/EA,
  h = (H/w)(√(1 + (V/H)²) - 1) + V²/(2 EA w). A fairlead placed at (l, h) from its anchor has tension
  √(H² + V²) exactly when the model uses the same ρ and g (1e-9 relative).
- OpenFAST v5 + MoorDyn on ``fl_decay_a`` with ``1200 rhoW`` and ``10.5 g`` added to the MoorDyn file only
  (run 2025, /work/scratch/s24/moordyn_audit): FAIRTEN1..3 at t = 0 = 3.314e6, 2.331e6, 2.331e6 N (the stock
  deck: 3.181e6, 2.236e6, 2.236e6). mbsym with the file's values: -0.06 %, -0.01 %, -0.01 %.
"""

from __future__ import annotations

import math
import shutil
import warnings

import numpy as np
import pytest

from mbsym.exceptions import ModelWarning, OpenFASTFormatError, UnsupportedFeatureError
from mbsym.wind.deck.moordyn import read_moordyn
from mbsym.wind.offshore.mooring import mooring_from_moordyn

from .conftest import SEMI

MASS, DIAM, EA, LENGTH = 685.0, 0.333, 3.27e9, 850.0
AREA = math.pi / 4 * DIAM ** 2
OPTION_LINE = 17          # the first line of the OPTIONS section in _deck()


def _deck(tmp_path, options=(), *, type_extra="", ea="3.27E+09", ei="0", fair="0 0 0 0", anchor_z="-200.0",
          fairlead=(-58.0, 0.0, -14.0)):
    """A one-line MoorDyn file; ``options`` are the lines of its OPTIONS section (from line 17)."""
    text = f"""--------------------- MoorDyn Input File ------------------------------------
test deck
----------------------- LINE TYPES ------------------------------------------
Name  Diam  MassDen  EA       BA/-zeta  EI    Cd    Ca    CdAx   CaAx
(-)   (m)   (kg/m)   (N)      (N-s/-)   (-)   (-)   (-)   (-)    (-)
main  {DIAM}  {MASS}  {ea}  -1.0  {ei}  2.0   0.82  0.4    0.27 {type_extra}
---------------------- POINTS --------------------------------
ID   Type      X         Y       Z       M    V    CdA   CA
(-)  (-)      (m)       (m)     (m)    (kg) (m^3) (m^2) (-)
1   Vessel  {fairlead[0]}  {fairlead[1]}  {fairlead[2]}  {fair}
2   Fixed  -837.600    0.000 {anchor_z}     0    0    0    0
---------------------- LINES --------------------------------------
ID  LineType  AttachA   AttachB  UnstrLen  NumSegs  Outputs
(-)   (-)       (-)       (-)      (m)       (-)      (-)
1     main       2         1     {LENGTH}      50        -
---------------------- SOLVER OPTIONS ---------------------------------------
"""
    assert text.count("\n") == OPTION_LINE - 1
    text += "".join(line + "\n" for line in options)
    text += "------------------------ OUTPUTS --------------------------------------------\nFairTen1\nEND\n"
    path = tmp_path / "md.dat"
    path.write_text(text)
    return path


def _system(path, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        system = mooring_from_moordyn(read_moordyn(path), **{"water_density": 1025.0, "gravity": 9.81, **kw})
    return system, " | ".join(str(w.message) for w in caught if issubclass(w.category, ModelWarning))


def _closed_form(H, V, w):
    """Spans (l, h) of the elastic catenary with a frictionless resting part (module docstring)."""
    return (LENGTH - V / w + H / w * math.asinh(V / H) + H * LENGTH / EA,
            H / w * (math.sqrt(1 + (V / H) ** 2) - 1) + V ** 2 / (2 * EA * w))


# ----------------------------------------------------------------------------- reading
def test_options_keep_file_order_lines_and_case(tmp_path):
    md = read_moordyn(_deck(tmp_path, ["0.001  dtM  - step", "1100 RHO", "3e6 KB"]))
    assert md.option_entries == ((17, "dtM", "0.001"), (18, "RHO", "1100"), (19, "KB", "3e6"))


@pytest.mark.parametrize("line, match", [
    ("1025", r"line 17: an OPTIONS line needs '<value> <key>'"),
    ("abc rhoW", r"line 17, option 'rhoW': expected a number, got 'abc'"),
    ("1.5 writeLog", r"line 17, option 'writeLog': expected an integer"),
    ("Euler tScheme", r"line 17, option 'tScheme': MoorDyn in OpenFAST knows only RK2 and RK4"),
    ("2 WaterKin", r"line 17, option 'WaterKin': MoorDyn takes 'SEASTATE' or a water-kinematics file"),
])
def test_options_moordyn_cannot_read_are_format_errors(tmp_path, line, match):
    with pytest.raises(OpenFASTFormatError, match=match):
        read_moordyn(_deck(tmp_path, [line]))


# ----------------------------------------------------------------------------- refused
@pytest.mark.parametrize("line, match", [
    ("bathy.txt WtrDpth", r"line 18, option 'WtrDpth': 'bathy.txt' names a bathymetry file"),
    ("'Bathy.dat' depth", r"line 18, option 'depth': 'Bathy.dat' names a bathymetry file"),
    ("SEASTATE WaterKin", r"line 18, option 'WaterKin': 'SEASTATE' puts waves and current on the mooring lines"),
    ("waterkin.txt waterkin", r"line 18, option 'waterkin': 'waterkin.txt' puts waves"),
    ("0.3 mu_kT", r"line 18, option 'mu_kT': seabed friction 0.3"),
    ("0.2 MU_KA", r"line 18, option 'MU_KA': seabed friction 0.2"),
    ("0 kbot", r"line 18, option 'kbot': a seabed stiffness 0"),
    ("-1 KB", r"line 18, option 'KB': a seabed stiffness -1"),
])
def test_refused_options_name_line_and_key(tmp_path, line, match):
    md = read_moordyn(_deck(tmp_path, ["0.001 dtM", line]))
    with pytest.raises(UnsupportedFeatureError, match=match):
        mooring_from_moordyn(md, water_density=1025.0, gravity=9.81)


# ----------------------------------------------------------------------------- accepted
ACCEPTED = ["0.0005 dtM", "RK4 tScheme", "0.5 dtIC", "30 TmaxIC", "2 CdScaleIC", "0.005 threshIC",
            "2 writeLog", "0.1 dtOut", "0 OutSwitch", "1 disableOutTime", "1 inertialF", "5 inertialF_rampT",
            "0 mu_kT", "0 mu_kA", "1.5 mc", "100 cv", "150 FricDamp", "1e6 kBot", "1e5 CB"]


def test_numerical_and_output_options_change_nothing(tmp_path):
    q = np.array([6.0, -2.0, 1.0, 0.01, 0.05, 0.02])
    plain, _ = _system(_deck(tmp_path))
    (tmp_path / "b").mkdir()
    system, warned = _system(_deck(tmp_path / "b", ACCEPTED))
    assert system.tensions(q) == pytest.approx(plain.tensions(q), rel=1e-14)
    assert system.water_density == plain.water_density == 1025.0
    assert ("integration and initial-condition settings (dtM, tScheme, dtIC, TmaxIC, CdScaleIC, threshIC) do not "
            "apply to quasi-static lines") in warned


@pytest.mark.parametrize("line", ["1 Currents", "0 disableOutput", "1 ICgenDynamic", "3 WaveKin"])
def test_unknown_options_are_ignored_with_a_warning_as_moordyn_does(tmp_path, line):
    system, warned = _system(_deck(tmp_path, ["0.001 dtM", line]))
    key = line.split()[1]
    assert f"option '{key}' (line 18) is unknown to OpenFAST v5's MoorDyn, which warns and ignores it" in warned


# ----------------------------------------------------------------------------- modelled
@pytest.mark.parametrize("lines, rho, g", [
    (["1100 rhoW"], 1100.0, 9.81),
    (["1100 RHO"], 1100.0, 9.81),
    (["1000 rhow", "1100 Rho"], 1100.0, 9.81),            # aliases and case folded; the later line wins
    (["9.5 g"], 1025.0, 9.5),
    (["1100 rhoW", "9.5 G"], 1100.0, 9.5),
])
def test_file_density_and_gravity_override_the_fst_values(tmp_path, lines, rho, g):
    w = (MASS - rho * AREA) * g
    H, V = 1.2e6, 0.6 * w * LENGTH
    l, h = _closed_form(H, V, w)
    anchor = np.array([-837.6, 0.0, -200.0])
    fair = anchor + [l, 0.0, h]
    system, _ = _system(_deck(tmp_path, lines, fairlead=tuple(fair)), water_depth=200.0)
    assert system.tensions(np.zeros(6))[0] == pytest.approx(math.hypot(H, V), rel=1e-9)
    assert system.water_density == rho                                   # the lines' drag and added mass too
    plain = (MASS - 1025.0 * AREA) * 9.81                                # the .fst's values would differ
    assert abs(system.lines[0].weight / plain - 1) > 0.005


def test_anchors_must_lie_on_moordyn_seabed(tmp_path):
    _system(_deck(tmp_path), water_depth=200.0)                          # on it: fine
    with pytest.raises(UnsupportedFeatureError, match=r"line 11: anchor 2 is at z = -200.0 m, but MoorDyn's seabed "
                                                      r"is at -250.0 m \(depth from .*line 17 \(WtrDpth\)\)"):
        _system(_deck(tmp_path, ["250 WtrDpth"]), water_depth=200.0)
    with pytest.raises(UnsupportedFeatureError, match=r"seabed is at -210.0 m \(depth from the .fst / SeaState\)"):
        _system(_deck(tmp_path), water_depth=210.0)
    _system(_deck(tmp_path, ["200 WaterDepth"]), water_depth=250.0)       # the file's depth wins, as in MoorDyn


def test_an_anchor_on_the_seabed_takes_moordyn_depth(tmp_path):
    q = np.array([5.0, 1.0, 0.5, 0.0, 0.03, 0.0])
    plain, _ = _system(_deck(tmp_path), water_depth=200.0)
    for n, (z, options, depth) in enumerate([("seabed", [], 200.0), ("Ground", ["200 depth"], None),
                                             ("SEAFLOOR", ["200 WtrDpth"], 300.0)]):
        (tmp_path / str(n)).mkdir()
        system, _ = _system(_deck(tmp_path / str(n), options, anchor_z=z), water_depth=depth)
        assert system.anchors[0][2] == -200.0
        assert system.tensions(q) == pytest.approx(plain.tensions(q), rel=1e-14)
    with pytest.raises(UnsupportedFeatureError, match=r"line 11: anchor 2 is on the 'seabed', but no depth is known"):
        _system(_deck(tmp_path, anchor_z="seabed"))
    with pytest.raises(OpenFASTFormatError, match=r"line 11, column 'Z': expected a number or 'seabed', got 'deep'"):
        read_moordyn(_deck(tmp_path, anchor_z="deep"))


# ----------------------------------------------------------------------------- line types and points
@pytest.mark.parametrize("kw, match", [
    ({"ea": "3.27e9|5e9"}, r"line 6, line type 'main': EA '3.27e9\|5e9' is visco-elastic"),
    ({"ea": "ea_curve.txt"}, r"line 6, line type 'main': EA 'ea_curve.txt' is a tension-strain curve file"),
    ({"type_extra": "0.8"}, r"line 6, line type 'main': Cl = 0.8 switches on MoorDyn's vortex-induced vibration"),
    ({"fair": "1000 0 0 0"}, r"line 10: vessel point 1 has M = 1000.0, V = 0.0, CdA = 0.0"),
    ({"fair": "0 2.5 0 1"}, r"line 10: vessel point 1 has M = 0.0, V = 2.5"),
    ({"fair": "0 0 1.2 0"}, r"CdA = 1.2"),
])
def test_line_type_and_point_columns_refused(tmp_path, kw, match):
    with pytest.raises(UnsupportedFeatureError, match=match):
        _system(_deck(tmp_path, **kw))


def test_line_type_and_point_columns_accepted(tmp_path):
    plain, _ = _system(_deck(tmp_path))
    for n, kw in enumerate([{"type_extra": "0"}, {"type_extra": "0 0.08 0.18"}, {"fair": "0 0 0 1"}]):
        (tmp_path / str(n)).mkdir()
        system, _ = _system(_deck(tmp_path / str(n), **kw))
        assert system.tensions(np.zeros(6)) == pytest.approx(plain.tensions(np.zeros(6)), rel=1e-14)
    _, warned = _system(_deck(tmp_path / "0", ei="1e4"))
    assert "bending stiffness EI of line type(s) main" in warned
    with pytest.raises(OpenFASTFormatError, match=r"line 6: a line type has 10, 11 or 13 columns .* got 12"):
        read_moordyn(_deck(tmp_path, type_extra="0 1"))


# ----------------------------------------------------------------------------- OpenFAST
@pytest.mark.skipif(not SEMI.is_dir(), reason=f"shared floating deck not found at {SEMI}")
def test_file_density_and_gravity_against_openfast(tmp_path):
    path = tmp_path / "md.dat"
    shutil.copy(SEMI / "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat", path)
    text = path.read_text()
    path.write_text(text.replace("0.001     threshIC", "1200 rhoW\n10.5 g\n0.001     threshIC"))
    system, _ = _system(path, water_depth=200.0)
    q0 = np.array([10.0, 0.0, 1.5, 0.0, math.radians(4.0), 0.0])     # fl_decay_a's initial platform position
    openfast = np.array([3.314e6, 2.331e6, 2.331e6])                 # FAIRTEN1..3 at t = 0 (module docstring)
    assert system.tensions(q0) == pytest.approx(openfast, rel=2e-3)
    stock = np.array([3.180983e6, 2.235681e6, 2.235681e6])
    assert np.all(np.abs(openfast / stock - 1) > 0.04)               # the options moved OpenFAST by > 4 %
