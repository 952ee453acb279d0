"""SeaState's constrained waves (mbsym.wind.offshore.constrained, ``ConstWaveMod`` 1 and 2).

References, each independent of the code under test:
- what the constraint promises: the elevation at the crest's place and time is ``CrestHmax/2`` (mode 1) with zero
  slope, or the crest stands ``CrestHmax`` over the lower neighbouring trough within SeaState's 1 mm (mode 2);
- OpenFAST v5.0.0's ``Wave1Elev``/``Wave2Elev`` of the same seas (tests/data/openfast_constrained_waves/README.md):
  mode 2 within SeaState's own crest tolerance (1 mm; measured 0.54 mm, the single-precision iteration stops at
  another point inside it), mode 1 (a spread sea) at the crest point and at the origin within 2e-5 m (measured
  6.7e-6 and 5.1e-6 m: SeaState's single precision).
"""

from __future__ import annotations

import csv
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ModelWarning, ParameterError
from mbsym.wind.deck.seastate import read_seastate
from mbsym.wind.offshore.waves import grid_elevation, incident_waves

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_constrained_waves"
G, DEPTH = 9.81, 200.0                      # the decks' .fst Gravity


def _reference(name: str) -> dict[str, np.ndarray]:
    with (DATA / f"{name}.csv").open() as fh:
        rows = list(csv.reader(fh))
    data = np.array(rows[1:], dtype=float)
    return {h.split("_[")[0]: data[:, k] for k, h in enumerate(rows[0])}


def _sea(name: str):
    sea = read_seastate(DATA / f"{name}_SeaState.dat")
    return sea, incident_waves(sea, gravity=G, water_depth=DEPTH)


def test_crest_elevation_mode_at_its_place_and_time():
    sea, waves = _sea("cw1")
    eta = waves.elevation(40.0, -20.0)
    t = waves.times()
    k = int(np.flatnonzero(np.isclose(t, 45.0))[0])
    assert eta[k] == pytest.approx(5.0, abs=1e-9)
    assert (eta[k + 1] - eta[k - 1]) / (2 * waves.time_step) == pytest.approx(0.0, abs=2e-2 * 5.0)
    assert "constrained" in waves.description


def test_crest_height_mode_stands_over_its_trough():
    sea, waves = _sea("cw2")
    eta, t = waves.elevation(), waves.times()
    k = int(np.flatnonzero(np.isclose(t, 60.0))[0])
    window = math.ceil(10.0 / 0.25)
    trough = min(eta[k + 1:k + window + 1].min(), eta[k - window:k].min())
    assert eta[k] - trough == pytest.approx(12.0, abs=1e-3)
    assert eta[k] == eta[:-1].max()


@pytest.mark.parametrize("name, channel, point, bound", [
    ("cw2", "Wave1Elev", (0.0, 0.0), 1e-3), ("cw1", "Wave2Elev", (40.0, -20.0), 2e-5),
    ("cw1", "Wave1Elev", (0.0, 0.0), 2e-5)])
def test_elevation_matches_openfast(name, channel, point, bound):
    sea, waves = _sea(name)
    ref = _reference(name)
    got = np.interp(ref["Time"], waves.times(), grid_elevation(waves, sea, *point))
    assert np.abs(got - ref[channel]).max() <= bound
    assert ref[channel].std() > 1.0                               # a sea, not a flat line


def test_crest_lower_than_the_sea_is_refused_and_other_wave_models_warn(tmp_path):
    from .test_offshore_current import edit

    path = tmp_path / "sea.dat"
    shutil.copy(DATA / "cw2_SeaState.dat", path)
    with pytest.raises(ParameterError, match="CrestHmax"):
        incident_waves(read_seastate(edit(path, {"CrestHmax": "3.0"})), gravity=G, water_depth=DEPTH)
    edit(path, {"WaveMod": "3"})                                       # white noise: SeaState ignores the constraint
    with pytest.warns(ModelWarning, match="ConstWaveMod"):
        incident_waves(read_seastate(path), gravity=G, water_depth=DEPTH)
