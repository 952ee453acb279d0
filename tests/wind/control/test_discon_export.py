"""The exported DISCON library (``export_discon``, ``mbsym export-discon``) against the law it was built from.

Reference: :class:`BaselineController`'s own CasADi Function (``ctrl.function`` / ``ctrl.run``, and the
compiled in-loop baseline ``baseline_in_loop``), an independent path: the library runs C generated from
the same graph behind a hand-written swap-array wrapper, called by mbsym's :class:`DisconController` as
ServoDyn calls it.

Tolerances. The swap array is single precision: the library reads float32 measurements and writes
float32 commands, and computes in double in between. So, on measurement sequences that are float32
numbers, its commands must equal the law's commands rounded to float32 *exactly* (any wiring, unit,
record, state or timing error breaks that); the pitch then differs from the double-precision law by at
most half a float32 spacing, 7.5e-9 rad = 4.3e-7 deg for a pitch below 0.25 rad (observed 2.1e-7 deg),
the torque by at most 2^-25 of itself (0.0013 N m at 43 kN m; observed 0.0020 N m at the 43.3 kN m
of region 3, whose float32 spacing is 0.0039 N m: the bound is half of that).
In a closed loop the rounding of both directions is fed back (the measurements differ by the
commands' rounding): see test_closed_loop_in_mbsyms_discon_loop for the figures.
"""

from __future__ import annotations

import ctypes
import json
import re
import shutil
import subprocess

import numpy as np
import pytest
from _ctrl_data import DECK, need
from _measurements import ipc_sweep, synthetic_sweep

from mbsym.codegen import compiler_command
from mbsym.exceptions import ControllerError
from mbsym.wind.control import BaselineController, DisconController, export_discon
from mbsym.wind.operation.nrel5mw import nrel5mw_baseline_settings

DT = 0.01           # the built-in NREL 5 MW controller sample time [s]
F32 = np.float32


@pytest.fixture(scope="module")
def compiler():
    if compiler_command() is None:
        pytest.skip("no C compiler (gcc/cc, $CC): export_discon cannot build a library here")


@pytest.fixture(scope="module")
def collective(compiler, tmp_path_factory):
    ctrl = BaselineController(nrel5mw_baseline_settings(DT))
    return ctrl, export_discon(ctrl, tmp_path_factory.mktemp("collective"))


@pytest.fixture(scope="module")
def decimated(compiler, tmp_path_factory):
    ctrl = BaselineController(nrel5mw_baseline_settings(4 * DT))
    return ctrl, export_discon(ctrl, tmp_path_factory.mktemp("decimated"))


def _f32(y):
    return np.asarray(y, dtype=F32).astype(float)


def _library_run(out, t, y, names, commands, dt, **options):
    res = np.empty((t.size, len(commands)))
    with DisconController(out["library"], out["input"], dt=dt, **options) as lib:
        for k in range(t.size):
            u = lib.step(float(t[k]), dict(zip(names, y[k])))
            res[k] = [u[c] for c in commands]
    return res


def test_exported_file_set_and_self_containment(collective):
    ctrl, out = collective
    assert set(out) == {"library", "input", "controller", "sample_time_s"}
    assert out["controller"] == "baseline" and out["sample_time_s"] == DT and out["library"].endswith(".so")
    text = open(out["input"]).read()
    assert re.search(r"^0\.01\s+SampleTime", text, re.M) and re.search(r"^baseline\s+Controller", text, re.M)
    if shutil.which("ldd") is None or shutil.which("nm") is None:
        pytest.skip("ldd/nm not available to inspect the library")
    needed = subprocess.run(["ldd", out["library"]], capture_output=True, text=True, check=True).stdout
    libs = {line.split()[0] for line in needed.splitlines() if line.strip()}
    # only the C runtime, libm and the loader: no Python, numpy or CasADi at run time
    assert all(re.match(r"(linux-vdso|libc\.so|libm\.so|/lib.*ld-linux|ld-linux)", n) for n in libs), libs
    defined = subprocess.run(["nm", "-D", "--defined-only", out["library"]], capture_output=True, text=True,
                             check=True).stdout.split()
    assert [s for s in defined if not re.fullmatch(r"[0-9a-fA-F]+|[A-Za-z]", s)] == ["DISCON"]


def test_open_loop_commands_are_the_law_rounded_to_float32(collective):
    # 160 s sweep through regions 2, 2.5 and 3 and back (16001 calls); measurements made float32 numbers
    ctrl, out = collective
    t, y = synthetic_sweep(DT, t_end=160.0)
    y = _f32(y)
    law, _ = ctrl.run(y, compiled=True)
    lib = _library_run(out, t, y, ctrl.measurements, ("BlPitchCom1", "GenTqCom"), DT)
    assert np.array_equal(lib, _f32(law))                     # bit for bit, after float32 rounding
    dp, dq = np.abs(np.rad2deg(lib[:, 0] - law[:, 0])), np.abs(lib[:, 1] - law[:, 1])
    assert dp.max() < 1e-6 and np.all(dq <= 2.0**-24 * np.abs(law[:, 1]))
    assert np.ptp(np.rad2deg(law[:, 0])) > 4.0 and law[:, 1].max() > 4.3e4    # pitch and torque both move


def test_decimation_runs_the_law_every_fourth_call_and_holds(decimated):
    # library sample time 0.04 s, called every 0.01 s: the law runs at t = 0, 0.04, ... on the
    # measurements of those calls; the three calls in between return the held commands
    ctrl, out = decimated
    t, y = synthetic_sweep(DT, t_end=60.0)
    y = _f32(y)
    law, _ = ctrl.run(y[::4], compiled=True)
    expected = np.repeat(_f32(law), 4, axis=0)[:t.size]
    lib = _library_run(out, t, y, ctrl.measurements, ("BlPitchCom1", "GenTqCom"), DT)
    assert np.array_equal(lib, expected)
    assert np.count_nonzero(np.diff(lib[:, 1])) > 0.2 * t.size / 4     # the torque moves at the samples


def test_individual_pitch_control_exports_and_matches(compiler, tmp_path):
    # IPC_ControlMode 2 (1P and 2P) with the gains of test_baseline_ipc.py (ROSCO's NREL 2.8 MW example's 1P
    # integral gain, half for 2P, small proportional gains); root moments and azimuth from ipc_sweep
    text = need(DECK / "DISCON.IN").read_text()
    for key, value in {"IPC_ControlMode": "2", "IPC_KP": "1e-9 5e-10", "IPC_KI": "5.2e-9 2.6e-9"}.items():
        text, n = re.subn(rf"^[^!\n]*?(\s+! {key}\b)", rf"{value}\1", text, count=1, flags=re.MULTILINE)
        assert n == 1, key
    (tmp_path / "DISCON.IN").write_text(text)
    shutil.copy(DECK / "Cp_Ct_Cq.NREL5MW.txt", tmp_path)
    dt = 0.0125
    ctrl = BaselineController.from_discon(tmp_path / "DISCON.IN", dt=dt)
    out = export_discon(tmp_path / "DISCON.IN", tmp_path / "ipc", sample_time=dt)
    t, y = ipc_sweep(dt, t_end=40.0)
    y = _f32(y)
    law, _ = ctrl.run(y, compiled=True)
    lib = _library_run(out, t, y, ctrl.measurements, ctrl.commands, dt, individual_pitch=True)
    assert np.array_equal(lib, _f32(law))
    spread = np.rad2deg(lib[:, :3].max(axis=1) - lib[:, :3].min(axis=1))
    assert spread.max() > 0.2                                   # the blades are pitched individually
    with pytest.raises(ControllerError, match=r"record 28 = ServoDyn Ptch_Cntrl"):
        _library_run(out, t[:2], y[:2], ctrl.measurements, ctrl.commands, dt, individual_pitch=False)


def test_notches_tower_damper_and_power_rating_export_and_match(compiler, tmp_path):
    # Generator-speed notch filters, the tower damper (records 53, 54, 37 read) and PRC_Mode 2 ratings at once
    # (the settings of test_baseline_modes.py): the exported library is the law on float32 signals, bit for bit.
    from _ctrl_data import discon_variant
    from test_baseline_modes import NOTCH, PRC_RATINGS, TOWER_DAMPER, _sweep_with_tower_top

    dt = 0.0125
    discon = discon_variant(tmp_path, {**NOTCH, **TOWER_DAMPER, **PRC_RATINGS})
    ctrl = BaselineController.from_discon(discon, dt=dt)
    assert ctrl.measurements[5:] == ("YawBrTAxp", "YawBrTAyp", "NacYaw")
    out = export_discon(discon, tmp_path / "modes", sample_time=dt)
    t, y = _sweep_with_tower_top(dt, 40.0)
    y = _f32(y)
    law, _ = ctrl.run(y, compiled=True)
    lib = _library_run(out, t, y, ctrl.measurements, ("BlPitchCom1", "GenTqCom"), dt)
    assert np.array_equal(lib, _f32(law))
    (tmp_path / "plain").mkdir()
    plain = BaselineController.from_discon(discon_variant(tmp_path / "plain", {}), dt=dt)
    plain = plain.run(y[:, :5], compiled=True)[0]
    assert np.max(np.abs(np.rad2deg(plain[:, 0] - law[:, 0]))) > 0.01           # the modes act


def test_shutdown_and_startup_export_and_match(compiler, tmp_path):
    # The start-up (SU_Mode 1) and a timed shut-down (SD_Mode 1 at 38 s) at once, on the start-up measurements of
    # test_baseline_shutdown.py: the library counts ROSCO's time from its first call as the law does, bit for bit.
    from _ctrl_data import discon_variant
    from test_baseline_shutdown import CASES, STARTUP, _measurements

    dt = 0.0125
    discon = discon_variant(tmp_path, {**STARTUP, **CASES["sd-time"], "SD_Time": 38.004})
    ctrl = BaselineController.from_discon(discon, dt=dt)
    out = export_discon(discon, tmp_path / "stages", sample_time=dt)
    t, y = _measurements("startup", dt)
    y = _f32(y)
    law, _ = ctrl.run(y, compiled=True)
    lib = _library_run(out, t, y, ctrl.measurements, ("BlPitchCom1", "GenTqCom"), dt)
    assert np.array_equal(lib, _f32(law))
    (tmp_path / "plain").mkdir()
    plain = BaselineController.from_discon(discon_variant(tmp_path / "plain", {}), dt=dt).run(y, compiled=True)[0]
    assert np.max(np.abs(np.rad2deg(plain[:, 0] - law[:, 0]))) > 0.01           # the modes act


# ---------------------------------------------------------------------------------------------- bad input
class _Raw:
    """The library called through ctypes directly (a private copy), to send what DisconController refuses."""

    def __init__(self, out, tmp_path):
        copy = tmp_path / "raw_copy.so"
        shutil.copy(out["library"], copy)
        self.lib = ctypes.CDLL(str(copy))
        self.swap = np.zeros(3300, dtype=np.float32)
        self.fail = ctypes.c_int(0)
        self.msg = ctypes.create_string_buffer(1025)
        self.out = ctypes.create_string_buffer(64)
        self.swap[[2, 48, 60, 27]] = DT, 1025, 3, 1            # records 3, 49, 61, 28

    def call(self, status, t, infile, y=(122.9, 1.267, 0.1, 5e6, 14.0), **records):
        name = str(infile).encode()
        self.swap[[0, 1, 49]] = status, t, len(name) + 1
        self.swap[[19, 20, 3, 14, 26]] = y
        for record, value in records.items():
            self.swap[int(record[1:]) - 1] = value
        self.fail.value = 0
        self.lib.DISCON(self.swap.ctypes.data_as(ctypes.POINTER(ctypes.c_float)), ctypes.byref(self.fail),
                        ctypes.c_char_p(name), self.out, self.msg)
        return self.fail.value, self.msg.value.decode()


def test_bad_input_is_reported_not_crashed(collective, decimated, tmp_path):
    ctrl, out = collective
    raw = _Raw(out, tmp_path)
    assert raw.call(1, 0.0, out["input"])[0] == -1                       # a step before the first call
    assert "before the first call" in raw.msg.value.decode()
    fail, msg = raw.call(0, 0.0, tmp_path / "missing.IN")
    assert fail == -1 and "cannot open the input file" in msg and "missing.IN" in msg
    fail, msg = raw.call(0, 0.0, decimated[1]["input"])                 # another export's input file
    assert fail == -1 and "SampleTime is '0.04' s" in msg
    edited = tmp_path / "edited.IN"
    text = open(out["input"]).read()
    edited.write_text(text.replace("Fingerprint", "Fingerprnt"))                   # nothing given is ignored
    fail, msg = raw.call(0, 0.0, edited)
    assert fail == -1 and "unknown key 'Fingerprnt'" in msg and "every setting of the law is compiled in" in msg
    edited.write_text("".join(line for line in text.splitlines(True) if "Fingerprint" not in line))
    fail, msg = raw.call(0, 0.0, edited)
    assert fail == -1 and "missing key(s) Fingerprint" in msg
    edited.write_text(text + "baseline Controller\n")
    fail, msg = raw.call(0, 0.0, edited)
    assert fail == -1 and "key Controller is given twice" in msg
    assert raw.call(0, 0.0, out["input"], r3=0.003)[1].find("not a multiple of the communication interval") > 0
    assert "record 10" in raw.call(0, 0.0, out["input"], r3=DT, r10=1.0)[1]
    fail, msg = raw.call(0, 0.0, out["input"], r10=0.0, y=(np.nan, 1.267, 0.1, 5e6, 14.0))
    assert fail == -1 and "record 20 (GenSpeed) is not finite" in msg
    assert raw.call(0, 0.0, out["input"])[0] == 0                                        # a good first call
    assert raw.swap[46] > 0 and raw.swap[54] == 0 and raw.swap[64] == 0                  # torque; 55, 65
    assert raw.swap[41] == raw.swap[42] == raw.swap[43] == raw.swap[44] > 0              # 42-45 collective
    assert raw.swap[34] == 1 and raw.swap[35] == 0                                       # 35 on, 36 no brake
    fail, msg = raw.call(-8, 0.01, out["input"])
    assert fail == -1 and "checkpoints (-8, -9) are not" in msg
    assert raw.call(0, 0.0, out["input"])[0] == 0 and raw.call(1, 0.01, out["input"], r3=0.005)[0] == -1
    assert "changed from 0.01 s" in raw.msg.value.decode()
    raw.swap[48] = 8                                                     # record 49: an 8-byte message buffer
    raw.msg.value = b""
    raw.call(7, 0.0, out["input"])
    assert len(raw.msg.value) == 7


def test_export_refuses_bad_arguments(compiler, tmp_path):
    with pytest.raises(TypeError, match="NMPC is not yet available"):
        export_discon(object(), tmp_path)
    with pytest.raises(ControllerError, match="needs sample_time"):
        export_discon(need(DECK / "DISCON.IN"), tmp_path)
    with pytest.raises(ControllerError, match="differs from the controller's"):
        export_discon(BaselineController(nrel5mw_baseline_settings(DT)), tmp_path, sample_time=0.02)


# ---------------------------------------------------------------------------------------------- CLI contract
def _cli(argv, capsys):
    from mbsym.cli import main

    code = main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_cli_contract_builtin_turbine(compiler, tmp_path, capsys):
    code, out, err = _cli(["export-discon", "--controller", "baseline", "--out", str(tmp_path / "x")], capsys)
    assert code == 0, err
    result = json.loads(out.strip().splitlines()[-1])
    assert result["controller"] == "baseline" and result["sample_time_s"] == DT      # as mbsym simulate's built-in
    assert tmp_path.joinpath("x", "baseline_discon.so").samefile(result["library"])
    assert open(result["input"]).read() == open(export_discon(
        BaselineController(nrel5mw_baseline_settings(DT)), tmp_path / "y")["input"]).read()   # same law
    code, out, err = _cli(["export-discon", "--controller", "baseline", "--estimator", "ekf", "--out",
                           str(tmp_path / "z")], capsys)
    assert code == 2 and "--estimator ekf belongs to --controller nmpc" in err


def test_cli_deck_configures_as_simulate_does(compiler, tmp_path, capsys):
    from mbsym.wind.operation.deck import operating_deck

    fst = need(DECK.parent / "steady_14" / "steady_14.fst")
    code, out, err = _cli(["export-discon", str(fst), "--controller", "baseline", "--out", str(tmp_path)], capsys)
    assert code == 0, err
    result = json.loads(out.strip().splitlines()[-1])
    deck = operating_deck(fst)
    ctrl = BaselineController(deck.baseline_settings())      # what mbsym simulate DECK --controller baseline runs
    assert result["sample_time_s"] == ctrl.dt == deck.controller_dt
    t, y = synthetic_sweep(ctrl.dt, t_end=5.0)
    y = _f32(y)
    law, _ = ctrl.run(y)
    lib = _library_run(result, t, y, ctrl.measurements, ("BlPitchCom1", "GenTqCom"), ctrl.dt)
    assert np.max(np.abs(lib - law) / np.maximum(np.abs(law), 1e-3)) < 2.0**-23    # float32 rounding only


def test_deck_naming_an_exported_library_still_reads_its_settings(compiler, tmp_path, capsys):
    # The docs' recipe: the two exported paths put into the deck's ServoDyn. mbsym must still read that deck (the
    # library's input file holds no settings: the DISCON.IN it was built from is recorded in it), with the same
    # baseline settings; an input file that records none is refused with the fix named.
    from mbsym.wind.operation.deck import operating_deck

    need(DECK.parent / "steady_14" / "steady_14.fst")
    for name in ("deck", "steady_14"):
        shutil.copytree(DECK.parent / name, tmp_path / name)
        for p in (tmp_path / name).iterdir():
            p.chmod(0o644)
    fst = tmp_path / "steady_14" / "steady_14.fst"
    code, out, err = _cli(["export-discon", str(fst), "--controller", "baseline", "--out", str(tmp_path / "lib")],
                          capsys)
    assert code == 0, err
    result = json.loads(out.strip().splitlines()[-1])
    before = operating_deck(fst).baseline_settings()
    servodyn = tmp_path / "deck" / "NRELOffshrBsline5MW_Onshore_ServoDyn.dat"
    text = servodyn.read_text()
    for key, value in (("DLL_FileName", result["library"]), ("DLL_InFile", result["input"])):
        text, n = re.subn(rf"^\s*\S+(\s+{key}\b)", lambda m, v=value: f'"{v}"{m.group(1)}', text, count=1, flags=re.M)
        assert n == 1
    servodyn.write_text(text)
    deck = operating_deck(fst)
    assert deck.exported_input and deck.settings_in == (tmp_path / "deck" / "DISCON.IN").resolve()
    after = deck.baseline_settings()
    assert (after.dt, after.rated_power, after.gearbox_ratio) == (before.dt, before.rated_power, before.gearbox_ratio)
    infile = result["input"]
    lines = [line for line in open(infile).read().splitlines() if not line.startswith("! controller settings from")]
    open(infile, "w").write("\n".join(lines) + "\n")
    with pytest.raises(ControllerError, match="--discon-input"):
        operating_deck(fst).baseline_settings()


# ---------------------------------------------------------------------------------------------- closed loop
def _loops(ctrl, out, tmax):
    """The NREL 5 MW rotor-effective plant (GenDOF, TwFADOF1) in a 10 -> 14 m/s step at 5 s, RK4 at 0.01 s,
    closed by: the compiled in-loop baseline; the law on float32 signals (a Python DiscreteController that
    rounds measurements and commands as the swap array does); the exported library (called every 0.01 s)."""
    from mbsym.codegen import compile_function
    from mbsym.simulate import DiscreteController
    from mbsym.wind import OperatingTurbine
    from mbsym.wind.inflow import StepWind
    from mbsym.wind.operation.controllers import ACTUATED, MEASUREMENTS, TO_SI, baseline_in_loop, discon_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine
    from mbsym.wind.operation.steady import steady_guess

    model = OperatingTurbine.nrel5mw(dofs=["GenDOF", "TwFADOF1"])
    x0, wind = steady_guess(model, 10.0).state, StepWind(10.0, 14.0, 5.0)
    t = np.round(np.arange(0.0, tmax + 1e-9, 0.05), 12)
    f, scale = compile_function(ctrl.function).function, np.asarray(TO_SI)

    def law(_t, xc, y):
        xn, u = f(xc, _f32(y * scale))
        return np.asarray(xn).ravel(), _f32(np.asarray(u).ravel())

    def run(controller):
        return simulate_turbine(model, wind, tmax, x0=x0, t_out=t, controller=controller, method="rk4", dt=DT)

    in_loop = run(baseline_in_loop(ctrl))
    emulated = run(DiscreteController(law, ctrl.dt, ctrl.x0, measurements=MEASUREMENTS, actuates=ACTUATED))
    with DisconController(out["library"], out["input"], dt=DT) as lib:
        library = run(discon_in_loop(lib))
    return in_loop, emulated, library


@pytest.mark.parametrize("which", ["same-sample-time", "decimated-4x"])
def test_closed_loop_in_mbsyms_discon_loop(collective, decimated, which):
    # 1. The library in mbsym's DISCON loop is the law on float32 signals, also in feedback: bit for bit at the
    #    same sample time; decimated, the two loops step the plant with differently accumulated times (one
    #    controller sample of 4 RK4 steps vs 4 samples of one), observed 1.2e-13 deg apart: tolerance 1e-9.
    # 2. Against the compiled in-loop baseline (double precision throughout) the difference is that float32
    #    rounding fed back: the commands' rounding (<= 4.3e-7 deg for pitch < 0.25 rad) moves the plant, whose
    #    float32-rounded measurements move the next commands. Observed over the 13 deg pitch transient:
    #    9.8e-7 deg (0.01 s) and 2.4e-6 deg (0.04 s: the slower loop amplifies more); generator torque 2.7e-6
    #    and 3.1e-6 kN m, rotor speed 1.1e-7 and 2.4e-7 rpm. Tolerances: 1e-6 deg (issue 21's requirement) at
    #    the same sample time, 3e-6 deg decimated; torque 1e-5 kN m (0.01 N m), rotor speed 1e-6 rpm.
    ctrl, out = collective if which == "same-sample-time" else decimated
    in_loop, emulated, library = _loops(ctrl, out, 20.0)
    for ch in ("BldPitch1", "GenTq", "RotSpeed", "TTDspFA"):
        gap = np.max(np.abs(library.output(ch) - emulated.output(ch)))
        assert gap == 0.0 if which == "same-sample-time" else gap < 1e-9, (ch, gap)
    pitch, ref = library.output("BldPitch1"), in_loop.output("BldPitch1")
    assert np.max(np.abs(pitch - ref)) < (1e-6 if which == "same-sample-time" else 3e-6)
    assert np.max(np.abs(library.output("GenTq") - in_loop.output("GenTq"))) < 1e-5
    assert np.max(np.abs(library.output("RotSpeed") - in_loop.output("RotSpeed"))) < 1e-6
    assert np.ptp(ref) > 10.0                                        # the step pitches the blades by > 10 deg


@pytest.mark.slow
def test_ipc_closed_loop_on_the_blade_element_turbine(compiler, tmp_path):
    # The shared ss14_shear_flex deck (14 m/s, shear 0.2: a 1P flap moment on every blade), GenDOF, per-blade
    # pitch, IPC 1P + 2P (gains of test_baseline_ipc.py), 20 s: the exported library in mbsym's DISCON loop
    # (records 30-32, 60 in; 42-44 out) against the compiled in-loop baseline. Tolerance: 1e-6 deg per blade as
    # for the collective loop (the same float32 rounding fed back; observed 8.3e-7 deg); the IPC must act
    # (blades > 0.1 deg apart; observed 2.17 deg). ~50 s: the blade-element plant.
    import mbsym as mb
    from mbsym.wind.operation.controllers import baseline_in_loop, discon_in_loop
    from mbsym.wind.operation.deck import operating_deck
    from mbsym.wind.operation.simulation import simulate_turbine, wind_at_start

    fst = need(DECK.parent / "ss14_shear_flex" / "ss14_shear_flex.fst")
    text = need(DECK / "DISCON.IN").read_text()
    for key, value in {"IPC_ControlMode": "2", "IPC_SatMode": "0", "IPC_KP": "1e-9 5e-10",
                       "IPC_KI": "5.2e-9 2.6e-9"}.items():
        text, n = re.subn(rf"^[^!\n]*?(\s+! {key}\b)", rf"{value}\1", text, count=1, flags=re.MULTILINE)
        assert n == 1, key
    (tmp_path / "DISCON.IN").write_text(text)
    shutil.copy(DECK / "Cp_Ct_Cq.NREL5MW.txt", tmp_path)
    ctrl = BaselineController.from_discon(tmp_path / "DISCON.IN", dt=0.0125)
    out = export_discon(ctrl, tmp_path / "lib")
    model = mb.wind.OperatingTurbine.from_openfast(fst, aero="blade", dofs=["GenDOF"], pitch="individual")
    field = operating_deck(fst).inflow.field()
    x0 = model.initial_state(wind_at_start(model, field), pitch=np.deg2rad(8.6))
    t = np.round(np.arange(0.0, 20.0 + 1e-9, 0.05), 10)
    # the library is called from Python at every sample with the aerodynamics evaluated there and held, by RK4:
    # the compiled loop the same way (its defaults evaluate them every few samples, extrapolated in between, and
    # integrate with the deck's ElastoDyn Method, ABM4 here: 0.0105 deg apart, which an xfail here once blamed on
    # an unknown cause)
    ours = simulate_turbine(model, field, 20.0, x0=x0, t_out=t, controller=baseline_in_loop(ctrl, model=model),
                            aero_dt=0.0125, aero_order=0, method="rk4-held")
    with DisconController(out["library"], out["input"], dt=0.0125, individual_pitch=True) as lib:
        theirs = simulate_turbine(model, field, 20.0, x0=x0, t_out=t, controller=discon_in_loop(lib, model=model))
    pitch = [f"BldPitch{k}" for k in (1, 2, 3)]
    a = np.column_stack([ours.output(n) for n in pitch])
    b = np.column_stack([theirs.output(n) for n in pitch])
    assert np.max(np.abs(a - b)) < 1e-6, np.max(np.abs(a - b))
    assert (np.max(b, axis=1) - np.min(b, axis=1))[t > 10].max() > 0.1
