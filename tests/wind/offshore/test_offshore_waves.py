"""First-order waves (issue 20, item 2): SeaState's sea and HydroDyn's excitation, against closed forms and OpenFAST.

Independent references:
- RANLUX: the first numbers for seed 1 published by OpenFAST's own unit test (``test_NWTC_RandomNumber.F90``);
- the JONSWAP spectrum's zeroth moment ``Hs²/16`` (Pierson–Moskowitz exactly; JONSWAP within the IEC
  normalization's accuracy, a few %);
- a regular wave: ``η = Hs/2 cos(ωt + φ)`` and ``F = Hs/2 |X| cos(ωt + φ + arg X)`` with ``X`` the ``.3`` row;
- OpenFAST v5.0.0 runs of the shared floating deck with JONSWAP and regular waves
  (``tests/data/openfast_waves``, README there): ``Wave1Elev`` and ``B1Wvs*`` within 1e-3 of their range
  (OpenFAST writes 4 significant digits: 5e-4 of the value).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ModelWarning, OpenFASTFormatError, UnsupportedFeatureError
from mbsym.wind.offshore.ranlux import RanLux
from mbsym.wind.offshore.waves import jonswap, wave_number, wave_steps

from .conftest import FLOATING

CASE = FLOATING / "cases" / "fl_decay_a"
DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_waves"
needs_deck = pytest.mark.skipif(not CASE.is_dir(), reason=f"shared floating deck not found at {CASE}")
RHO, G, DEPTH = 1025.0, 9.81, 200.0    # fl_decay_a.fst (gravity 9.81, water 1025 kg/m^3, 200 m)


def test_ranlux_gives_openfasts_numbers():
    rng = RanLux(1)
    assert rng.uniform() == pytest.approx(0.94589489698410034, abs=1e-15)
    assert rng.uniform() == pytest.approx(0.47347849607467651, abs=1e-15)
    x = RanLux(561580799).uniforms(5000)          # past several skips (every 24 numbers at luxury 3)
    assert 0 < x.min() and x.max() < 1 and abs(x.mean() - 0.5) < 0.02


def test_wave_steps_are_seastates_fft_friendly_counts():
    assert wave_steps(850.0, 0.25) == 3400                 # 1700 = 2^2 5^2 17
    assert wave_steps(2018.0, 1.0) == 2024                 # 1009 is prime -> 1012 = 2^2 11 23
    assert wave_steps(3.3, 1.0) == 4


@pytest.mark.parametrize("gamma, tol", [(1.0, 2e-3), (3.3, 0.03)])
def test_jonswap_holds_the_significant_height(gamma, tol):
    omega = np.linspace(0.0, 20.0, 200001)
    m0 = np.trapezoid(jonswap(omega, 4.0, 10.0, gamma), omega)
    assert m0 == pytest.approx(4.0 ** 2 / 16, rel=tol)


def test_wave_number_solves_the_dispersion_relation():
    for omega in (0.1, 0.5, 2.0):
        k = wave_number(omega, G, DEPTH)
        assert G * k * math.tanh(k * DEPTH) == pytest.approx(omega ** 2, rel=1e-12)
    assert wave_number(1.0, G, math.inf) == pytest.approx(1 / G)


def _edited(source: Path, keys: dict) -> str:
    """``source``'s text with the values of ``keys`` (by their key names) replaced."""
    lines = source.read_text().splitlines()
    for k, line in enumerate(lines):
        tokens = line.split()
        if len(tokens) > 1 and tokens[1] in keys:
            lines[k] = f"{keys[tokens[1]]}   {tokens[1]}   -"
    return "\n".join(lines) + "\n"


def _sea(tmp_path, **keys):
    from mbsym.wind.deck.seastate import read_seastate

    path = tmp_path / "sea.dat"
    path.write_text(_edited(CASE / "fl_decay_a_SeaState.dat", keys))
    return read_seastate(path)


def _hydrodyn(tmp_path, **keys):
    """The decay case's HydroDyn file with ``keys`` changed, as ``tmp_path/hd.dat`` (WAMIT files found)."""
    text = _edited(CASE / "fl_decay_a_HydroDyn.dat", keys)
    (tmp_path / "hd.dat").write_text(text.replace('"../../IEA-15-240-RWT-UMaineSemi/',
                                                  f'"{CASE}/../../IEA-15-240-RWT-UMaineSemi/'))
    return tmp_path / "hd.dat"


def _wamit():
    from mbsym.wind.deck.hydrodyn import read_hydrodyn
    from mbsym.wind.deck.wamit import read_wamit

    hd = read_hydrodyn(CASE / "fl_decay_a_HydroDyn.dat")
    return read_wamit(hd.potential_files[0]).redimensionalize(RHO, G, hd.wamit_length[0])


@needs_deck
def test_regular_wave_and_its_force_are_closed_forms(tmp_path):
    from mbsym.wind.offshore.excitation import excitation_transfer, wave_excitation
    from mbsym.wind.offshore.waves import incident_waves

    sea = _sea(tmp_path, WaveMod="1P30", WaveHs=3.0, WaveTp=12.0)
    waves = incident_waves(sea, gravity=G, water_depth=DEPTH)
    kp = round(waves.period / 12.0)
    omega = kp * waves.frequency_step
    t = waves.times()
    assert waves.elevation() == pytest.approx(1.5 * np.cos(omega * t + math.radians(30)), abs=1e-12)
    x = excitation_transfer(_wamit(), np.array([omega]), 0.0)[0]
    forces = wave_excitation(_wamit(), waves).forces
    for m in (0, 2, 4):
        expected = 1.5 * abs(x[m]) * np.cos(omega * t + math.radians(30) + np.angle(x[m]))
        assert forces[:, m] == pytest.approx(expected, abs=1e-9 * abs(x[m]))
    assert np.abs(forces[:, [1, 3, 5]]).max() < 1e-6 * np.abs(forces).max()     # head seas: no sway, roll, yaw


@needs_deck
@pytest.mark.parametrize("case, keys", [
    ("jonswap", {"WaveMod": 2, "WaveHs": 4.0, "WaveTp": 10.0}),
    ("regular", {"WaveMod": 1, "WaveHs": 3.0, "WaveTp": 12.0}),
])
def test_sea_and_excitation_equal_openfasts(tmp_path, case, keys):
    from mbsym.wind.offshore.excitation import wave_excitation
    from mbsym.wind.offshore.waves import incident_waves

    ref = np.loadtxt(DATA / f"{case}_excitation.csv", delimiter=",", skiprows=1)
    waves = incident_waves(_sea(tmp_path, **keys), gravity=G, water_depth=DEPTH)
    got = wave_excitation(_wamit(), waves).at(ref[:, 0])
    for col, m in ((1, 6), (2, 0), (3, 2), (4, 4)):         # Wave1Elev, Fx, Fz, My
        err = np.abs(got[:, m] - ref[:, col]).max() / np.ptp(ref[:, col])
        assert err < 1e-3, (case, col, err)


@needs_deck
def test_oblique_waves_and_an_elevation_point_off_the_grid_equal_openfasts(tmp_path):
    """WaveDir 25° exercises the .3 headings (all six forces and moments non-zero) and an elevation point at
    (50 m, 20 m) SeaState's clamping to its ±5 m surface grid (OpenFAST reports the corner's elevation)."""
    from mbsym.wind.offshore.excitation import wave_excitation
    from mbsym.wind.offshore.waves import incident_waves

    ref = np.loadtxt(DATA / "heading25_excitation.csv", delimiter=",", skiprows=1)
    sea = _sea(tmp_path, WaveMod=2, WaveHs=4.0, WaveTp=10.0, WaveDir=25.0, WaveElevxi=50.0, WaveElevyi=20.0)
    waves = incident_waves(sea, gravity=G, water_depth=DEPTH)
    got = wave_excitation(_wamit(), waves, elevation_point=sea.elevation_points[0], sea=sea).at(ref[:, 0])
    for col, m in ((1, 6), (2, 0), (3, 1), (4, 2), (5, 3), (6, 4), (7, 5)):
        err = np.abs(got[:, m] - ref[:, col]).max() / np.ptp(ref[:, col])
        assert err < 1e-3, (col, err)
    exact = wave_excitation(_wamit(), waves, elevation_point=(50.0, 20.0)).at(ref[:, 0])[:, 6]
    assert np.abs(exact - ref[:, 1]).max() > 0.1 * np.ptp(ref[:, 1])     # the point itself is elsewhere


@needs_deck
def test_a_spread_sea_equals_openfasts(tmp_path):
    """Directional spreading (cos-2s, s = 2, five headings over 90° about 10°): SeaState's equal-energy headings
    and their random assignment to the frequency components, drawn after the phases from the same RANLUX, give
    OpenFAST's excitation to its printed digits (measured ≤ 2.1e-4 of the range)."""
    from mbsym.wind.offshore.excitation import wave_excitation
    from mbsym.wind.offshore.spreading import equal_energy_headings
    from mbsym.wind.offshore.waves import incident_waves

    ref = np.loadtxt(DATA / "spread_excitation.csv", delimiter=",", skiprows=1)
    sea = _sea(tmp_path, WaveMod=2, WaveHs=4.0, WaveTp=10.0, WaveDir=10.0, WaveDirMod=1, WaveDirSpread=2.0,
               WaveNDir=5, WaveDirRange=90)
    waves = incident_waves(sea, gravity=G, water_depth=DEPTH)
    got = wave_excitation(_wamit(), waves, sea=sea).at(ref[:, 0])
    for col, m in ((1, 6), (2, 0), (3, 1), (4, 2), (5, 3), (6, 4), (7, 5)):
        err = np.abs(got[:, m] - ref[:, col]).max() / np.ptp(ref[:, col])
        assert err < 1e-3, (col, err)
    headings = equal_energy_headings(10.0, 2.0, 90.0, 5)
    # symmetric about WaveDir to SeaState's rectangle-rule integration step (90°/1000: the middle one sits at 9.955°)
    assert abs(headings[2] - 10.0) < 0.09 and headings[0] + headings[4] == pytest.approx(2 * headings[2], abs=1e-6)
    counts = np.unique(np.degrees(waves.headings()[:-1]).round(6), return_counts=True)[1]
    assert len(counts) == 5 and np.all(counts == counts[0])            # every heading gets as many components


@needs_deck
def test_state_space_excitation_equals_openfasts(tmp_path):
    """``ExctnMod = 2``: the deck's ``.ssexctn`` (38 states driven by the elevation Tc = 12 s ahead) in the
    platform's graph, integrated by RK4 at 0.025 s from the sea's tables, gives OpenFAST's excitation (measured
    1.8e-4 of the range; the whole floating structure from the CLI gives the same)."""
    import casadi as ca

    from mbsym.wind.offshore import platform_hydrodynamics
    from mbsym.wind.offshore.operating import ELEVATION_AHEAD, FloatingPlatform

    ref = np.loadtxt(DATA / "ssexctn_excitation.csv", delimiter=",", skiprows=1)
    _hydrodyn(tmp_path, ExctnMod=2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        hydro = platform_hydrodynamics(tmp_path / "hd.dat", water_density=RHO, gravity=G, water_depth=DEPTH,
                                       seastate=_sea(tmp_path, WaveMod=2, WaveHs=4.0, WaveTp=10.0).path)
    platform = FloatingPlatform(hydro)
    assert platform.n_excitation == 38 and platform.sea_inputs[-1] == ELEVATION_AHEAD
    tables = platform.sea_tables(30.0)
    names = platform.sea_inputs
    sea = (lambda t: np.array([np.interp(t, *tables[n]) if n in tables else 0.0 for n in names]))
    zero = ca.DM.zeros(6)
    f = (lambda t, x: np.array(platform.loads(zero, zero, x, sea(t))["xr_dot"]).ravel())
    dt, x, rows = 0.025, np.zeros(platform.n_excitation), []
    for k in range(int(round(30.0 / dt)) + 1):
        t = k * dt
        rows.append(np.array(platform.loads(zero, zero, x, sea(t))["sea_out"]).ravel()[:6])
        k1 = f(t, x)
        k2 = f(t + dt / 2, x + dt / 2 * k1)
        k3 = f(t + dt / 2, x + dt / 2 * k2)
        x = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + f(t + dt, x + dt * k3))
    got = np.array(rows)[::4]                                  # OpenFAST's 0.1 s samples
    for col, m in ((1, 0), (2, 2), (3, 4)):
        assert np.abs(got[:, m] - ref[:, col]).max() < 1e-3 * np.ptp(ref[:, col]), col


@needs_deck
def test_an_external_elevation_series_gives_the_same_sea(tmp_path):
    from mbsym.wind.offshore.excitation import wave_excitation
    from mbsym.wind.offshore.waves import incident_waves

    waves = incident_waves(_sea(tmp_path, WaveMod=2, WaveHs=4.0, WaveTp=10.0), gravity=G, water_depth=DEPTH)
    t, eta = waves.times(), waves.elevation()
    np.savetxt(tmp_path / "series.Elev", np.column_stack([t, eta]), header="time elevation", comments="")
    external = incident_waves(_sea(tmp_path, WaveMod=5, WvKinFile='"series"'), gravity=G, water_depth=DEPTH)
    assert external.elevation() == pytest.approx(eta, abs=1e-9)
    a, b = wave_excitation(_wamit(), waves).forces, wave_excitation(_wamit(), external).forces
    assert b == pytest.approx(a, abs=1e-9 * np.abs(a).max())
    np.savetxt(tmp_path / "short.Elev", np.column_stack([t[:100], eta[:100]]))
    with pytest.raises(OpenFASTFormatError, match="spans"):
        incident_waves(_sea(tmp_path, WaveMod=5, WvKinFile='"short"'), gravity=G, water_depth=DEPTH)


@needs_deck
def test_unmodelled_wave_settings_are_refused_or_named(tmp_path):
    from mbsym.wind.offshore import platform_hydrodynamics
    from mbsym.wind.offshore.waves import incident_waves

    with pytest.raises(UnsupportedFeatureError, match="WaveMod = 4"):
        incident_waves(_sea(tmp_path, WaveMod=4), gravity=G, water_depth=DEPTH)
    with pytest.warns(ModelWarning, match="compiler's random generator"):
        incident_waves(_sea(tmp_path, WaveMod=2, **{"WaveSeed(2)": 7}), gravity=G, water_depth=DEPTH)
    _hydrodyn(tmp_path, ExctnDisp=1)
    _sea(tmp_path, WaveMod=2)
    with pytest.raises(UnsupportedFeatureError, match="ExctnDisp = 1"), warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        platform_hydrodynamics(tmp_path / "hd.dat", water_density=RHO, gravity=G, seastate=tmp_path / "sea.dat")
    _hydrodyn(tmp_path, ExctnMod=2)
    _sea(tmp_path, WaveMod=2, WaveDir=25.0)
    with pytest.raises(UnsupportedFeatureError, match="fitted for waves from 0 deg"), warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        platform_hydrodynamics(tmp_path / "hd.dat", water_density=RHO, gravity=G, seastate=tmp_path / "sea.dat")
    _sea(tmp_path, WaveMod=2)
    with pytest.warns(ModelWarning, match="second-order elevation"), warnings.catch_warnings():
        warnings.filterwarnings("ignore", "RdtnMod", ModelWarning)
        ph = platform_hydrodynamics(CASE / "fl_decay_a_HydroDyn.dat", water_density=RHO, gravity=G,
                                    seastate=tmp_path / "sea.dat", water_depth=DEPTH)
    assert ph.waves is not None and ph.waves.waves.significant_height() == pytest.approx(1.1, rel=0.15)


#: Measured (600 s, series after 100 s, mbsym's rotor-effective rung with the ROSCO library, the disk's damping
#: across the shaft on as the floating default): R² surge 0.973, heave 1.000, pitch 0.976, TTDspFA 0.994,
#: RotSpeed 0.993, BldPitch1 0.985 (without the disk terms 0.972, 1.000, 0.971, 0.989, 0.988, 0.979); means: surge +0.1 %,
#: heave −0.4 %, pitch −0.9 %, TTDspFA −2.3 % (the rotor-effective rung's thrust, as in still water), FAIRTEN1
#: +0.07 %. Bounds: those figures with a margin for the library's and the machine's rounding.
#: Since 2026-11-30 (night) the CLI moves MoorDyn's lines (docs/offshore.md §3c): R² of FAIRTEN1 0.993 (its std 0.99×
#: OpenFAST's; with the quasi-static lines −0.54, the std 0.62×: the wave-frequency tension is the lines' own
#: dynamics), surge 0.986 (0.965), heave 1.000, pitch 0.996, TTDspFA 1.000, RotSpeed 0.994, BldPitch1 0.982.
R2_BOUNDS = {"Wave1Elev": 0.9999, "PtfmSurge": 0.95, "PtfmHeave": 0.995, "PtfmPitch": 0.95, "TTDspFA": 0.97,
             "RotSpeed": 0.97, "BldPitch1": 0.96, "FAIRTEN1": 0.98}
MEAN_BOUNDS = {"PtfmSurge": 0.01, "PtfmHeave": 0.02, "PtfmPitch": 0.02, "TTDspFA": 0.035, "RotSpeed": 0.005,
               "FAIRTEN1": 0.01}


@pytest.mark.slow
def test_floating_turbine_in_irregular_waves_tracks_openfast(tmp_path):
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    from .conftest import rosco_library
    from .test_offshore_blade import _deck

    lib = rosco_library()
    if lib is None:
        pytest.skip("the rosco 2.10.6 wheel is not available (no registry access)")
    fst = _deck(tmp_path)
    sea = fst.parent / "fl_steady_13_SeaState.dat"
    lines = sea.read_text().splitlines()
    values = {"WaveMod": "2", "WaveHs": "4.0", "WaveTp": "10.0", "WvDiffQTF": "False", "WvSumQTF": "False"}
    lines = [f"{values[l.split()[1]]}   {l.split()[1]}   -" if len(l.split()) > 1 and l.split()[1] in values else l
             for l in lines]
    sea.write_text("\n".join(lines) + "\n")
    out = tmp_path / "waves.csv"
    assert main(["simulate", str(fst), "--aero", "rotor", "--discon", str(lib), "--tmax", "600", "--out", str(out)]) == 0
    ours = read_csv(out)
    ref = np.loadtxt(DATA / "fl_steady_13_jonswap.csv", delimiter=",", skiprows=1)
    names = (DATA / "fl_steady_13_jonswap.csv").read_text().split("\n", 1)[0].split(",")
    series = {n: (ref[:, names.index(n)], np.interp(ref[:, 0], np.asarray(ours.time), np.asarray(ours.channel(n))))
              for n in {*R2_BOUNDS, *MEAN_BOUNDS}}
    for name, bound in R2_BOUNDS.items():
        want, got = series[name]
        r2 = 1 - np.sum((got - want) ** 2) / np.sum((want - want.mean()) ** 2)
        assert r2 > bound, (name, r2)
    for name, bound in MEAN_BOUNDS.items():
        want, got = series[name]
        assert abs(got.mean() / want.mean() - 1) < bound, (name, got.mean(), want.mean())


@needs_deck
def test_cli_runs_the_floating_decay_deck_as_written(tmp_path, capsys):
    """``mbsym simulate fl_decay_a.fst`` (HydroDyn, SeaState, MoorDyn; no AeroDyn) as written, first 30 s against
    OpenFAST's shared run. Measured when written over 60 s: ε surge 0.22 %, heave 0.26 %, pitch 0.21 % (TTDspFA
    3.2 %: the tower's 0.5 Hz ringing in the first seconds). Bound: the issue's 2 % on the platform."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    out = tmp_path / "decay.csv"
    assert main(["simulate", str(CASE / "fl_decay_a.fst"), "--tmax", "30", "--out", str(out)]) == 0
    ours = read_csv(out)
    ref = read_csv(FLOATING / "fl_decay_a.csv")
    t = np.asarray(ours.time)
    keep = np.asarray(ref.time) <= 30.0 + 1e-9
    for name in ("PtfmSurge", "PtfmHeave", "PtfmPitch"):
        want = np.asarray(ref.channel(name))[keep]
        got = np.interp(np.asarray(ref.time)[keep], t, np.asarray(ours.channel(name)))
        assert np.sqrt(np.mean((got - want) ** 2)) / np.ptp(want) < 0.02, name
    assert "B1WvsFxi" in ours.names and np.all(np.asarray(ours.channel("Wave1Elev")) == 0.0)   # still water
