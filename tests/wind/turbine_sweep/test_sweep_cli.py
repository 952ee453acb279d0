"""``mbsym sweep``: the CLI contract (columns, rows, error cells, typed errors, nothing left behind).

Free decays of the built-in NREL 5 MW (rigid blades), 1 s each: the contract is checked on the
table itself. References: the grid is the Cartesian product of the --set values (last key
fastest); a value below a key's physical bound (a negative stiffness tuner) must fail its own row
only; the CSV is written with 17 significant digits, so the swept values read back exactly.
"""

import csv
import math

import pytest

from mbsym.cli import main


def read(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]


def test_columns_exactly_as_passed_and_one_row_per_combination(tmp_path):
    out = tmp_path / "table.csv"
    rc = main(["sweep", "--set", "FAStTunr(1)=0.9,1.1", "--set", "TwrFADmp1=1,2,4", "--tmax", "1",
               "--channels", "TTDspFA,RotSpeed", "--out", str(out)])
    assert rc == 0
    header, rows = read(out)
    stats = [f"{c}_{s}" for c in ("TTDspFA", "RotSpeed") for s in ("mean", "std", "max", "min")]
    assert header == ["FAStTunr(1)", "TwrFADmp1", "wind"] + stats + ["error"]
    assert [(float(r[0]), float(r[1])) for r in rows] == [(a, b) for a in (0.9, 1.1) for b in (1.0, 2.0, 4.0)]
    assert all(r[2] == "none" and r[-1] == "" for r in rows)
    # the free decay starts from TTDspFA = 0.5 m (the built-in scene of mbsym simulate): its maximum
    assert all(float(r[header.index("TTDspFA_max")]) == pytest.approx(0.5, abs=1e-12) for r in rows)
    # damping changes the decay: the std falls as TwrFADmp(1) grows, at each tuner
    std = [float(r[header.index("TTDspFA_std")]) for r in rows]
    assert std[0] > std[1] > std[2] and std[3] > std[4] > std[5]


def test_a_failing_case_fills_its_error_cell_and_the_others_run(tmp_path, capsys):
    out = tmp_path / "table.csv"
    assert main(["sweep", "--set", "FAStTunr(1)=1,-1", "--tmax", "0.5", "--channels", "TTDspFA",
                 "--out", str(out)]) == 0
    header, rows = read(out)
    assert rows[0][-1] == "" and math.isfinite(float(rows[0][header.index("TTDspFA_mean")]))
    assert rows[1][-1].startswith("ParameterError: FAStTunr(1) = -1")
    assert all(math.isnan(float(v)) for v in rows[1][3:-1])
    assert "case 2 (FAStTunr(1)=-1.0, wind=none) failed" in capsys.readouterr().err


def test_initial_condition_keys_set_the_state_at_t0(tmp_path):
    out = tmp_path / "ic.csv"
    assert main(["sweep", "--set", "TTDspFA=0.2,0.4", "--set", "RotSpeed=6", "--tmax", "0.2",
                 "--channels", "TTDspFA,RotSpeed", "--out", str(out)]) == 0
    header, rows = read(out)
    # the decay starts at rest at the given deflection (max over the run), rotor at 6 rpm
    assert [float(r[header.index("TTDspFA_max")]) for r in rows] == pytest.approx([0.2, 0.4], abs=1e-12)
    assert [float(r[header.index("RotSpeed_mean")]) for r in rows] == pytest.approx([6.0, 6.0], rel=1e-3)


@pytest.mark.parametrize("args, message", [
    (["--set", "NoSuchKey=1,2"], "unknown sweep key 'NoSuchKey'"),
    (["--set", "TwrFADmp(1)=1,abc"], "'abc' is not a number"),
    (["--set", "TwrFADmp(1)"], "expected KEY=V1,V2"),
    (["--set", "NacMass=1", "--set", "NacMass=2"], "given twice"),
    (["--set", "wind=1"], "is not a swept key"),
    (["--set", "FlStTunr(1)=1"], "enable one of the DOFs ['FlapDOF1']"),
    (["--set", "NacMass=1", "--wind", "kaimal:12:0.1"], "'kaimal' takes 3 field(s)"),
    (["--set", "NacMass=1", "--wind", "no_such_file.wnd"], "neither a known form nor an existing file"),
    (["--set", "NacMass=1", "--executor", "dask:zero"], "executor 'dask:zero' is not understood"),
    (["--set", "NacMass=1", "--controller", "none"], "add --wind SPEC"),
    (["--set", "NacMass=1", "--tmax", "-1"], "--tmax must be a positive"),
    (["--set", "NacMass=1", "--wohler", "0"], "--wohler '0'"),
    (["--set", "NacMass=1", "--del", "TwrBsMyt"], "TwrBsMyt"),
])
def test_bad_input_is_one_typed_line_exit_2_and_no_file(tmp_path, capsys, args, message):
    out = tmp_path / "table.csv"
    out.write_text("previous\n")
    assert main(["sweep", *args, "--tmax", "0.1", "--out", str(out)] if "--tmax" not in args else
                ["sweep", *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mbsym sweep: error:") and message in err[0], err
    assert out.read_text() == "previous\n"                      # untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.csv"]     # no temporary left


def test_an_unwritable_destination_fails_before_running(tmp_path, capsys):
    assert main(["sweep", "--set", "NacMass=1", "--out", str(tmp_path / "missing" / "t.csv")]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_wind_sweep_on_dask_2_writes_the_serial_table_byte_for_byte(tmp_path):
    pytest.importorskip("distributed")
    args = ["sweep", "--set", "TwrFADmp(1)=1,2", "--wind", "steady:10", "--wind", "step:8:12:0.5", "--tmax", "1",
            "--channels", "GenPwr,TwrBsMyt", "--del", "TwrBsMyt", "--wohler", "4", "--controller", "baseline"]
    serial, dask = tmp_path / "serial.csv", tmp_path / "dask.csv"
    assert main([*args, "--out", str(serial)]) == 0
    assert main([*args, "--executor", "dask:2", "--out", str(dask)]) == 0
    header, rows = read(dask)
    stats = [f"{c}_{s}" for c in ("GenPwr", "TwrBsMyt") for s in ("mean", "std", "max", "min")]
    assert header == ["TwrFADmp(1)", "wind"] + stats + ["TwrBsMyt_del_m4", "error"]
    assert [(r[0], r[1]) for r in rows] == [(v, w) for v in ("1.0", "2.0") for w in ("steady:10", "step:8:12:0.5")]
    assert all(r[-1] == "" for r in rows)
    assert dask.read_bytes() == serial.read_bytes()
