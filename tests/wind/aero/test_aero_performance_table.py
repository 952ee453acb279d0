"""ROSCO ``Cp_Ct_Cq`` performance tables: reading, writing, typed errors.

References: ROSCO's published NREL 5 MW table (``../shared/openfast/aero/Cp_Ct_Cq.NREL5MW.txt``,
written by the ROSCO toolbox) for the layout and its internal consistency (cq = cp / tsr),
and small hand-written tables whose values are known exactly.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import DimensionError, OpenFASTFormatError, ParameterError
from mbsym.wind.deck.performance import (
    PerformanceTable, read_performance_table, write_performance_table,
)

from .conftest import ROSCO_TABLE, need


@pytest.fixture(scope="module")
def rosco_table() -> PerformanceTable:
    return read_performance_table(need(ROSCO_TABLE))


def small_table() -> PerformanceTable:
    tsr = np.array([4.0, 6.0, 8.0])
    pitch = np.deg2rad([-1.0, 0.0, 2.5, 5.0])
    cp = np.array([[0.20, 0.25, 0.22, 0.18], [0.40, 0.45, 0.40, 0.30], [0.35, 0.44, 0.38, 0.20]])
    return PerformanceTable(tsr=tsr, pitch=pitch, cp=cp, ct=cp + 0.3, cq=cp / tsr[:, None],
                            wind_speed=11.4, source="hand-written")


SMALL_TEXT = """\
# ----- Rotor performance tables for the test wind turbine -----
# ------------ hand written ------------

# Pitch angle vector, 3 entries - x axis (matrix columns) (deg)
0.0   1.0   2.0
# TSR vector, 2 entries - y axis (matrix rows) (-)
5.0   7.0
# Wind speed vector - z axis (m/s)
11.4

# Power coefficient

0.30   0.31   0.32
0.40   0.41   0.42


#  Thrust coefficient

0.60   0.61   0.62
0.80   0.81   0.82


# Torque coefficient

0.060   0.062   0.064
0.057   0.058   0.060

"""


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "Cp_Ct_Cq.test.txt"
    path.write_text(text)
    return path


# ----------------------------------------------------------------------------- reading
def test_reads_rosco_nrel5mw_table(rosco_table):
    t = rosco_table
    assert t.cp.shape == t.ct.shape == t.cq.shape == (26, 36)
    assert t.tsr[0] == 2.0 and t.tsr[-1] == 14.5
    np.testing.assert_allclose(t.pitch_deg[[0, -1]], [-5.0, 30.0], rtol=0, atol=1e-12)
    assert t.wind_speed == 11.4
    # ROSCO's peak Cp of the NREL 5 MW is 0.4659 (max of the published table, shared README
    # quotes 0.4657 at the region-2 operating point TSR 7.6, pitch 0).
    assert abs(t.cp.max() - 0.465861) < 1e-6
    # Independent invariant: Q = P / Omega, so cq = cp / tsr; ROSCO computes them separately
    # (CCBlade torque and power), agreeing to 1e-3 absolute.
    np.testing.assert_allclose(t.cq, t.cp / t.tsr[:, None], rtol=0, atol=1e-3)


def test_small_table_values_and_units(tmp_path):
    t = read_performance_table(write(tmp_path, SMALL_TEXT))
    np.testing.assert_array_equal(t.tsr, [5.0, 7.0])
    np.testing.assert_allclose(t.pitch, np.deg2rad([0.0, 1.0, 2.0]), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(t.cp, [[0.30, 0.31, 0.32], [0.40, 0.41, 0.42]])
    np.testing.assert_array_equal(t.ct[1], [0.80, 0.81, 0.82])
    np.testing.assert_array_equal(t.cq[0], [0.060, 0.062, 0.064])
    assert t.source == str(tmp_path / "Cp_Ct_Cq.test.txt")


def test_table_is_immutable():
    t = small_table()
    with pytest.raises(ValueError):
        t.cp[0, 0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        t.tsr = np.array([1.0, 2.0])  # type: ignore[misc]


# ----------------------------------------------------------------------------- writing
def test_round_trip_is_exact_on_axes_and_to_the_written_decimals(tmp_path):
    t = small_table()
    back = read_performance_table(write_performance_table(t, tmp_path / "t.txt", decimals=10))
    np.testing.assert_array_equal(back.tsr, t.tsr)
    np.testing.assert_allclose(back.pitch, t.pitch, rtol=1e-15, atol=0)
    for name in ("cp", "ct", "cq"):
        np.testing.assert_allclose(getattr(back, name), getattr(t, name), rtol=0, atol=5e-11)
    assert back.wind_speed == 11.4


def test_written_layout_matches_rosco_line_for_line(rosco_table, tmp_path):
    # ROSCO's Fortran reader reads the file by line position: labels, blank lines and
    # value rows must sit on the same lines as in ROSCO's own file.
    out = write_performance_table(rosco_table, tmp_path / "t.txt", turbine_name="NREL-5MW")

    def kinds(path: Path) -> list[str]:
        return ["blank" if not s.strip() else "label" if s.lstrip().startswith("#") else "values"
                for s in path.read_text().splitlines()]

    assert kinds(out) == kinds(ROSCO_TABLE)
    assert read_performance_table(out) == rosco_table  # ROSCO writes 6 decimals, as we do


def test_write_rejects_bad_options(tmp_path):
    with pytest.raises(TypeError, match="PerformanceTable"):
        write_performance_table({"cp": 1}, tmp_path / "t.txt")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="decimals"):
        write_performance_table(small_table(), tmp_path / "t.txt", decimals=0)
    with pytest.raises(TypeError):
        write_performance_table(small_table(), tmp_path / "t.txt", digits=3)  # type: ignore[call-arg]


# ----------------------------------------------------------------------------- constructor
def test_constructor_checks_shapes_and_axes():
    t = small_table()
    with pytest.raises(DimensionError, match=r"cp must have shape \(len\(tsr\), len\(pitch\)\)"):
        dataclasses.replace(t, cp=t.cp[:, :3])
    with pytest.raises(ParameterError, match="tsr must hold at least 2 strictly increasing"):
        dataclasses.replace(t, tsr=np.array([4.0, 4.0, 8.0]))
    with pytest.raises(ParameterError, match="non-finite"):
        dataclasses.replace(t, ct=np.full((3, 4), np.nan))
    with pytest.raises(ParameterError, match="wind_speed"):
        dataclasses.replace(t, wind_speed=-1.0)


# ----------------------------------------------------------------------------- bad files
def _bad(tmp_path: Path, old: str, new: str, count: int = 1) -> Path:
    text, n = re.subn(old, new, SMALL_TEXT, count=count, flags=re.M)
    assert n == count, f"mutation {old!r} did not apply"
    return write(tmp_path, text)


@pytest.mark.parametrize("old, new, message", [
    (r"^0\.40   0\.41   0\.42$", "0.40   0.41   x42", r"line 14: expected numbers, got 'x42'"),
    (r"^0\.40   0\.41   0\.42$", "0.40   0.41", r"line 14: this power coefficient row has 2 values; "
                                               r"expected 3"),
    (r"^0\.80   0\.81   0\.82\n", "", r"line 17: the thrust coefficient table has 1 rows; "
                                      r"expected 2"),
    (r"^5\.0   7\.0$", "7.0   5.0", r"line 7: the TSR vector must strictly increase"),
    (r"3 entries", "4 entries", r"line 4: the label says 4 entries, but 3 values follow"),
    (r"^# Torque coefficient$", "# something else", r"section '# Torque coefficient' is missing"),
    (r"^# Pitch angle vector.*\n0\.0   1\.0   2\.0\n", "",
     r"section '# Pitch angle vector, <n> entries.*' is missing"),
    (r"^11\.4$", "11.4 12.0", r"line 8: expected one positive wind speed"),
    (r"^#  Thrust coefficient$", "# Power coefficient", r"line 17: a second '# Power coefficient' "
                                                        r"section \(the first is on line 11\)"),
    (r"^# Pitch angle vector.*$", "", r"line 5: numbers before any section label"),
])
def test_bad_table_raises_typed_error_with_file_and_line(tmp_path, old, new, message):
    path = _bad(tmp_path, old, new)
    with pytest.raises(OpenFASTFormatError, match=message) as info:
        read_performance_table(path)
    assert str(path) in str(info.value)
    assert isinstance(info.value, ValueError)


def test_several_problems_are_reported_together(tmp_path):
    text = SMALL_TEXT.replace("0.30   0.31   0.32", "0.30   0.31")
    text = text.replace("0.060   0.062   0.064", "0.060   nan   0.064")
    with pytest.raises(OpenFASTFormatError, match=r"(?s)2 problems in .*line 13.*line 25") as info:
        read_performance_table(write(tmp_path, text))
    assert "nan" in str(info.value)


def test_missing_file_names_the_path(tmp_path):
    with pytest.raises(OpenFASTFormatError, match="rotor performance table not found"):
        read_performance_table(tmp_path / "absent.txt")
