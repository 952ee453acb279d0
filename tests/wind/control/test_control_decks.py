"""ServoDyn and DISCON.IN readers: values of the shared NREL 5 MW deck, typed errors naming file, line and key.

References: the shared deck's files (``shared/openfast/aero/openfast_inputs/deck``) as OpenFAST and
ROSCO 2.10.6 read them (values checked against the text of the files; units as documented there).
"""

from __future__ import annotations

import math
import re
import shutil

import numpy as np
import pytest

from _ctrl_data import DECK, need
from mbsym.exceptions import ControllerError, OpenFASTFormatError
from mbsym.wind.control import BaselineSettings
from mbsym.wind.deck.discon_in import read_discon_in
from mbsym.wind.deck.servodyn import read_servodyn

SERVODYN = "NRELOffshrBsline5MW_Onshore_ServoDyn.dat"


@pytest.fixture
def deck_copy(tmp_path):
    """A writable copy of the shared ServoDyn file, DISCON.IN and Cp table."""
    for name in (SERVODYN, "DISCON.IN", "Cp_Ct_Cq.NREL5MW.txt"):
        shutil.copy(need(DECK / name), tmp_path / name)
        (tmp_path / name).chmod(0o644)
    return tmp_path


def _edit(path, old, new):
    text = path.read_text()
    changed, n = re.subn(old, new, text, count=1, flags=re.M)
    assert n == 1, f"mutation {old!r} did not apply to {path.name}"
    path.write_text(changed)


def test_servodyn_of_the_shared_deck():
    srv = read_servodyn(need(DECK / SERVODYN))
    assert srv.pitch_control_mode == 5 and srv.torque_control_mode == 5 and srv.uses_library
    assert srv.generator_efficiency == pytest.approx(0.944)
    assert srv.library.name == "libdiscon.so" and srv.library.parent.name == "lib"
    assert srv.library_input == DECK / "DISCON.IN" and srv.procedure_name == "DISCON"
    assert srv.library_time_step == "default" and srv.time_step == "default"
    assert srv.controller_time_step(0.00625) == 0.00625
    assert srv.individual_pitch == 1 and srv.n_torque_table == 0 and srv.torque_table_speed.size == 0
    assert srv.pitch_filter_cutoff == pytest.approx(2 * math.pi * 9999.9)      # Hz -> rad/s
    assert "PitSpr(1)" in srv.extra and srv.lines["DLL_FileName"] == 86


def test_servodyn_torque_table_in_rpm_becomes_rad_per_s(deck_copy):
    path = deck_copy / SERVODYN
    _edit(path, r"^          0   DLL_NumTrq", "          2   DLL_NumTrq")
    _edit(path, r"^ \(rpm\)          \(Nm\)\n", " (rpm)          (Nm)\n 600  10000\n 1200  40000\n")
    srv = read_servodyn(path)
    assert np.allclose(srv.torque_table_speed, [600 * math.pi / 30, 1200 * math.pi / 30])
    assert srv.torque_table_torque.tolist() == [10000.0, 40000.0]


@pytest.mark.parametrize("old, new, match", [
    (r"^          5   PCMode", "          7   PCMode", r"line 7, key 'PCMode'.*must be one of 0, 3, 4, 5"),
    (r"^       94.4   GenEff", "       120.0  GenEff", r"key 'GenEff'.*\[0, 100\]"),
    (r"^          1   Ptch_Cntrl", "          x   Ptch_Cntrl", r"key 'Ptch_Cntrl'.*expected an integer"),
    (r"^          0   DLL_NumTrq", "          2   DLL_NumTrq", r"key 'DLL_NumTrq'.*says 2 rows.*has 0"),
    (r'^"DISCON.IN"    DLL_InFile.*\n', "", r"key 'DLL_InFile'.*missing"),
])
def test_bad_servodyn_files_name_file_line_and_key(deck_copy, old, new, match):
    path = deck_copy / SERVODYN
    _edit(path, old, new)
    with pytest.raises(OpenFASTFormatError, match=match) as info:
        read_servodyn(path)
    assert str(path) in str(info.value)


def test_discon_in_of_the_shared_deck(discon_in):
    d = read_discon_in(discon_in)
    assert len(d.values) == 195            # every key ROSCO reads is in the file
    assert d["VS_ControlMode"] == 2 and d["WE_Mode"] == 2 and d["PS_Mode"] == 1 and d["vs_controlmode"] == 2
    assert d["PC_GS_KP"].shape == (30,) and d["PC_GS_KP"][0] == -2.075e-02 and d["PC_GS_KI"][-1] == -1.917e-03
    assert d["WE_FOPoles"].shape == (60,) and d["PerfTableSize"].tolist() == [36, 26]
    assert d["PerfFileName"] == "Cp_Ct_Cq.NREL5MW.txt" and d.performance_file == discon_in.parent / d["PerfFileName"]
    assert d["ZMQ_CommAddress"] == "tcp://localhost:5555" and d["VS_RtPwr"] == 5.0e6
    assert d.lines["PC_GS_KP"] == 59 and d.where("VS_KP").endswith("line 92, key 'VS_KP'")
    assert not d.extra and not d.ignored_lines
    with pytest.raises(KeyError, match="not a ROSCO 2.10.6 DISCON.IN key"):
        d["NoSuchKey"]


@pytest.mark.parametrize("old, new, match", [
    (r"^1.57080             ! F_LPFCornerFreq", "1.5x080  ! F_LPFCornerFreq",
     r"line 38, key 'F_LPFCornerFreq'.*expected finite number"),
    (r"^1.57080             ! F_LPFCornerFreq.*\n", "", r"key 'F_LPFCornerFreq'.*missing"),
    (r"^30                  ! PC_GS_n", "29                  ! PC_GS_n",
     r"line 58, key 'PC_GS_angles'.*expected 29 values \(PC_GS_n = 29 on line 57\), got 30"),
    (r"^0.057        0.084", "0.090        0.084", r"key 'PC_GS_angles'.*strictly increase.*entry 2"),
    (r"^-0.17450000000      ! PC_MinRat", "0.1745   ! PC_MinRat", r"line 66, key 'PC_MinRat'.*less than 0"),
    (r"^4.30935e\+04         ! VS_RtTq", "5.30935e+04         ! VS_RtTq", r"key 'VS_MaxTq'.*VS_RtTq"),
    (r"^2                   ! WE_Mode", "7                   ! WE_Mode", r"key 'WE_Mode'.*between 0 and 2"),
    (r"^1                   ! VS_n", "1                   ! VS_n\n2  ! VS_n",
     r"line 92, key 'VS_n'.*duplicate key \(also on line 91\)"),
    (r"^60                  ! WE_FOPoles_N", "1.5                 ! WE_FOPoles_N", r"key 'WE_FOPoles_N'.*integer"),
])
def test_bad_discon_in_files_name_file_line_and_key(deck_copy, old, new, match):
    path = deck_copy / "DISCON.IN"
    _edit(path, old, new)
    with pytest.raises(OpenFASTFormatError, match=match) as info:
        read_discon_in(path)
    assert str(path) in str(info.value)


def test_free_text_lines_are_skipped_and_listed_like_rosco(deck_copy):
    path = deck_copy / "DISCON.IN"
    _edit(path, r"^(!------- FILTERS)", r"Some text ROSCO ignores\n\1")
    d = read_discon_in(path)
    assert list(d.ignored_lines.values()) == ["Some text ROSCO ignores"]


def test_baseline_refuses_unsupported_modes_naming_the_line(deck_copy):
    path = deck_copy / "DISCON.IN"
    # (IPC_ControlMode 1 was refused here before the baseline modelled IPC: test_baseline_ipc.py)
    _edit(path, r"^0                   ! Y_ControlMode", "1                   ! Y_ControlMode")
    with pytest.raises(ControllerError, match=r"line 17, key 'Y_ControlMode'.*Y_ControlMode = 1 is not supported"):
        BaselineSettings.from_discon(path, dt=0.00625)


def test_baseline_reports_a_missing_performance_table_at_perffilename(deck_copy):
    (deck_copy / "Cp_Ct_Cq.NREL5MW.txt").unlink()
    with pytest.raises(OpenFASTFormatError, match=r"line 127, key 'PerfFileName'.*performance table not found"):
        BaselineSettings.from_discon(deck_copy / "DISCON.IN", dt=0.00625)


def test_baseline_reports_a_bad_performance_table_with_its_line(deck_copy):
    path = deck_copy / "Cp_Ct_Cq.NREL5MW.txt"
    lines = path.read_text().splitlines()
    row = next(i for i, line in enumerate(lines) if line.startswith("# Power coefficient")) + 2
    lines[row] = lines[row].replace(lines[row].split()[3], "oops", 1)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(OpenFASTFormatError, match=rf"Cp_Ct_Cq.NREL5MW.txt.*line {row + 1}"):
        BaselineSettings.from_discon(deck_copy / "DISCON.IN", dt=0.00625)


def test_a_main_fst_leads_to_its_servodyn_library_and_discon_in():
    from mbsym.wind.deck.servodyn import deck_servodyn
    fst = need(DECK.parent / "step_10_14" / "step_10_14.fst")
    srv, dt = deck_servodyn(fst)
    assert dt == 0.00625 and srv.controller_time_step(dt) == 0.00625
    assert srv.library_input.resolve() == (DECK / "DISCON.IN").resolve()
    assert read_discon_in(srv.library_input)["VS_ControlMode"] == 2
