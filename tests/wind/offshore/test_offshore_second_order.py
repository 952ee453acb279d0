"""Second-order difference-frequency wave forces from a full QTF (HydroDyn's ``DiffQTF``).

References:
- closed form: two wave components ``a_1``, ``a_2`` give ``F(t) = Re Q(ω1, ω1)|a_1|² + Re Q(ω2, ω2)|a_2|²
  + 2 Re(a_2 conj(a_1) Q(ω2, ω1) e^{i(ω2 − ω1)t})`` (the difference-frequency QTF's definition in amplitude
  products), to 1e-9 relative; a bilinear Q is read exactly between grid points;
- OpenFAST v5.0.0 on the `rosco` 2.10.6 wheel's IEA 15 MW VolturnUS-S deck as shipped (DiffQTF 12, JONSWAP Hs
  1.1 m, Tp 8.52 s; tests/data/openfast_qtf/README.md): HydroDyn's ``B1WvsF2xi`` … ``B1WvsM2zi`` and the total
  ``B1WvsFxi``, ``B1WvsFzi``, ``B1WvsMyi`` on 0-60 s; measured when written: the second-order series within 3e-6
  of their standard deviations (HydroDyn computes in single precision), the totals within 1e-6;
- reader: a file giving one triangle is completed with the conjugate; a grid entry given by no row is an error
  naming it, like HydroDyn's "too sparse".
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError, UnsupportedFeatureError
from mbsym.wind.deck.wamit_qtf import QtfData, read_wamit_qtf
from mbsym.wind.offshore.second_order import difference_frequency_forces, qtf_at, sum_frequency_forces
from mbsym.wind.offshore.waves import IncidentWaves

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_qtf"


def _bilinear_qtf() -> QtfData:
    """Q(ω1, ω2) = (1 + 2 ω1 − ω2) + i (ω1 − ω2) on a 0.2 … 2 rad/s grid (bilinear: read exactly)."""
    f = np.linspace(0.2, 2.0, 10)
    w1, w2 = np.meshgrid(f, f, indexing="ij")
    q = (1 + 2 * w1 - w2) + 1j * (w1 - w2)
    values = np.repeat(q[:, :, None, None, None], 6, axis=4) * np.arange(1, 7)
    return QtfData(f, np.array([0.0]), values, "difference", "bilinear")


def _two_waves():
    """A sea of two components (64 samples of 0.5 s) and their amplitudes a_k = C_k / (N/2) and frequencies."""
    n, dt = 64, 0.5
    dw = 2 * math.pi / (n * dt)
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    spectrum[5], spectrum[9] = 3.0 + 1.0j, -2.0 + 4.0j
    waves = IncidentWaves(dt, spectrum, dw, 0.0, 200.0, 9.81)
    return waves, (spectrum[5] / (n // 2), 5 * dw), (spectrum[9] / (n // 2), 9 * dw)


def test_two_components_closed_form():
    waves, (a1, w1), (a2, w2) = _two_waves()
    qtf = _bilinear_qtf()
    force = difference_frequency_forces(qtf, waves, band=(0.0, 10.0), difference_band=(0.0, 10.0))
    q = lambda x, y: (1 + 2 * x - y) + 1j * (x - y) # noqa: E731
    t = waves.times()
    expected = (q(w1, w1).real * abs(a1) ** 2 + q(w2, w2).real * abs(a2) ** 2
                + 2 * np.real(a2 * np.conj(a1) * q(w2, w1) * np.exp(1j * (w2 - w1) * t)))
    for m in range(6):
        np.testing.assert_allclose(force[:, m], (m + 1) * expected, rtol=1e-9, atol=1e-12)
    # outside the difference band only the mean drift is left
    mean = difference_frequency_forces(qtf, waves, band=(0.0, 10.0), difference_band=(0.0, 0.5 * (w2 - w1)))
    np.testing.assert_allclose(mean[:, 0], q(w1, w1).real * abs(a1) ** 2 + q(w2, w2).real * abs(a2) ** 2)
    # zero outside the file's frequencies
    assert np.all(qtf_at(qtf, np.array([0.1, 2.1]), np.array([1.0, 1.0]), 0.0) == 0)


def test_sum_frequency_two_components_closed_form():
    """HydroDyn's sum-frequency definition: F = Re a₁²Q(ω₁, ω₁)e^{2iω₁t} + Re a₂²Q(ω₂, ω₂)e^{2iω₂t}
    + 2 Re a₁a₂Q(ω₁, ω₂)e^{i(ω₁+ω₂)t}, to 1e-9 (Q bilinear, so read exactly)."""
    waves, (a1, w1), (a2, w2) = _two_waves()
    qtf = dataclasses.replace(_bilinear_qtf(), kind="sum")
    force = sum_frequency_forces(qtf, waves, sum_band=(0.0, 100.0))
    q = lambda x, y: (1 + 2 * x - y) + 1j * (x - y) # noqa: E731
    t = waves.times()
    expected = (np.real(a1**2 * q(w1, w1) * np.exp(2j * w1 * t)) + np.real(a2**2 * q(w2, w2) * np.exp(2j * w2 * t))
                + 2 * np.real(a1 * a2 * q(w1, w2) * np.exp(1j * (w1 + w2) * t)))
    np.testing.assert_allclose(force[:, 2], 3 * expected, rtol=1e-9, atol=1e-12)
    with pytest.raises(UnsupportedFeatureError, match="sum-frequency file"):
        sum_frequency_forces(_bilinear_qtf(), waves, sum_band=(0.0, 100.0))


def test_spread_seas_and_other_headings_are_refused():
    waves = IncidentWaves(0.5, np.ones(33, dtype=complex), 0.2, 0.0, 200.0, 9.81, directions=np.zeros(33))
    with pytest.raises(UnsupportedFeatureError, match="unidirectional"):
        difference_frequency_forces(_bilinear_qtf(), waves, band=(0, 9), difference_band=(0, 9))
    waves = IncidentWaves(0.5, np.ones(33, dtype=complex), 0.2, math.radians(30.0), 200.0, 9.81)
    with pytest.raises(UnsupportedFeatureError, match="heading 0 deg only"):
        difference_frequency_forces(_bilinear_qtf(), waves, band=(0, 9), difference_band=(0, 9))


def _write(path: Path, rows) -> Path:
    path.write_text("\n".join(" ".join(f"{v:.6E}" if isinstance(v, float) else str(v) for v in r) for r in rows))
    return path


def test_reader_fills_the_conjugate_triangle_and_names_missing_entries(tmp_path):
    periods = (10.0, 5.0)
    rows = []
    for i, p1 in enumerate(periods):
        for p2 in periods[i:]:
            for comp in range(1, 7):
                re, im = comp * p1, comp * (p1 - p2)
                rows.append((p1, p2, 0.0, 0.0, comp, abs(complex(re, im)), 0.0, re, im))
    q = read_wamit_qtf(_write(tmp_path / "x.12d", rows))
    assert q.kind == "difference" and np.allclose(q.frequencies, [2 * math.pi / 10, 2 * math.pi / 5])
    # (ω for 10 s, ω for 5 s) given, the mirror is its conjugate
    assert q.values[0, 1, 0, 0, 2] == pytest.approx(complex(30.0, 15.0))
    assert q.values[1, 0, 0, 0, 2] == pytest.approx(complex(30.0, -15.0))
    with pytest.raises(OpenFASTFormatError, match="too sparse"):
        read_wamit_qtf(_write(tmp_path / "y.12d", [r for r in rows if not (r[0] == 5.0 and r[4] == 4)]))
    with pytest.raises(OpenFASTFormatError, match="line 2: expected 9 numbers"):
        read_wamit_qtf(_write(tmp_path / "z.12d", [rows[0], rows[1][:8]]))


@pytest.fixture(scope="module")
def stock_semi():
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "control"))
    import _rosco

    fst = _rosco.rosco_test_case("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi/IEA-15-240-RWT-UMaineSemi.fst")
    if fst is None:
        pytest.skip("the ROSCO 2.10.6 wheel is not cached and could not be fetched with pip")
    return fst


def test_stock_deck_forces_match_hydrodyn(stock_semi):
    from mbsym.wind.analysis.compare import read_csv
    from mbsym.wind.offshore.platform import platform_hydrodynamics

    d = stock_semi.parent
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ph = platform_hydrodynamics(d / "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat", water_density=1025.0, gravity=9.81,
                                    seastate=d / "IEA-15-240-RWT-UMaineSemi_SeaState.dat", water_depth=200.0)
    ref = read_csv(DATA / "umainesemi_stock_wvs.csv")
    t = np.asarray(ref.time)
    total = ph.waves.at(t)
    qtf = read_wamit_qtf(d / "HydroData" / "IEA-15-240-RWT-UMaineSemi.12d").redimensionalize(1025.0, 9.81, 1.0)
    sea = ph.waves.waves
    second = difference_frequency_forces(qtf, sea, band=(0.111527, 3.2), difference_band=(0.0, 0.737863))
    second = second[np.rint(t / sea.time_step).astype(int) % sea.n_steps]
    names = ("B1WvsF2xi", "B1WvsF2yi", "B1WvsF2zi", "B1WvsM2xi", "B1WvsM2yi", "B1WvsM2zi")
    for k, name in enumerate(names):
        theirs = np.asarray(ref.channel(name))
        assert np.max(np.abs(second[:, k] - theirs)) <= 1e-5 * np.std(theirs) + 1e-6, name
    for k, name in ((0, "B1WvsFxi"), (2, "B1WvsFzi"), (4, "B1WvsMyi")):
        theirs = np.asarray(ref.channel(name))
        assert np.max(np.abs(total[:, k] - theirs)) <= 1e-5 * np.std(theirs), name
    assert np.std(ref.channel("B1WvsF2xi")) > 0.01 * np.std(ref.channel("B1WvsFxi"))    # the term is there


def _second_order(stock_semi, tmp_path: Path, switches: dict):
    """The second-order loads ``(N + 1, 6)`` of the wheel's deck with the HydroDyn ``switches`` set (the rest as
    shipped: DiffQTF 12), the first-order loads taken off, and its sea."""
    import re

    from mbsym.wind.offshore.platform import platform_hydrodynamics

    d = stock_semi.parent
    tmp_path.mkdir(parents=True, exist_ok=True)
    if not (tmp_path / "HydroData").exists():
        (tmp_path / "HydroData").symlink_to(d / "HydroData")
    text = (d / "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat").read_text()
    for key, value in switches.items():
        text = re.sub(rf"^\s*\S+(\s+{key}\b)", rf"{value}\1", text, count=1, flags=re.M)
    hd = tmp_path / "hd.dat"
    hd.write_text(text)
    args = dict(water_density=1025.0, gravity=9.81, water_depth=200.0,
                seastate=d / "IEA-15-240-RWT-UMaineSemi_SeaState.dat")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        total = platform_hydrodynamics(hd, **args).waves
        first = platform_hydrodynamics(_first_order(tmp_path, text), **args).waves
    return total.forces - first.forces, total.waves


NAMES2 = ("B1WvsF2xi", "B1WvsF2yi", "B1WvsF2zi", "B1WvsM2xi", "B1WvsM2yi", "B1WvsM2zi")


def _against_series(second, sea, csv_name: str) -> None:
    """``second`` at the samples of HydroDyn's series in ``csv_name``: within 1e-5 of each one's std."""
    from mbsym.wind.analysis.compare import read_csv

    ref = read_csv(DATA / csv_name)
    i = np.rint(np.asarray(ref.time) / sea.time_step).astype(int) % sea.n_steps
    for k, name in enumerate(NAMES2):
        theirs = np.asarray(ref.channel(name))
        assert np.max(np.abs(second[i, k] - theirs)) <= 1e-5 * np.std(theirs) + 1e-6, name


def test_sum_frequency_forces_match_hydrodyn(stock_semi, tmp_path):
    """The wheel's deck with SumQTF 12 too: HydroDyn's B1WvsF2xi … (difference + sum frequency) at its WaveDT samples
    (tests/data/openfast_qtf/README.md) within 1e-5 of their std (measured when written: 4e-5 of the std at the
    samples between them, 1e-6 at them); the sum part alone is a sizeable share of it."""
    second, sea = _second_order(stock_semi, tmp_path, {"SumQTF": 12})
    _against_series(second, sea, "umainesemi_sumqtf_wvs2.csv")
    diff, _ = _second_order(stock_semi, tmp_path / "diff", {})
    assert np.std(second[:, 0] - diff[:, 0]) > 0.3 * np.std(second[:, 0])           # the sum term is there


def test_mean_drift_alone_matches_hydrodyn(stock_semi, tmp_path):
    """MnDrift 12 (the .12d file's diagonal, without the slow drift) against HydroDyn's constant B1WvsF2xi …
    (tests/data/openfast_qtf/umainesemi_mndrift12.json): within 1e-4 relative (single precision in HydroDyn;
    measured 1e-5 to 4e-5). MnDrift together with DiffQTF is refused, as HydroDyn refuses it."""
    import json

    with pytest.raises(UnsupportedFeatureError,
                       match=r"'MnDrift': 12, 'DiffQTF': 12.*allows one of MnDrift, NewmanApp and DiffQTF"):
        _second_order(stock_semi, tmp_path / "both", {"MnDrift": 12})
    drift, _ = _second_order(stock_semi, tmp_path, {"DiffQTF": 0, "MnDrift": 12})
    ref = json.loads((DATA / "umainesemi_mndrift12.json").read_text())["means"]
    assert np.ptp(drift, axis=0).max() < 1e-6 * np.abs(drift[0]).max()                # a constant
    for k, name in enumerate(NAMES2):
        assert drift[0, k] == pytest.approx(ref[name], rel=1e-4), name


def test_newman_approximation_matches_hydrodyn(stock_semi, tmp_path):
    """NewmanApp 12 against HydroDyn's B1WvsF2xi … at its WaveDT samples (tests/data/openfast_qtf/README.md): within
    1e-5 of their std (HydroDyn reads the file's diagonal alone here; read bilinearly off the diagonal, as its full
    QTF is, the surge force was 8 % of its std off)."""
    second, sea = _second_order(stock_semi, tmp_path, {"DiffQTF": 0, "NewmanApp": 12})
    _against_series(second, sea, "umainesemi_newman_wvs2.csv")


def test_mean_drift_from_a_3d_file_matches_hydrodyn(stock_semi, tmp_path):
    """MnDrift 8: a WAMIT .8 file (3-D: PER BETA1 BETA2 I MOD PHS RE IM), here written from the .12d diagonal,
    read linearly along the frequency; HydroDyn uses its surge, sway and yaw only
    (tests/data/openfast_qtf/umainesemi_mndrift8.json): within 1e-4 relative, zero elsewhere."""
    import json

    data = tmp_path / "HydroData"
    data.mkdir()
    for f in (stock_semi.parent / "HydroData").iterdir():
        (data / f.name).symlink_to(f)
    rows = [r.split() for r in (data / "IEA-15-240-RWT-UMaineSemi.12d").read_text().splitlines() if r.strip()]
    (data / "IEA-15-240-RWT-UMaineSemi.8").write_text(
        "\n".join("  ".join([r[0], *r[2:]]) for r in rows if float(r[0]) == float(r[1])) + "\n")
    drift, _ = _second_order(stock_semi, tmp_path, {"DiffQTF": 0, "MnDrift": 8})
    ref = json.loads((DATA / "umainesemi_mndrift8.json").read_text())["means"]
    for k, name in enumerate(NAMES2):
        assert drift[0, k] == pytest.approx(ref[name], rel=1e-4, abs=1e-9), name


def _first_order(tmp_path: Path, text: str) -> Path:
    """The deck's HydroDyn with every second-order switch off."""
    import re

    for key in ("MnDrift", "NewmanApp", "DiffQTF", "SumQTF"):
        text = re.sub(rf"^\s*\S+(\s+{key}\b)", r"0\1", text, count=1, flags=re.M)
    path = tmp_path / "first.dat"
    path.write_text(text)
    return path


def test_other_second_order_options_are_refused(stock_semi, tmp_path):
    import re

    from mbsym.wind.offshore.platform import platform_hydrodynamics

    d = stock_semi.parent
    (tmp_path / "HydroData").symlink_to(d / "HydroData")
    sea = tmp_path / "sea.dat"
    sea.write_text((d / "IEA-15-240-RWT-UMaineSemi_SeaState.dat").read_text())
    text = (d / "IEA-15-240-RWT-UMaineSemi_HydroDyn.dat").read_text()
    for key, value in (("MnDrift", 12), ("NewmanApp", 12)):         # with the deck's DiffQTF 12
        hd = tmp_path / f"hd_{key}.dat"
        hd.write_text(re.sub(rf"^\s*\S+(\s+{key}\b)", rf"{value}\1", text, count=1, flags=re.M))
        with pytest.raises(UnsupportedFeatureError, match=f"{key}.*allows one of MnDrift, NewmanApp and DiffQTF"), \
                warnings.catch_warnings():
            warnings.simplefilter("ignore")
            platform_hydrodynamics(hd, water_density=1025.0, gravity=9.81, seastate=sea, water_depth=200.0)


#: Measured when written (mbsym simulate on the deck as shipped, 60 s, its blade-element default with the ROSCO
#: library; 10-60 s against OpenFAST): means surge -0.59 %, heave -0.48 %, pitch -0.95 %, roll -0.01 %, RotSpeed
#: -0.42 %, BldPitch1 -0.11 %, GenPwr -0.42 %, TwrBsMyt -0.92 %; ε 0.35-2.2 %. Bounds: 2 % on means, 4 % on ε.
STOCK_MEAN, STOCK_EPS = 0.02, 0.04


@pytest.mark.slow
def test_stock_floating_deck_runs_as_shipped(stock_semi, tmp_path, monkeypatch):
    """The wheel's VolturnUS-S deck as shipped (second-order forces, waves, MoorDyn, UA, flexible blades) runs
    from the CLI and tracks OpenFAST v5.0.0 (tests/data/openfast_qtf/README.md)."""
    import io
    import json
    import sys
    from contextlib import redirect_stdout

    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "control"))
    import _rosco

    lib = _rosco.rosco_library()
    monkeypatch.chdir(tmp_path)                       # the library's own log files land here
    out = tmp_path / "run.csv"
    with redirect_stdout(io.StringIO()), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["simulate", str(stock_semi), "--discon", str(lib), "--tmax", "60", "--out", str(out)]) == 0
    ours = read_csv(out)
    ref = json.loads((DATA / "umainesemi_stock_60s.json").read_text())
    t = np.asarray(ref["time"])
    for name, series in ref["series"].items():
        y = np.asarray(series)
        mine = np.interp(t, np.asarray(ours.time), np.asarray(ours.channel(name)))
        assert mine.mean() == pytest.approx(y.mean(), rel=STOCK_MEAN), name
        assert np.mean(np.abs(mine - y)) / np.ptp(y) < STOCK_EPS, name
