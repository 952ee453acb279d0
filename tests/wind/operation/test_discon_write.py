"""ROSCO's library on the built-in NREL 5 MW: the package writes its DISCON.IN (issue 22 item 9).

References: ROSCO 2.10.6's own ``Examples/Test_Cases/NREL-5MW/DISCON.IN`` and ``Cp_Ct_Cq.NREL5MW.txt``
(the rosco wheel, fetched once with ``pip download``; the shared OpenFAST runs hold the same file with
``LoggingLevel 0``), read key by key with mbsym's reader and run by ROSCO's own library.
"""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from _op_data import DECK, discon_other_data, need
from mbsym.exceptions import ControllerError
from mbsym.wind.control.discon_write import HEADER
from mbsym.wind.deck.discon_in import DISCON_KEYS, read_discon_in
from mbsym.wind.deck.performance import read_performance_table
from mbsym.wind.operation.nrel5mw import write_nrel5mw_discon


def _wheel_files():
    import _rosco

    if _rosco.rosco_library() is None or _rosco.rosco_nrel5mw_discon() is None:
        pytest.skip("the ROSCO 2.10.6 wheel is not cached and could not be fetched with pip")
    path = _rosco.rosco_nrel5mw_discon()
    return path, path.parent / "Cp_Ct_Cq.NREL5MW.txt"


def _same(a, b) -> bool:
    return a == b if isinstance(a, str) else np.array_equal(np.asarray(a), np.asarray(b))


def test_builtin_discon_data_matches_the_discon_in():
    from importlib import resources

    packaged = json.loads(resources.files("mbsym.wind.operation").joinpath("data/nrel5mw_discon.json")
                          .read_text(encoding="utf-8"))
    generated = json.loads(json.dumps(discon_other_data(need(DECK / "DISCON.IN"))))
    assert packaged["other"] == generated["other"]
    assert packaged["ct"] == generated["ct"] and packaged["cq"] == generated["cq"]


def test_written_discon_in_is_roscos_key_by_key(tmp_path):
    """Every key ROSCO 2.10.6 reads, equal to the wheel's file; only the performance file's name and the debug
    output (LoggingLevel 1 in the wheel, 0 here: no .dbg files) differ. The performance tables are equal to
    the 6 decimals ROSCO's file has (exact: the same decimal strings)."""
    wheel_in, wheel_perf = _wheel_files()
    path = write_nrel5mw_discon(tmp_path)
    ours, theirs = read_discon_in(path), read_discon_in(wheel_in)
    assert [s.key for s in DISCON_KEYS] == [k for k, _ in sorted(ours.lines.items(), key=lambda kv: kv[1])]
    differ = {s.key for s in DISCON_KEYS if not _same(ours[s.key], theirs[s.key])}
    assert differ == {"PerfFileName", "LoggingLevel"}
    assert ours["LoggingLevel"] == 0 and (path.parent / ours["PerfFileName"]).is_file()
    a, b = read_performance_table(ours.performance_file), read_performance_table(wheel_perf)
    for name in ("tsr", "pitch", "cp", "ct", "cq"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def test_written_discon_in_reads_back_as_the_builtin_settings(tmp_path):
    from mbsym.wind.control import BaselineSettings
    from mbsym.wind.operation.nrel5mw import nrel5mw_baseline_settings

    back = BaselineSettings.from_discon(write_nrel5mw_discon(tmp_path), dt=0.01)
    ref = nrel5mw_baseline_settings(0.01)
    for f in ref.__dataclass_fields__:
        if f != "source":
            # 5e-7: the power table is written with ROSCO's 6 decimals (the package holds the same decimals)
            np.testing.assert_allclose(np.asarray(getattr(back, f), dtype=float),
                                       np.asarray(getattr(ref, f), dtype=float), rtol=1e-12, atol=5e-7, err_msg=f)


def test_an_existing_foreign_discon_in_is_not_replaced(tmp_path):
    (tmp_path / "DISCON.IN").write_text("1  ! LoggingLevel\n")
    with pytest.raises(ControllerError, match="not written by mbsym; not replacing"):
        write_nrel5mw_discon(tmp_path)
    assert (tmp_path / "DISCON.IN").read_text() == "1  ! LoggingLevel\n"
    (tmp_path / "DISCON.IN").unlink()
    first = write_nrel5mw_discon(tmp_path).read_text()
    assert first.startswith(HEADER) and write_nrel5mw_discon(tmp_path).read_text() == first     # ours: rewritten


def test_builtin_turbine_without_a_folder_names_where_a_discon_in_is(tmp_path):
    from mbsym.wind.operation.deck import builtin_deck

    lib = tmp_path / "libdiscon.so"
    lib.write_bytes(b"")
    with pytest.raises(ControllerError, match="write_nrel5mw_discon.*Examples/Test_Cases/NREL-5MW/DISCON.IN"):
        builtin_deck().discon_paths(lib)
    lib_path, infile = builtin_deck().discon_paths(lib, folder=tmp_path)
    assert infile == tmp_path / "nrel5mw_rosco" / "DISCON.IN" and infile.read_text().startswith(HEADER)


@pytest.mark.slow
def test_rosco_library_runs_the_written_discon_in_as_its_own(rosco_lib, tmp_path, capsys):
    """``mbsym simulate --discon libdiscon.so`` on the built-in turbine (the issue's command) writes the DISCON.IN,
    says where, and ROSCO's library then commands the same pitch and torque as with the wheel's own file:
    identical to the last digit of the CSV (same numbers parsed by the same library; a tolerance of 1e-9 deg
    and 1e-9 kN m only absorbs the CSV's decimal round trip)."""
    from mbsym.cli import main

    wheel_in, wheel_perf = _wheel_files()
    theirs_dir = tmp_path / "wheel"
    theirs_dir.mkdir()
    text = wheel_in.read_text().replace("1                   ! LoggingLevel", "0                   ! LoggingLevel")
    (theirs_dir / "DISCON.IN").write_text(text)
    shutil.copy(wheel_perf, theirs_dir / wheel_perf.name)
    common = ["simulate", "--discon", str(rosco_lib), "--wind", "step:12:15:1", "--tmax", "3"]
    assert main(common + ["--out", str(tmp_path / "ours.csv")]) == 0
    out = capsys.readouterr().out
    written = tmp_path / "nrel5mw_rosco" / "DISCON.IN"
    assert f"to {written}" in out and written.is_file()
    assert main(common + ["--discon-input", str(theirs_dir / "DISCON.IN"), "--out", str(tmp_path / "theirs.csv")]) == 0
    ours, theirs = (_csv(tmp_path / f"{n}.csv") for n in ("ours", "theirs"))
    assert np.ptp(theirs["BldPitch1_[deg]"]) > 0.5                      # the pitch loop acts in the step
    for name in ("BldPitch1_[deg]", "GenTq_[kN-m]"):
        np.testing.assert_allclose(ours[name], theirs[name], rtol=0.0, atol=1e-9, err_msg=name)


def _csv(path) -> dict:
    data = np.genfromtxt(path, delimiter=",", names=True, deletechars="")
    return {n: data[n] for n in data.dtype.names}
