"""InflowWind decks → spatial wind (InflowWindSettings.field), refusals with file/line/key, rotor-effective wind.

References: the shared OpenFAST decks (ff14_flex: WindType 3 with a relative FileName_BTS; ss14_yaw10_flex:
steady wind turned 10 deg) and their OpenFAST outputs; the README statistics of the ff14 rotor-disk average
(std 1.50 m/s vs 1.99 m/s at the hub, correlation 0.70); closed forms for a linearly sheared uniform wind.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError, WindInputError
from mbsym.wind.deck.inflowwind import read_inflowwind
from mbsym.wind.inflow import FullFieldWind, TabulatedWind, UniformFieldWind, UniformWind, rotor_effective_wind

from .conftest import need


@pytest.fixture(scope="module")
def ff14_deck(aero):
    return need(aero / "openfast_inputs" / "ff14_flex" / "ff14_flex_IfW.dat")


def _mutated(tmp_path, source, old, new):
    text = source.read_text()
    assert old in text
    path = tmp_path / source.name
    path.write_text(text.replace(old, new))
    return path


def test_full_field_deck_reads_the_bts_relative_to_the_deck(ff14_deck):
    ifw = read_inflowwind(ff14_deck)
    assert ifw.wind_type == 3 and ifw.full_field_file.resolve().name == "ff14.bts"
    field = ifw.field()
    assert isinstance(field, FullFieldWind) and (field.n_y, field.n_z) == (25, 25)
    with pytest.raises(WindInputError, match="full field"):
        ifw.wind()                                            # a hub signal would drop the field: refused
    hub = ifw.wind(allow_unmodelled=True)                     # ... unless asked: Wind1VelX at (0, 0, RefHt)
    assert hub(0.05) == pytest.approx(16.4421, abs=1e-4)      # ff14_rigid.csv, first row


def test_steady_deck_with_propagation_direction(aero):
    ifw = read_inflowwind(need(aero / "openfast_inputs" / "ss14_yaw10_flex" / "ss14_yaw10_flex_IfW.dat"))
    field = ifw.field()
    assert isinstance(field, UniformFieldWind)
    assert field.propagation_direction == pytest.approx(10 * math.pi / 180)
    assert np.allclose(field.velocity(0.0, [0.0, 0.0, 90.0]), [13.78731, -2.431074, 0.0], atol=1e-5)  # OpenFAST


def test_uniform_deck_field(aero):
    ifw = read_inflowwind(need(aero / "openfast_inputs" / "step_10_14" / "step_10_14_IfW.dat"))
    field = ifw.field()
    assert field.reference_length == 125.88 and field.velocity(40.0, [0.0, 0.0, 90.0])[0] == 14.0
    assert ifw.wind()(40.0) == 14.0                           # the hub signal as before


@pytest.mark.parametrize("old, new, key, match", [
    ("          3   WindType", "          6   WindType", "WindType", "must be 1 .* or 7 .native Bladed.: mbsym "
     "does not model user-defined wind"),
    ("0                      SensorType", "2                      SensorType", "SensorType", "continuous-wave"),
])
def test_unmodelled_settings_are_refused_with_file_line_key(tmp_path, ff14_deck, old, new, key, match):
    path = _mutated(tmp_path, ff14_deck, old, new)
    with pytest.raises(OpenFASTFormatError, match=match) as info:
        read_inflowwind(path)
    line = next(i for i, text in enumerate(path.read_text().splitlines(), 1) if new in text)
    assert f"{path}, line {line}, key '{key}'" in str(info.value)


def test_cubic_interpolation_is_taken_and_missing_files_are_refused_by_field(tmp_path, ff14_deck):
    cubic = _mutated(tmp_path, ff14_deck, "False         VelInterpCubic", "True          VelInterpCubic")
    assert read_inflowwind(cubic).cubic_interpolation        # taken, not refused: test_wind_cubic.py
    missing = _mutated(tmp_path, ff14_deck, '"../../wind/ff14.bts"', '"nowhere.bts"')
    with pytest.raises(OpenFASTFormatError, match="line 22, key 'FileName_BTS'.*not found: tried 'nowhere.bts'"):
        read_inflowwind(missing).field()


def test_rotor_effective_wind_of_a_linear_shear_is_exact():
    """A uniform field with linear shears only: disk average = HorSpd, plane fit = the shears (with L = 2R)."""
    table = UniformWind([0.0], [12.0], horizontal_shear=[0.15], linear_vertical_shear=[0.25])
    field = UniformFieldWind(table, 90.0, 126.0)
    out = rotor_effective_wind(field, hub_height=90.0, radius=63.0, times=[0.0, 1.0], n_radial=5, n_azimuth=12)
    assert np.allclose(out["average"], 12.0, atol=1e-12) and out["reference_length"] == 126.0
    assert np.allclose(out["horizontal_shear"], 0.15, atol=1e-12)
    assert np.allclose(out["vertical_shear"], 0.25, atol=1e-12)
    assert isinstance(out["signal"], TabulatedWind) and out["signal"](0.5) == pytest.approx(12.0)


def test_ff14_disk_average_statistics_of_the_readme(ff14_deck):
    """README: disk (R 63 m, hub 90 m) average std 1.50 m/s, hub 1.99 m/s, correlation 0.70 over 660 s.
    A coarse grid (6 x 16 every 0.2 s) keeps the test fast; measured: 1.513, 1.993, 0.702 (12 x 36 every
    0.05 s: 1.504, 1.989, 0.702). Tolerances: 0.03 m/s, 0.01 m/s, 0.02 (the README's rounding + the grid)."""
    field = read_inflowwind(ff14_deck).field()
    t = np.arange(0.0, 660.0001, 0.2)
    out = rotor_effective_wind(field, hub_height=90.0, radius=63.0, times=t, n_radial=6, n_azimuth=16)
    assert out["average"].std() == pytest.approx(1.50, abs=0.03)
    assert out["hub_speed"].std() == pytest.approx(1.99, abs=0.01)
    assert np.corrcoef(out["average"], out["hub_speed"])[0, 1] == pytest.approx(0.70, abs=0.02)
    # the mean shear of the plane fit follows the file's power law 0.2: d/dz (z/90)^0.2 * 126 m = 0.28 at the hub
    assert out["vertical_shear"].mean() == pytest.approx(0.28, abs=0.05)


def test_rotor_effective_wind_bad_arguments():
    field = UniformFieldWind.steady(10.0, reference_height=90.0)
    with pytest.raises(WindInputError, match="radius must be a number greater than 0"):
        rotor_effective_wind(field, hub_height=90.0, radius=-1.0, times=[0.0])
    with pytest.raises(WindInputError, match="n_radial must be an integer"):
        rotor_effective_wind(field, hub_height=90.0, radius=63.0, times=[0.0], n_radial=2.5)
