"""SeaState's sea from wave components (``WaveMod = 7``, mbsym.wind.offshore.wave_components).

References, each independent of the code under test:
- the sum the file describes, ``η(t) = Σ A cos(ω t + φ)`` at the origin (A = H/2 in OpenFAST's layout);
- the layouts and checks of SeaState's ``WaveComp_ReadFile`` (``UserWaves.f90``): units, the ``.SEA`` header,
  frequencies on the 2π/WaveTMax grid, each once;
- OpenFAST v5.0.0's ``Wave1Elev``, ``Wave2Elev`` and HydroDyn's excitation ``B1Wvs*`` for the same components
  (tests/data/openfast_wave_components/README.md): measured 3.5e-7 and 4.6e-7 m (std 0.47, 0.52 m), the excitation
  within 1.2e-6 of its standard deviation; bounds 2e-6 m and 1e-5 (SeaState's single precision).
"""

from __future__ import annotations

import csv
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError, UnsupportedFeatureError
from mbsym.wind.deck.seastate import read_seastate
from mbsym.wind.offshore.excitation import catmull_rom
from mbsym.wind.offshore.wave_components import component_spectrum, read_wave_components
from mbsym.wind.offshore.waves import grid_elevation, incident_waves

from .test_offshore_morison import CASE, needs_deck

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_wave_components"
G, DEPTH = 9.81, 200.0                                 # the deck's .fst Gravity and WtrDpth


def _reference() -> dict[str, np.ndarray]:
    with (DATA / "wc7.csv").open() as fh:
        rows = list(csv.reader(fh))
    data = np.array(rows[1:], dtype=float)
    return {h.split("_[")[0]: data[:, k] for k, h in enumerate(rows[0])}


def _sea():
    sea = read_seastate(DATA / "wc7_SeaState.dat")
    return sea, incident_waves(sea, gravity=G, water_depth=DEPTH)


def test_the_sea_is_the_sum_of_its_components():
    sea, waves = _sea()
    comp = read_wave_components(DATA / "components.txt")
    t = waves.times()[:2000]
    grid = np.rint(comp.frequency / waves.frequency_step) * 2 * math.pi / waves.period    # the DFT's own grid
    expected = sum(a * np.cos(w * t + p) for w, a, p in zip(grid, comp.amplitude, comp.phase))
    assert np.abs(waves.elevation()[:2000] - expected).max() < 1e-9 * np.abs(expected).max() + 1e-12
    assert waves.time_step == pytest.approx(850.0 / 6804)                   # SeaState's "WaveDT 0.12493 s"
    assert np.allclose(np.degrees(waves.headings()[np.abs(waves.spectrum) > 0]), np.degrees(comp.heading))


def test_sea_layout_and_the_checks(tmp_path):
    path = tmp_path / "c.sea"
    path.write_text("source: SEAFileGenerator.exe\nduration: 400\nfreq amp dir phase\n"
                    f"{2 / 400:.12f} 0.5 0.3 1.0\n{10 / 400:.12f} 0.25 -0.2 -2.0\n")
    comp = read_wave_components(path)
    assert comp.duration == 400.0
    assert np.allclose(comp.frequency, 2 * math.pi * np.array([2, 10]) / 400)
    assert np.allclose(comp.amplitude, [0.5, 0.25]) and np.allclose(comp.heading, [0.3, -0.2])
    spectrum, headings, dw, dt = component_spectrum(comp, time_max=850.0, time_step=0.5, band=(0.0, 10.0))
    assert dw == pytest.approx(2 * math.pi / 400, rel=1e-7)                  # the duration replaces WaveTMax
    assert np.count_nonzero(spectrum) == 2 and headings[10] == pytest.approx(-0.2)
    path.write_text("source: SEAFileGenerator.exe\ndconv: naut\n0.005 0.5 0.3 1.0\n")
    with pytest.raises(UnsupportedFeatureError, match="naut"):
        read_wave_components(path)
    cases = {"0.5 1.0 0 0\nend\n": "text inside the data", "0.5 1.0 0\n": "3 columns",
             "0.5 1.0 0 0 0\n": "5 columns"}
    for text, match in cases.items():
        path.write_text("w H dir phase\n" + text)
        with pytest.raises(OpenFASTFormatError, match=match):
            read_wave_components(path)
    dw = 2 * math.pi / 850.0
    for rows, match in ((f"{10.4 * dw} 1 0 0\n", "whole multiple"), (f"{10 * dw} 1 0 0\n{10 * dw} 2 0 0\n", "share"),
                        (f"{-3 * dw} 1 0 0\n", "positive")):
        path.write_text("w H dir phase\n" + rows)
        with pytest.raises(OpenFASTFormatError, match=match):
            component_spectrum(read_wave_components(path), time_max=850.0, time_step=0.25, band=(0.0, 10.0))


def test_elevation_matches_openfast():
    sea, waves = _sea()
    ref = _reference()
    for channel, point in (("Wave1Elev", (0.0, 0.0)), ("Wave2Elev", (40.0, -20.0))):
        got = catmull_rom(grid_elevation(waves, sea, *point)[:, None], waves.time_step, ref["Time"])[:, 0]
        assert np.abs(got - ref[channel]).max() < 2e-6, channel
        assert ref[channel].std() > 0.4


@needs_deck
def test_excitation_matches_openfast(tmp_path):
    from mbsym.wind.offshore.platform import platform_hydrodynamics

    shutil.copy(DATA / "wc7_SeaState.dat", tmp_path / "sea.dat")
    shutil.copy(DATA / "components.txt", tmp_path / "components.txt")
    with pytest.warns(Warning):
        hydro = platform_hydrodynamics(CASE / "fl_decay_a_HydroDyn.dat", water_density=1025.0, gravity=G,
                                       seastate=tmp_path / "sea.dat", water_depth=DEPTH)
    ref = _reference()
    forces = catmull_rom(hydro.waves.forces, hydro.waves.waves.time_step, ref["Time"])
    for j, name in enumerate(("B1WvsFxi", "B1WvsFyi", "B1WvsFzi", "B1WvsMxi", "B1WvsMyi", "B1WvsMzi")):
        assert np.abs(forces[:, j] - ref[name]).max() < 1e-5 * ref[name].std(), name
