"""The exported NMPC + EKF library (``mbsym export-discon --controller nmpc``): step time and a run inside OpenFAST.

``python benchmarks/nmpc_discon_export.py loop [--seconds 20] [--pitch-acceleration 2] [--estimator mhe] [--lidar-ocp]``:
the library (built-in NREL 5 MW, 0.01 s) closed on
mbsym's rotor-effective plant (GenDOF, TwFADOF1, TwSSDOF1, dynamic inflow) in mbsym's DISCON loop at 14 m/s
(Kaimal, seed 3), each call timed; then the Python loop (:class:`TurbineLoop`: RTI driven from Python with hpipm,
numpy EKF) on the same float32 measurements, its NMPC steps timed (``TurbineNMPC.step``, the EKF apart), in the
same process. Printed: the time per DISCON call at NMPC samples (EKF + RTI + baseline + wrapper, with the ctypes
call and the swap-array writes of ``DisconController.step``), at the other calls (the overhead floor), the Python
RTI step, and the largest command differences. With ``--pitch-acceleration A`` a second library with
``NMPCTuning.estimated_wind(pitch_acceleration_scale=A deg/s²)`` runs the same, and the ratio of the two libraries'
median calls at NMPC samples is printed; with ``--estimator mhe`` a second library with the MHE
(``--estimator mhe``) runs the same, and the ratios of its median calls to the EKF library's; with ``--lidar-ocp``
a second library whose OCP has the size of ``NMPCTuning.full_field_lidar``'s (0.05 s, 80 stages) runs the same.

``python benchmarks/nmpc_discon_export.py openfast [--case step_10_14] [--seconds 60] [--keep DIR]``: the deck of
``../shared/openfast/aero/openfast_inputs/<case>`` copied, ``mbsym export-discon <case>.fst --controller nmpc``,
the two paths put into its ServoDyn file, ``TMax`` set, OpenFAST run; printed: the library's messages, OpenFAST's
wall time, and rotor speed, pitch, torque, power and tower-base moment statistics beside the ROSCO reference run
of the same case over the same time.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent), str(HERE.parent / "tests" / "wind" / "control")]


def loop(seconds: float, pitch_acceleration: float | None = None, estimator: str = "ekf",
         lidar_ocp: bool = False) -> None:
    """The default library; with ``pitch_acceleration`` [deg/s²] then the library with that term, same run; with
    ``estimator="mhe"`` then the library with the MHE, same run, and the ratios of its calls to the EKF library's; with
    ``lidar_ocp`` then a library whose OCP has the size of :meth:`NMPCTuning.full_field_lidar`'s (0.05 s, 80 stages)."""
    base = _loop(seconds, None)
    if estimator == "mhe":
        print("\n-- with the MHE (window 20 intervals, one real-time iteration per 0.05 s) --")
        other = _loop(seconds, None, "mhe")
        print(f"ratio of the median calls (MHE / EKF library): NMPC samples {other[0] / base[0]:.2f}, estimator-only "
              f"samples {other[1] / base[1]:.2f}")
    if lidar_ocp:
        from mbsym.wind.mpc import NMPCTuning

        print("\n-- the OCP of NMPCTuning.full_field_lidar: 0.05 s, 80 stages --")
        other = _loop(seconds, NMPCTuning.estimated_wind(dt=0.05, horizon=80))
        print(f"ratio of the library's median call at NMPC samples (80 stages at 0.05 s / 40 at 0.1 s): "
              f"{other[0] / base[0]:.2f}")
    if pitch_acceleration is None:
        return
    import math

    from mbsym.wind.mpc import NMPCTuning

    tuning = NMPCTuning.estimated_wind(pitch_acceleration_scale=math.radians(pitch_acceleration))
    print(f"\n-- with a pitch-acceleration term, scale {pitch_acceleration:g} deg/s^2 --")
    other = _loop(seconds, tuning)
    print(f"ratio of the library's median call at NMPC samples (with / without the term): {other[0] / base[0]:.2f}")


def _with_estimator(kind: str, est):
    """``est`` (the test's EKF) or an MHE of the same model and prior (kind ``"mhe"``)."""
    from mbsym.wind.mpc import TurbineEstimator

    return est if kind == "ekf" else TurbineEstimator(est.prediction, kind, x0=est.x)


def _loop(seconds: float, tuning, kind: str = "ekf") -> tuple[float, float]:
    """One library run (module docstring); returns the median DISCON calls at NMPC samples and at the estimator's
    other samples [s]."""
    from _mpc_setup import turbine
    from test_nmpc_export import LOOP_SI, _controllers, _wind

    from mbsym.simulate.api import simulate
    from mbsym.simulate.controller import DiscreteController
    from mbsym.wind.control import BaselineController, DisconController
    from mbsym.wind.mpc import LOOP_CHANNELS, TurbineLoop, measurement_dynamics
    from mbsym.wind.mpc.discon_nmpc import export_nmpc_discon
    from mbsym.wind.mpc.sample import sample_functions
    from mbsym.wind.operation.controllers import ACTUATED, held_commands

    t = turbine()
    wind = _wind(seconds)
    est, nmpc, x0 = _controllers(wind, tuning=tuning)
    est = _with_estimator(kind, est)
    work = Path(tempfile.mkdtemp(prefix="mbsym_nmpc_lib_"))
    c0 = time.perf_counter()
    out = export_nmpc_discon(nmpc, est, BaselineController(t.deck.baseline_settings()), work, loop_dt=0.01)
    print(f"export {time.perf_counter() - c0:.1f} s: {out['library']}")
    rows, walls = [], []
    with DisconController(out["library"], out["input"], dt=0.01, individual_pitch=False) as lib:
        step = lib.callable(LOOP_CHANNELS, ("BlPitchCom1", "GenTqCom"))

        def law(tt, xc, y):
            y32 = np.asarray(y * np.asarray(LOOP_SI), dtype=np.float32).astype(float)
            c = time.perf_counter()
            u = step(tt, y32)
            walls.append(time.perf_counter() - c)
            rows.append((tt, y32, u))
            return xc, u

        ctrl = DiscreteController(law, 0.01, np.zeros(0), measurements=LOOP_CHANNELS, actuates=ACTUATED)
        simulate(measurement_dynamics(t.plant, LOOP_CHANNELS), seconds, x0=x0, controller=ctrl, method="rk4", dt=0.01,
                 inputs={"Wind1VelX": wind, **held_commands(t.plant, x0)}, compile=True)
        messages = list(lib.messages)
    # the Python EKF starts where the library's does: the steady estimate at the hub wind of its first step call
    start = sample_functions(nmpc, est, 0.01, settings=t.deck.baseline_settings()).init(rows[1][1][4])
    est, nmpc, _ = _controllers(wind, z0=np.asarray(start, dtype=float).ravel(), tuning=tuning)
    est = _with_estimator(kind, est)
    lp = TurbineLoop(t.plant, 0.01, nmpc=nmpc, estimator=est)
    xc = lp.controller().x0
    ref = []
    for tt, y32, _ in rows[1:]:          # the library answers its initialization call with the baseline
        xc, u = lp.law(tt - rows[1][0], xc, y32 / np.asarray(LOOP_SI))
        ref.append(u)
    ref, got, walls = np.array(ref), np.array([u for _, _, u in rows[1:]]), np.array(walls)
    k = np.arange(walls.size) - 1        # schedule index: 0 at the first step call
    per = int(round(nmpc.dt / 0.01))     # loop calls per NMPC sample (the EKF: every 5)
    at_nmpc, other = walls[(k % per == 0) & (k > 0)], walls[(k % 5 != 0) & (k > 0)]
    at_est = walls[(k % 5 == 0) & (k % per != 0) & (k > 0)]
    py = np.array(lp.controller_times[1:])
    ms = 1e3
    print(f"{seconds:g} s closed loop, {walls.size} DISCON calls, library messages: {messages or 'none'}")
    print(f"DISCON call at NMPC samples ({kind.upper()} + RTI + baseline): median {np.median(at_nmpc) * ms:.3f} ms, "
          f"max {np.max(at_nmpc) * ms:.3f} ms; first step call (start-up, 10 iterations) {walls[1] * ms:.3f} ms")
    if at_est.size:                      # none when the NMPC samples as often as the estimator
        print(f"DISCON call at the estimator's other samples (baseline + {kind.upper()}): median "
              f"{np.median(at_est) * ms:.3f} ms, max {np.max(at_est) * ms:.3f} ms")
    print(f"DISCON call at other samples (baseline): median {np.median(other) * ms:.3f} ms, "
          f"max {np.max(other) * ms:.3f} ms")
    print(f"Python TurbineNMPC.step (RTI, hpipm, compiled preparation): median {np.median(py) * ms:.3f} ms, "
          f"max {np.max(py) * ms:.3f} ms; ratio of medians (library call / Python step) "
          f"{np.median(at_nmpc) / np.median(py):.2f}")
    pe = np.array(est.walls[1:])
    print(f"Python TurbineEstimator.step ({kind.upper()}): median {np.median(pe) * ms:.3f} ms, max {np.max(pe) * ms:.3f} ms")
    print(f"max |Δ pitch| {np.max(np.abs(got[:, 0] - ref[:, 0])):.3g} rad, max |Δ torque|/torque "
          f"{np.max(np.abs(got[:, 1] - ref[:, 1]) / np.abs(ref[:, 1])):.3g}")
    shutil.rmtree(work, ignore_errors=True)
    return float(np.median(at_nmpc)), float(np.median(at_est)) if at_est.size else float("nan")


def openfast(case: str, seconds: float, keep: str | None) -> None:
    from discon_export_openfast import _read_csv, _read_out, _set_value, _shared

    shared = _shared()
    aero = shared / "openfast" / "aero"
    exe = shared / "tools" / "openfast" / "openfast"
    if not exe.is_file():
        sys.exit(f"needs {exe}")
    work = Path(keep) if keep else Path(tempfile.mkdtemp(prefix="mbsym_nmpc_of_"))
    work.mkdir(parents=True, exist_ok=True)
    for name in ("deck", case):
        if not (work / "openfast_inputs" / name).exists():
            shutil.copytree(aero / "openfast_inputs" / name, work / "openfast_inputs" / name)
    if not (work / "wind").exists():
        (work / "wind").symlink_to(aero / "wind")
    fst = work / "openfast_inputs" / case / f"{case}.fst"
    c0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "mbsym", "export-discon", str(fst), "--controller", "nmpc",
                           "--out", str(work / "lib")], capture_output=True, text=True, cwd=HERE.parent)
    if proc.returncode != 0:
        sys.exit(f"mbsym export-discon failed: {proc.stderr.strip()}")
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    print(f"export {time.perf_counter() - c0:.1f} s: {out}")
    servodyn = work / "openfast_inputs" / "deck" / "NRELOffshrBsline5MW_Onshore_ServoDyn.dat"
    _set_value(servodyn, "DLL_FileName", f'"{out["library"]}"')
    _set_value(servodyn, "DLL_InFile", f'"{out["input"]}"')
    _set_value(fst, "OutFileFmt", "1")
    _set_value(fst, "TMax", f"{seconds:g}")
    c0 = time.perf_counter()
    run = subprocess.run([str(exe), fst.name], capture_output=True, text=True, cwd=fst.parent)
    wall = time.perf_counter() - c0
    notes = [line for line in run.stdout.splitlines() if "mbsym DISCON" in line or "DISCON" in line][:10]
    if run.returncode != 0 or "terminated normally" not in run.stdout:
        sys.exit(f"OpenFAST failed (exit {run.returncode}) after {wall:.0f} s:\n{run.stdout[-3000:]}\n"
                 f"{run.stderr[-2000:]}")
    ours = _read_out(fst.with_suffix(".out"))
    print(f"OpenFAST {wall:.1f} s wall for {seconds:g} s; library messages in its log: {notes or 'none'}")
    ref_path = aero / f"{case}.csv"
    ref = _read_csv(ref_path) if ref_path.is_file() else None
    print(f"{'channel':<10} {'NMPC mean':>12} {'NMPC std':>10} {'NMPC min':>10} {'NMPC max':>10} | "
          f"{'ROSCO mean':>12} {'ROSCO std':>10}")
    for ch in ("RotSpeed", "BldPitch1", "GenTq", "GenPwr", "TwrBsMyt", "Wind1VelX"):
        if ch not in ours:
            continue
        keep_t = ours["Time"] >= 10.0
        a = ours[ch][keep_t]
        line = f"{ch:<10} {a.mean():12.4g} {a.std():10.4g} {a.min():10.4g} {a.max():10.4g} |"
        if ref is not None and ch in ref:
            r = ref[ch][(ref["Time"] >= 10.0) & (ref["Time"] <= seconds)]
            line += f" {r.mean():12.4g} {r.std():10.4g}"
        print(line)
    if not keep:
        shutil.rmtree(work, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="what", required=True)
    p = sub.add_parser("loop")
    p.add_argument("--seconds", type=float, default=20.0)
    p.add_argument("--pitch-acceleration", type=float, metavar="DEG_S2",
                   help="then the library with NMPCTuning(pitch_acceleration_scale) in the same run, and the ratio")
    p.add_argument("--estimator", choices=("ekf", "mhe"), default="ekf",
                   help="mhe: then the library with the MHE in the same run, and the ratios")
    p.add_argument("--lidar-ocp", action="store_true",
                   help="then a library with the OCP size of NMPCTuning.full_field_lidar (0.05 s, 80 stages)")
    p = sub.add_parser("openfast")
    p.add_argument("--case", default="step_10_14")
    p.add_argument("--seconds", type=float, default=60.0)
    p.add_argument("--keep", metavar="DIR")
    args = parser.parse_args()
    if args.what == "loop":
        loop(args.seconds, args.pitch_acceleration, args.estimator, args.lidar_ocp)
    else:
        openfast(args.case, args.seconds, args.keep)


if __name__ == "__main__":
    main()
