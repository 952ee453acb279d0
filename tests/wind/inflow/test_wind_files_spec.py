"""Wind files (InflowWind uniform ``.hh``, ``Time_[s],Wind1VelX_[m/s]`` CSV), InflowWind decks, ``--wind`` specs.

References: the shared OpenFAST inputs (``shared/openfast/aero``): the uniform wind file OpenFAST ran,
its InflowWind deck, and OpenFAST's own ``Wind1VelX`` output of that run; round trips must be exact.
"""

from __future__ import annotations

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError, WindInputError
from mbsym.wind.deck.inflowwind import read_inflowwind
from mbsym.wind.inflow import (RampWind, StepWind, UniformWind, kaimal_wind, parse_wind_spec, read_uniform_wind,
                               read_wind_csv, write_uniform_wind, write_wind_csv)


def test_shared_uniform_file_gives_openfasts_wind1velx(aero):
    wind = read_uniform_wind(aero / "wind" / "step_10_14.hh").signal()
    out = read_wind_csv(aero / "step_10_14.csv")          # OpenFAST's Wind1VelX output, every 0.05 s
    assert np.max(np.abs(wind(out.time) - out.speed)) < 1e-6     # OpenFAST writes ~7 significant digits


def test_shared_inflowwind_deck_names_that_file(aero):
    ifw = read_inflowwind(aero / "openfast_inputs" / "step_10_14" / "step_10_14_IfW.dat")
    assert ifw.wind_type == 2 and ifw.uniform_reference_height == 90.0
    assert ifw.uniform_file.name == "step_10_14.hh"
    wind = ifw.wind()
    assert wind(29.9) == 10.0 and wind(30.05) == pytest.approx(12.0) and wind(31.0) == 14.0
    assert "WindVziList" in ifw.extra                             # unused keys are kept, not dropped


def test_uniform_file_round_trip_is_exact(tmp_path):
    rng = np.random.default_rng(0)
    n = 50
    original = UniformWind(time=np.cumsum(rng.uniform(0.01, 1.0, n)), speed=rng.uniform(3, 25, n),
                           direction=rng.uniform(-0.5, 0.5, n), vertical_speed=rng.normal(size=n),
                           horizontal_shear=rng.normal(size=n), power_law_exponent=rng.uniform(0, 0.3, n),
                           linear_vertical_shear=rng.normal(size=n), gust_speed=rng.normal(size=n),
                           upflow=rng.uniform(-0.1, 0.1, n))
    back = read_uniform_wind(write_uniform_wind(tmp_path / "w.hh", original, comment="round trip"))
    for name in ("time", "speed", "vertical_speed", "horizontal_shear", "power_law_exponent",
                 "linear_vertical_shear", "gust_speed"):
        assert np.array_equal(getattr(back, name), getattr(original, name)), name
    for name in ("direction", "upflow"):      # stored in rad, written in deg: one conversion each way
        assert np.max(np.abs(getattr(back, name) - getattr(original, name))) < 1e-15, name
    assert back.lines[0] == 5                  # 4 header comment lines


def test_signal_to_uniform_file_and_csv_and_back(tmp_path):
    for wind in (StepWind(10.0, 14.0, 30.0, rise=0.1), RampWind(4.0, 8.0, 2.0, 7.0),
                 kaimal_wind(12.0, 0.1, 3, duration=60.0)):
        hh = read_uniform_wind(write_uniform_wind(tmp_path / "a.hh", wind, t_end=60.0)).signal()
        csv = read_wind_csv(write_wind_csv(tmp_path / "a.csv", wind, t_end=60.0))
        t = np.linspace(0.0, 60.0, 2401)
        assert np.array_equal(hh(t), np.interp(t, *wind.table(60.0)))
        assert np.array_equal(csv(t), hh(t))
    table = kaimal_wind(9.0, 0.1, 1, duration=30.0)
    assert np.array_equal(read_wind_csv(write_wind_csv(tmp_path / "k.csv", table)).speed, table.speed)


def test_hub_signal_refuses_unmodelled_columns_unless_allowed():
    w = UniformWind(time=[0.0, 10.0], speed=[10.0, 12.0], direction=[0.0, 0.1], gust_speed=[1.0, 1.0])
    with pytest.raises(WindInputError, match="direction"):
        w.signal()
    hub = w.signal(allow_unmodelled=True)
    assert hub(10.0) == pytest.approx(13.0 * np.cos(0.1), rel=1e-15)   # (HorSpd + GstSpd) cos(WndDir)
    assert UniformWind(time=[0.0], speed=[7.0], gust_speed=[0.5]).signal()(3.0) == 7.5


@pytest.mark.parametrize("text, match, line", [
    ("! header\n0 10 0 0 0 0 0 0\n5 x 0 0 0 0 0 0\n", "expected numbers", 3),
    ("0 10 0 0 0 0 0\n", "expected 8 or 9 columns", 1),
    ("0 10 0 0 0 0 0 0\n1 10 0 0 0 0 0 0 0\n", "has 9 columns but line 1 has 8", 2),
    ("0 10 0 0 0 0 0 0\n! c\n0 11 0 0 0 0 0 0\n", "does not increase", 3),
    ("0 inf 0 0 0 0 0 0\n", "expected numbers", 1),
    ("! only comments\n\n", "no data rows", None),
])
def test_bad_uniform_files_name_file_and_line(tmp_path, text, match, line):
    path = tmp_path / "bad.hh"
    path.write_text(text)
    with pytest.raises(OpenFASTFormatError, match=match) as info:
        read_uniform_wind(path)
    assert str(path) in str(info.value)
    if line is not None:
        assert f"line {line}:" in str(info.value)


@pytest.mark.parametrize("text, match, line", [
    ("Time,WindSpeed\n0,10\n", "must name the columns", 1),
    ("Time_[s],Wind1VelX_[m/s]\n0,10\n1,abc\n", "expected numbers", 3),
    ("Time_[s],Wind1VelX_[m/s]\n0,10\n1,11,5\n", "3 values but the header has 2", 3),
    ("Time_[s],Wind1VelX_[m/s]\n0,10\n0,11\n", "does not increase", 3),
    ("Time_[s],Wind1VelX_[m/s]\n", "no data rows", None),
])
def test_bad_csv_files_name_file_and_line(tmp_path, text, match, line):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(OpenFASTFormatError, match=match) as info:
        read_wind_csv(path)
    if line is not None:
        assert f"line {line}:" in str(info.value)


def test_inflowwind_unmodelled_wind_type_is_refused_with_its_line(tmp_path, aero):
    source = aero / "openfast_inputs" / "step_10_14" / "step_10_14_IfW.dat"
    text = source.read_text().replace("          2   WindType", "          6   WindType")
    (tmp_path / "ifw.dat").write_text(text)
    with pytest.raises(OpenFASTFormatError, match="line 5, key 'WindType'.*must be 1 \\(steady\\), 2 .* or 7 .*"
                       "user-defined wind \\(6\\)"):
        read_inflowwind(tmp_path / "ifw.dat")


def test_spec_strings():
    assert parse_wind_spec("steady:12")(5.0) == 12.0
    step = parse_wind_spec("step:10:14:30")
    assert step(29.0) == 10.0 and step(30.0) == 14.0
    assert parse_wind_spec("ramp:4:8:10:20")(15.0) == pytest.approx(6.0)
    turbulent = parse_wind_spec("kaimal:12:14%:3", duration=120.0)
    assert turbulent.turbulence_intensity == pytest.approx(0.14) and turbulent.time[-1] == pytest.approx(120.0)
    assert np.array_equal(turbulent.speed, parse_wind_spec("kaimal:12:0.14:3", duration=120.0).speed)
    assert parse_wind_spec("eog:20:5:8")(5.0 + 10.5 / 2) == pytest.approx(20.0 - 0.37 * 8 * np.sin(1.5 * np.pi) * 2)


def test_spec_file_paths(tmp_path, aero):
    assert parse_wind_spec(str(aero / "wind" / "step_10_14.hh"))(40.0) == 14.0
    write_wind_csv(tmp_path / "w.csv", StepWind(5.0, 6.0, 1.0), t_end=2.0)
    assert parse_wind_spec(str(tmp_path / "w.csv"))(1.5) == 6.0


@pytest.mark.parametrize("spec, match", [
    ("steady", "takes 1 field"), ("steady:abc", "U must be a number"), ("step:10:14", "takes 3 field"),
    ("steady:-3", "at least 0"), ("kaimal:12:14:3", "fraction in \\(0, 1\\)"),
    ("kaimal:12:0.1:x", "non-negative integer"), ("gusty:12", "neither a known form nor an existing file"),
    ("/no/such/file.hh", "neither a known form"),
])
def test_bad_specs_raise_wind_input_errors(spec, match):
    with pytest.raises(WindInputError, match=match):
        parse_wind_spec(spec)


def test_a_main_fst_leads_to_its_wind(aero, tmp_path):
    from mbsym.wind.deck.inflowwind import deck_inflowwind
    fst = aero / "openfast_inputs" / "step_10_14" / "step_10_14.fst"
    assert deck_inflowwind(fst).wind()(40.0) == 14.0
    still = tmp_path / "still.fst"
    still.write_text(fst.read_text().replace("          1   CompInflow", "          0   CompInflow"))
    assert deck_inflowwind(still) is None
