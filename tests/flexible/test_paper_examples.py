"""The paper's Sect. 4.4 example against the printed numbers and OpenFAST.

References
----------
- Branlard & Geisler (2022), Sect. 4.4 (printed to 2-3 digits), shared/guide/REFERENCE_NUMBERS.md:
  ν_y = 0.0185, Me = 5.4e4, Ke = 1.91e6, Kg = -6.20e4, Mq = 4.375e5, Kq = 1.849e6 (the printed
  1.849e9 is a typo), f = 0.3272 Hz. Tolerance: 0.3 % on f (issue 3), otherwise half a unit of
  the last printed digit plus 0.2 % for the quadrature.
- OpenFAST v5 linearization of the same turbine, undeflected operating point
  (shared/openfast/cases/paper44_fa_gen/paper44_fa_gen_lin.json): 0.32705 Hz, tolerance 0.5 %.
"""

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / "examples" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def paper44():
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "paper_4_4_two_dof.py")],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_paper44_frequency(paper44):
    assert paper44["f_hz"] == pytest.approx(0.3272, rel=3e-3)


@pytest.mark.parametrize("key, printed, digits_rel", [
    ("nu_y", 0.0185, 0.003), ("Me", 5.4e4, 0.01), ("Ke", 1.91e6, 0.003),
    ("Kg", -6.20e4, 0.01), ("Mq", 4.375e5, 0.002), ("Kq", 1.849e6, 0.001),
])
def test_paper44_printed_numbers(paper44, key, printed, digits_rel):
    assert paper44[key] == pytest.approx(printed, rel=digits_rel + 2e-3)


def test_paper44_closed_form_eq46(paper44):
    """Kq = Ke + Kg - ν_y² g (M_N z_NG + M_R z_NR) (paper Eq. 46 at f_a = 0), to 1e-3.

    Eq. 46 keeps the second-order small-angle terms the example uses (end_rotation_order=2).
    """
    m = _load("paper_4_4_two_dof")
    expected = paper44["Ke"] + paper44["Kg"] - paper44["nu_y"] ** 2 * m.G * (m.M_N * m.Z_NG + m.M_R * m.Z_NR)
    assert paper44["Kq"] == pytest.approx(expected, rel=1e-3)


def test_paper44_against_openfast_linearization(paper44):
    path = SHARED / "openfast/cases/paper44_fa_gen/paper44_fa_gen_lin.json"
    if not path.exists():
        pytest.skip("shared OpenFAST reference data not available")
    modes = json.loads(path.read_text())["undeflected"]["structural_modes"]
    assert paper44["f_hz"] == pytest.approx(modes[0]["freq_natural_Hz"], rel=5e-3)


# ---------------------------------------------------------------- Sect. 4.3
@pytest.fixture(scope="module")
def paper43():
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "paper_4_3_rotating_blade.py")],
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def _openfast_blade_hz():
    """OpenFAST v5 blade_campbell frequencies (flap1, edge1, flap2) per rpm, from the shared CSV."""
    path = SHARED / "openfast/cases/blade_campbell/blade_campbell.csv"
    if not path.exists():
        pytest.skip("shared OpenFAST reference data not available")
    import numpy as np
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {int(r["RotSpeed_rpm"]): (r["flap1_freq_Hz"], r["edge1_freq_Hz"], r["flap2_freq_Hz"]) for r in data}


def test_paper43_keys_and_shapes(paper43):
    assert set(paper43) >= {"Me", "Ke", "k_omega", "freq_hz"}
    assert all(len(paper43[k]) == 3 for k in ("Me", "Ke", "k_omega"))
    assert set(paper43["freq_hz"]) == {"0", "6", "12"} and all(len(v) == 3 for v in paper43["freq_hz"].values())


def test_paper43_against_printed_numbers(paper43):
    """Paper Sect. 4.3 (2 digits printed): Ke within 5 %, kΩ within ±0.2 (issue 3 acceptance)."""
    for got, printed in zip(paper43["Ke"], [1.7e4, 6.7e4, 8.7e4]):
        assert got == pytest.approx(printed, rel=0.05)
    for got, printed in zip(paper43["k_omega"], [1.7, 1.4, 5.5]):
        assert abs(got - printed) <= 0.2


def test_paper43_printed_mass_is_ten_times_too_large(paper43):
    """The printed Me = [9.5e3, 1.5e4, 5.7e3] are ~10x ours (a misprint, see the report)."""
    for got, printed in zip(paper43["Me"], [9.5e3, 1.5e4, 5.7e3]):
        assert printed / got == pytest.approx(10.0, rel=0.05)


def test_paper43_single_shape_frequencies_vs_openfast(paper43):
    """sqrt(Ke/Me)/2π within 1 % of OpenFAST's 0-rpm blade frequencies (issue 3 acceptance)."""
    import math
    ref = _openfast_blade_hz()[0]
    for k, m, f_ref in zip(paper43["Ke"], paper43["Me"], ref):
        assert math.sqrt(k / m) / (2 * math.pi) == pytest.approx(f_ref, rel=0.01)


def test_paper43_southwell_law(paper43):
    """The frequencies at 6 and 12 rpm follow ω² = ω0² + (kΩ - [edge]) Ω² exactly (same model)."""
    import math
    for rpm in ("6", "12"):
        om = int(rpm) * math.pi / 30
        for i, soft in enumerate((0.0, 1.0, 0.0)):
            w0 = 2 * math.pi * paper43["freq_hz"]["0"][i]
            w = math.sqrt(w0**2 + (paper43["k_omega"][i] - soft) * om**2)
            assert 2 * math.pi * paper43["freq_hz"][rpm][i] == pytest.approx(w, rel=1e-9)


def test_paper43_coupled_blade_vs_openfast(paper43):
    """ElastoDyn-equivalent coupled blade vs OpenFAST at 0..15 rpm: within 1e-4 (issue 3 asks 1 %)."""
    ref = _openfast_blade_hz()
    for rpm, freqs in paper43["coupled_freq_hz"].items():
        for got, f_ref in zip(freqs, sorted(ref[int(rpm)])):
            assert got == pytest.approx(f_ref, rel=1e-4)
