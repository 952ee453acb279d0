"""Unsteady-aero (Beddoes-Leishman) constants of AeroDyn airfoil files: parsing and defaults.

Reference data: the AeroDyn 15 airfoil files of the IEA 15 MW (``shared/openfast/floating/
IEA-15-240-RWT/Airfoils``) and of the NREL 5 MW (``shared/openfast/aero/openfast_inputs/deck/
Airfoils``), next to the repository (``../shared``); the tests needing them skip when absent.

Reference values (``OPENFAST``): printed by OpenFAST v5.0.0's own ``AFI_Init`` (AirfoilInfo.f90
with the NWTC library), built from the v5.0.0 source with gfortran 12.2 in double precision
(``-DDOUBLE_PRECISION=ON``, like the shared OpenFAST binary), called with UAMod = 3, AFTabMod = 1,
InCol = (1, 2, 3, 4) on the files named, and ``ES26.17`` output of ``p%Table(1)%UA_BL``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError, ParameterError
from mbsym.wind.deck.airfoil_ua import UA_KEYS, UACoefficients, ua_coefficients_from_polar
from mbsym.wind.deck.airfoils import AirfoilPolar, _constant_data, read_airfoil


def _find_shared() -> Path:
    here = Path(__file__).resolve()
    for parent in here.parents[2:]:  # the repository root, then its ancestors
        if (parent / "shared" / "openfast").is_dir():
            return parent / "shared"
    return here.parents[2].parent / "shared"


SHARED = _find_shared()
IEA = SHARED / "openfast" / "floating" / "IEA-15-240-RWT" / "Airfoils"
NREL = SHARED / "openfast" / "aero" / "openfast_inputs" / "deck" / "Airfoils"
DEG = math.pi / 180.0
# Polar-derived constants (the other keys are fixed defaults or read values).
DERIVED = ("alpha0", "alpha1", "alpha2", "C_nalpha", "C_lalpha", "Cn1", "Cn2", "Cd0", "Cm0",
           "alphaUpper", "alphaLower")


def iea(number: int) -> Path:
    path = IEA / f"IEA-15-240-RWT_AeroDyn15_Polar_{number:02d}.dat"
    if not path.is_file():
        pytest.skip(f"shared reference data not found at {path}")
    return path


def nrel(name: str) -> Path:
    path = NREL / f"{name}.dat"
    if not path.is_file():
        pytest.skip(f"shared reference data not found at {path}")
    return path


# OpenFAST v5.0.0 AFI_Init output (see the module docstring); "all computed" = the polar of the
# file with the UA lines removed and InclUAdata = False.
OPENFAST = {
    # InclUAdata False, cylinder-like polar (max Cl < 0.01 within +/-20 deg)
    ("Polar_01", "file"): dict(
        alpha0=0.0, alpha1=1.74532925199432948e-01, alpha2=-1.74532925199432948e-01, C_nalpha=0.0,
        C_lalpha=0.0, Cn1=0.0, Cn2=0.0, Cd0=3.49992053110435020e-01, Cm0=0.0,
        alphaUpper=7.93331478179241517e-02, alphaLower=-7.93331478179239713e-02),
    # InclUAdata False, degenerate root polar: OpenFAST finds alphaUpper == alphaLower
    ("Polar_02", "file"): dict(
        alpha0=-3.75393233075828370e+00, alpha1=4.10416818044726572e-01,
        alpha2=-1.58650429006284566e+00, C_nalpha=4.06664240216715323e-02,
        C_lalpha=8.73238888740704711e-02, Cn1=1.60015869255743515e-01,
        Cn2=-1.04698403678232799e-01, Cd0=3.31585267832590014e-01, Cm0=-9.00230260490810934e-05,
        alphaUpper=3.01465961708111907e-01, alphaLower=3.01465961708111907e-01),
    # the file's numbers for alpha0..Cm0, computed alphaUpper/alphaLower/C_lalpha
    ("Polar_05", "file"): dict(
        alpha0=-6.46793015383243797e-02, alpha1=3.05745277381209934e-01,
        alpha2=-3.00597934897935737e-01, C_nalpha=5.37732000000000010e+00,
        C_lalpha=5.10979467992415959e+00, Cn1=1.67009199999999991e+00,
        Cn2=-1.10138699999999989e+00, Cd0=1.82988000000000012e-01, Cm0=-6.53859999999999997e-02,
        alphaUpper=2.59154949538551116e-01, alphaLower=-1.53377419114653246e-01),
    ("Polar_20", "all computed"): dict(
        alpha0=-4.87921668228673139e-02, alpha1=2.57973157578383017e-01,
        alpha2=-2.05800803860169634e-01, C_nalpha=7.91850224298659811e+00,
        C_lalpha=7.92469149837998899e+00, Cn1=1.94059508714291762e+00,
        Cn2=-1.04955660269864737e+00, Cd0=1.19361347460918005e-02, Cm0=-8.51952226180468231e-02,
        alphaUpper=8.99109008603139193e-02, alphaLower=-8.99109008603139193e-02),
    ("Polar_40", "all computed"): dict(
        alpha0=-5.25079234385622401e-02, alpha1=2.55816839253523554e-01,
        alpha2=-2.41264003820658074e-01, C_nalpha=7.12756471246182954e+00,
        C_lalpha=7.14034182847152188e+00, Cn1=1.76254763662614966e+00,
        Cn2=-1.13023177650142248e+00, Cd0=6.63685060622060986e-03, Cm0=-7.97913920821925332e-02,
        alphaUpper=8.99109008603139193e-02, alphaLower=-1.63955172157043000e-01),
    ("DU25_A17", "file"): dict(
        alpha0=-5.58505360638185469e-02, alpha1=1.48352986419518024e-01,
        alpha2=-1.48352986419518024e-01, C_nalpha=6.44620000000000015e+00,
        C_lalpha=7.56864962631025495e+00, Cn1=1.43359999999999999e+00,
        Cn2=-6.87300000000000022e-01, Cd0=6.00000000000000012e-03, Cm0=-1.19999999999999996e-01,
        alphaUpper=6.10865238198015359e-02, alphaLower=-1.30027029273577566e-01),
}


# ----------------------------------------------------------------------------- parsing
def test_numeric_keys_are_read_and_converted_default_keys_get_openfast_constants():
    # Polar_05 lists alpha0..Cm0 as numbers (deg for the angles), "Default" for the time
    # constants, and has no alphaUpper, alphaLower, C_lalpha, UACutout_delta lines.
    ua = read_airfoil(iea(5)).ua
    assert ua is not None
    read = dict(alpha0=-3.705851 * DEG, alpha1=17.517914 * DEG, alpha2=-17.222993 * DEG,
                eta_e=1.0, C_nalpha=5.377320, Cn1=1.670092, Cn2=-1.101387, Cd0=0.182988,
                Cm0=-0.065386, S1=0.0, S2=0.0, S3=0.0, S4=0.0, k0=0.0, k1=0.0, k2=0.0, k3=0.0,
                k1_hat=0.0)
    for key, value in read.items():
        assert getattr(ua, key) == pytest.approx(value, rel=1e-15, abs=0.0), key
    # OpenFAST v5 CalculateUACoeffs defaults for UA_Mod 2/3; UACutout 45 deg, delta 5 deg
    defaults = dict(T_f0=3.0, T_V0=6.0, T_p=1.7, T_VL=11.0, b1=0.14, b2=0.53, b5=5.0, A1=0.3,
                    A2=0.7, A5=1.0, St_sh=0.19, x_cp_bar=0.2, UACutout=45 * DEG,
                    UACutout_delta=5 * DEG, filtCutOff=0.5)
    for key, value in defaults.items():
        assert getattr(ua, key) == value, key
    assert ua.UACutout_blend == pytest.approx(40 * DEG, abs=1e-15)
    assert ua.computed == set(defaults) | {"alphaUpper", "alphaLower", "C_lalpha"}
    assert set(read).isdisjoint(ua.computed)


def test_quoted_default_and_numbers_of_the_nrel5mw_files():
    # DU21_A17 gives every time constant as a number and "DEFAULT" (quoted) for UACutout
    # and filtCutOff; no UACutout_delta line.
    ua = read_airfoil(nrel("DU21_A17")).ua
    assert (ua.T_f0, ua.T_V0, ua.T_p, ua.T_VL, ua.x_cp_bar) == (3.0, 6.0, 1.7, 11.0, 0.2)
    assert ua.alpha1 == pytest.approx(8 * DEG, rel=1e-15) and ua.C_nalpha == 6.2047
    assert ua.computed == {"UACutout", "UACutout_delta", "filtCutOff", "alphaUpper",
                           "alphaLower", "C_lalpha"}
    assert ua.filtCutOff == 0.5  # a reduced frequency, although the file comment says Hz


def test_a_given_angle_is_read_in_deg_and_alpha_upper_lower_are_snapped(tmp_path):
    # A given UACutout [deg] is converted; given alphaUpper/alphaLower are still snapped to
    # the nearest table angle inside the region (OpenFAST v5 ComputeUA360_AttachedFlow).
    path = tmp_path / "polar.dat"
    text = iea(5).read_text(encoding="latin-1")
    text = text.replace("Default                  UACutout ", "30                       UACutout ")
    text = text.replace("-17.222993               alpha2 ", "-17.222993  alpha2\n"
                        "7.0  alphaUpper\n-4.0  alphaLower\n")
    path.write_text(text, encoding="latin-1")
    polar = read_airfoil(path)
    ua = polar.ua
    assert ua.UACutout == pytest.approx(30 * DEG, rel=1e-15)
    assert ua.UACutout_blend == pytest.approx(25 * DEG, rel=1e-15)
    table = np.degrees(polar.alpha)
    assert math.degrees(ua.alphaUpper) == pytest.approx(table[table <= 7.0][-1], abs=1e-12)
    assert math.degrees(ua.alphaLower) == pytest.approx(table[table >= -4.0][0], abs=1e-12)
    assert not {"UACutout", "alphaUpper", "alphaLower"} & ua.computed


# ----------------------------------------------------------------------------- OpenFAST
@pytest.mark.parametrize("name, variant", list(OPENFAST))
def test_constants_equal_openfast_afi_init(name, variant):
    # Reference: OpenFAST v5.0.0 AFI_Init itself (module docstring). Measured agreement of
    # this implementation on all 58 shared airfoil files, as given and all computed, with and
    # without Cm, UAMod 2 and 3: max |d| / max(1, |ref|) = 1.4e-13 (alpha0 of Polar_02), i.e.
    # rounding; the tolerance 1e-11 leaves 70x room and still fails on any algorithmic change.
    path = nrel(name) if name.startswith("DU") else iea(int(name.split("_")[1]))
    polar = read_airfoil(path)
    ua = polar.ua if variant == "file" else ua_coefficients_from_polar(
        polar.alpha, polar.cl, polar.cd, polar.cm, {}, has_cm=True)
    for key, expected in OPENFAST[(name, variant)].items():
        assert getattr(ua, key) == pytest.approx(expected, rel=1e-11, abs=1e-11), key


def test_without_cm_column_cm0_is_zero():
    polar = read_airfoil(iea(20), columns=(1, 2, 3, 0))
    assert polar.ua.Cm0 == -0.085427  # given in the file: kept
    ua = ua_coefficients_from_polar(polar.alpha, polar.cl, polar.cd, None, {}, has_cm=False)
    assert ua.Cm0 == 0.0
    expected = OPENFAST[("Polar_20", "all computed")]
    assert ua.alpha1 == pytest.approx(expected["alpha1"], rel=1e-11)  # Cm plays no other part


# ----------------------------------------------------------------------------- file numbers
# Max |computed - file| over Polar_05..49 measured with this implementation (angles in deg):
MEASURED = dict(alpha0=0.107, alpha1=3.55, alpha2=3.58, C_nalpha=0.328, Cn1=0.148, Cn2=0.522,
                Cd0=1.54e-3, Cm0=5.8e-4)


def test_defaults_from_the_polar_against_the_file_numbers():
    """Recompute alpha0..Cm0 of Polar_05..49 from the polar alone and compare with the file.

    The file's numbers do NOT come from OpenFAST's algorithm: they were written by WISDEM's
    ``Polar.unsteadyParams`` (WISDEM/WISDEM ``wisdem/ccblade/Polar.py``, used by the
    AeroElasticSE writer named in the file header), which defines alpha0 as the zero crossing
    of Cl (OpenFAST: the zero of a line fitted to Cn), Cd0 and Cm0 as Cd, Cm at that alpha0
    (OpenFAST: Cd0 = min Cd within +/-20 deg, Cm0 = Cm at its own alpha0), C_nalpha as a fit
    on a 720-point resampled polar over alpha0cn + [-5, 10] deg, alpha1/alpha2 from a
    Kirchhoff f = 0.7 line and Cn1/Cn2 at Cn inflection points.  The first three definitions
    are checked below against the file to its 6 printed decimals.  So the agreement is only
    that of two estimators of the same quantities; the tolerances are the measured maxima
    (``MEASURED``) plus 25 %: they catch unit or sign errors and a wrong branch, while the
    exact check against OpenFAST is ``test_constants_equal_openfast_afi_init``.
    """
    worst = dict.fromkeys(MEASURED, 0.0)
    for number in range(5, 50):
        polar = read_airfoil(iea(number))
        given = polar.ua
        mine = ua_coefficients_from_polar(polar.alpha, polar.cl, polar.cd, polar.cm, {}, True)
        assert mine.computed == set(UA_KEYS)
        for key in MEASURED:
            scale = 1 / DEG if key.startswith("alpha") else 1.0
            worst[key] = max(worst[key], abs(getattr(mine, key) - getattr(given, key)) * scale)
        # Cd0 is OpenFAST's minimum Cd within +/-20 deg, never above the file's Cd(alpha0)
        near = np.abs(polar.alpha) <= 20 * DEG
        assert mine.Cd0 == polar.cd[near].min() <= given.Cd0 + 5e-7
        # the file's alpha0, Cd0, Cm0: WISDEM's definitions (Cl zero crossing, values there)
        a, cl = polar.alpha, polar.cl
        j = next(j for j in range(1, a.size) if abs(a[j]) <= 30 * DEG and cl[j - 1] < 0 <= cl[j])
        alpha0 = a[j - 1] - cl[j - 1] * (a[j] - a[j - 1]) / (cl[j] - cl[j - 1])
        assert math.degrees(alpha0 - given.alpha0) == pytest.approx(0, abs=1e-6)
        assert np.interp(alpha0, a, polar.cd) == pytest.approx(given.Cd0, abs=1e-6)
        assert np.interp(alpha0, a, polar.cm) == pytest.approx(given.Cm0, abs=1e-6)
    for key, limit in MEASURED.items():
        assert worst[key] <= 1.25 * limit, (key, worst[key])


# ----------------------------------------------------------------------------- constant data
def test_constant_data_polar00_versus_polar01():
    # Polar_00: Cl, Cd, Cm constant to 4e-16 (ConstData: no UA constants). Polar_01: Cl varies
    # by 1.3e-4, far above EqualRealNos (1.1e-14 in double precision): UA constants computed, by
    # the cylinder branch (max Cl < 0.01 within +/-20 deg).
    p00, p01 = read_airfoil(iea(0)), read_airfoil(iea(1))
    assert p00.constant_data and p00.ua is None
    assert not p01.constant_data and p01.ua is not None
    assert p01.ua.computed == set(UA_KEYS)
    assert (p01.ua.alpha0, p01.ua.C_nalpha, p01.ua.Cn1, p01.ua.Cn2) == (0.0, 0.0, 0.0, 0.0)
    assert p01.ua.alpha1 == pytest.approx(10 * DEG) and p01.ua.alpha2 == pytest.approx(-10 * DEG)
    assert read_airfoil(nrel("Cylinder1")).constant_data  # 3 equal rows


def test_constant_data_uses_double_precision_equal_real_nos():
    # NWTC EqualRealNos in OpenFAST's double-precision build (the shared v5.0.0 binary): |a - b| <=
    # max(|a + b|, 1) * 100 eps / 2, eps = 2^-52, i.e. 1.1e-14 near 0 and 2.2e-14 between values near 1.
    base = np.zeros((4, 2))
    for step, constant in ((1.0e-14, True), (1.3e-14, False), (1.0e-7, False)):
        table = base.copy()
        table[2, 0] = step
        assert _constant_data(table) is constant, step
    table = np.ones((4, 2))
    table[1, 1] = 1.0 + 2.0e-14
    assert _constant_data(table)
    table[1, 1] = 1.0 + 3.0e-14
    assert not _constant_data(table)
    assert _constant_data(np.array([[0.0, 1.0], [5.0, 9.0]]))  # fewer than 3 rows


# ----------------------------------------------------------------------------- errors
def _edit(tmp_path: Path, old: str, new: str) -> Path:
    path = tmp_path / "polar.dat"
    text = iea(5).read_text(encoding="latin-1")
    assert old in text
    path.write_text(text.replace(old, new), encoding="latin-1")
    return path


@pytest.mark.parametrize("old, new, message", [
    ("1.000000                 eta_e", "Default   eta_e",
     r"line 21, key 'eta_e': AeroDyn reads eta_e as a number only"),
    ("Default                  T_f0", "x.y   T_f0",
     r"line 23, key 'T_f0': expected a number or \"Default\", got 'x.y'"),
    ("-3.705851                alpha0", "abc   alpha0",
     r"line 18, key 'alpha0': expected a number, got 'abc'"),
    ("True                     InclUAdata", "False   InclUAdata",
     r"line 18, key 'alpha0': InclUAdata is False \(or missing\)"),
])
def test_malformed_ua_values_name_file_line_and_key(tmp_path, old, new, message):
    # OpenFAST v5.0.0 stops on each of these (checked with AFI_Init: "The variable NumAlf was
    # not found"), since ParseVar does not consume a line it cannot read.
    path = _edit(tmp_path, old, new)
    with pytest.raises(OpenFASTFormatError, match=message) as info:
        read_airfoil(path)
    assert str(path) in str(info.value)


def test_missing_lines_are_computed(tmp_path):
    path = _edit(tmp_path, "17.517914                alpha1", "")
    ua = read_airfoil(path).ua
    assert "alpha1" in ua.computed
    assert ua.alpha1 == pytest.approx(0.367601617458666, rel=1e-11)  # OpenFAST v5.0.0 AFI_Init


# ----------------------------------------------------------------------------- records
def test_records_round_trip_and_validate():
    polar = read_airfoil(iea(5))
    again = AirfoilPolar.from_dict(polar.to_dict())
    assert again == polar and isinstance(again.ua, UACoefficients)
    assert again.ua.computed == polar.ua.computed and isinstance(again.ua.computed, frozenset)
    plain = AirfoilPolar(name="x", alpha=np.array([-math.pi, math.pi]), cl=np.zeros(2),
                         cd=np.zeros(2), cm=np.zeros(2), reynolds=1e6)
    assert plain.ua is None and plain.constant_data is False
    with pytest.raises(ParameterError, match="computed names unknown"):
        UACoefficients(**{k: 0.0 for k in UA_KEYS}, computed=frozenset({"nope"}))
    with pytest.raises(ParameterError, match="unknown UA constant"):
        ua_coefficients_from_polar(polar.alpha, polar.cl, polar.cd, polar.cm, {"T_f": 1.0}, True)


def test_given_values_are_kept_and_only_missing_ones_computed():
    polar = read_airfoil(iea(30))
    given = {"alpha1": 0.2, "C_nalpha": 6.0, "T_f0": None}
    ua = ua_coefficients_from_polar(polar.alpha, polar.cl, polar.cd, polar.cm, given, True)
    assert (ua.alpha1, ua.C_nalpha, ua.T_f0) == (0.2, 6.0, 3.0)
    assert ua.Cn1 == pytest.approx(np.interp(0.2, polar.alpha, polar.cl * np.cos(polar.alpha)
                                             + (polar.cd - ua.Cd0) * np.sin(polar.alpha)))
    assert ua.computed == set(UA_KEYS) - {"alpha1", "C_nalpha"}


def test_synthetic_flat_plate_polar():
    # Works without ../shared: a flat-plate-like polar (Cl = 2 pi sin a cos a, Cd = 0.01 +
    # 2 sin^2 a) has Cn slope 2 pi at 0 deg, alpha0 = 0 and Cd0 = 0.01.
    alpha = np.radians(np.arange(-180.0, 180.5, 0.5))
    cl = 2 * np.pi * np.sin(alpha) * np.cos(alpha)
    cd = 0.01 + 2 * np.sin(alpha) ** 2
    ua = ua_coefficients_from_polar(alpha, cl, cd, None, {}, has_cm=False)
    assert ua.alpha0 == pytest.approx(0.0, abs=1e-12) and ua.Cd0 == pytest.approx(0.01)
    assert ua.C_nalpha == pytest.approx(2 * np.pi, rel=0.02)
    assert ua.Cm0 == 0.0 and ua.alphaLower < 0 < ua.alphaUpper
    with pytest.raises(ParameterError, match="at least 3 strictly increasing"):
        ua_coefficients_from_polar(alpha[::-1], cl, cd, None, {}, has_cm=False)
