"""Closed-loop benchmark of the turbine NMPC and estimators (issue 13, points 4 and 7).

Plant: the built-in NREL 5 MW operating turbine (GenDOF, TwFADOF1, TwSSDOF1, rotor aerodynamics
with dynamic inflow, pitch and torque actuators; ``mbsym.wind.operation``), one RK4 step per
controller sample of 0.01 s. Winds: Kaimal turbulence (``mbsym.wind.inflow.kaimal_wind``) of
600 s at 8, 14 and 18 m/s mean with the IEC 61400-1 class B normal turbulence intensity
(``I_ref = 0.14``: 20.3, 16.1, 14.9 %), seeds 11, 12, 13. Every controller runs on the same winds
from the same initial state (the steady guess at the first wind sample); statistics leave out the
first 30 s.

Controllers:

* ``ROSCO``: the real ROSCO 2.10.6 library (``libdiscon.so`` from the PyPI wheel, fetched once by
  ``tests/wind/control/_rosco.py``), its NREL 5 MW ``DISCON.IN`` with logging off;
* ``baseline``: our ROSCO-scheme controller compiled into the loop (same settings);
* ``NMPC preview``: the NMPC (``mbsym.wind.mpc.TurbineNMPC``, RTI, 0.1 s, N = 40) with the
  plant's true state and an ideal 5 s preview of the hub wind (a perfect lidar);
* ``NMPC + MHE`` / ``NMPC + EKF``: the same NMPC (``NMPCTuning.estimated_wind()``) with the state and
  the rotor-effective wind estimated at 20 Hz from generator speed, tower-top acceleration, pitch and
  torque (``estimation_model``: the prediction model with the first side-side tower mode); no preview;
* ``baseline + MHE``: our baseline in the Python loop, the MHE beside it (estimates reported only);
* ``ROSCO, no peak shaving``: the ROSCO library with ``PS_Mode 0`` (the energy reference of an NMPC
  that has no thrust limit).

Metrics: generator-speed RMS error (against the rated speed at 14 and 18 m/s; at 8 m/s against
the speed schedule of the measured wind... see README), electrical power mean and standard
deviation, pitch travel and pitch-rate RMS (the plant's actuator speed), tower-base fore-aft DEL
(``TwrBsMyt``, rainflow, Wöhler exponent 4, 1 Hz equivalent cycles; ``mbsym.sweep``), controller
and estimator step times (median, max; first NMPC step reported separately) and estimator errors.

Run: ``python benchmarks/control.py [--tmax 600] [--speeds 8 14 18] [--seeds 11 12 13] [--quick]
[--no-readme]``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

SPIN_UP = 30.0          # s left out of the statistics
I_REF = 0.14            # IEC class B
SEEDS = (11, 12, 13)
SPEEDS = (8.0, 14.0, 18.0)
RPM_RATED = 122.90967 * 30 / math.pi


def turbulence_intensity(mean: float) -> float:
    """IEC 61400-1 ed. 3 normal turbulence model: σ = I_ref (0.75 U + 5.6)."""
    return I_REF * (0.75 * mean + 5.6) / mean


# ------------------------------------------------------------------ set-up
class Setup:
    """The plant, the prediction model, set-points and reference table (built once)."""

    def __init__(self) -> None:
        from mbsym.wind.mpc.estimator import estimation_model
        from mbsym.wind.mpc.prediction import PredictionModel
        from mbsym.wind.mpc.setpoints import SetPoints, reference_table
        from mbsym.wind.operation.deck import builtin_deck

        self.deck = builtin_deck()
        self.plant = self.deck.model()
        self.plant.dynamics()
        self.prediction = PredictionModel(self.plant)
        self.observed = estimation_model(self.plant)          # the estimator's model (+ TwSSDOF1)
        self.setpoints = SetPoints.from_settings(self.deck.baseline_settings(), self.plant.rotor)
        self.references = reference_table(self.prediction, self.setpoints)

    def x0(self, wind) -> np.ndarray:
        from mbsym.wind.operation.steady import steady_guess

        return steady_guess(self.plant, float(wind(0.0))).state


def rosco_files(peak_shaving: bool = True) -> tuple[Path, Path] | None:
    """ROSCO's library and its NREL 5 MW DISCON.IN with logging off (copied next to its Cp table);
    ``peak_shaving=False`` also sets ``PS_Mode 0`` (no minimum-pitch schedule near rated)."""
    sys.path.insert(0, str(HERE.parent / "tests" / "wind" / "control"))
    import _rosco

    lib = _rosco.rosco_library()
    src = _rosco.rosco_nrel5mw_discon()
    if lib is None or src is None:
        return None
    folder = Path(tempfile.gettempdir()) / ("mbsym_rosco_nrel5mw" if peak_shaving else "mbsym_rosco_nrel5mw_ps0")
    folder.mkdir(exist_ok=True)
    text = src.read_text().splitlines()
    text = [("0" + line[1:] if "LoggingLevel" in line and line.lstrip().startswith("1") else line) for line in text]
    if not peak_shaving:
        text = [("0" + line.lstrip()[1:] if "! PS_Mode" in line else line) for line in text]
    (folder / "DISCON.IN").write_text("\n".join(text) + "\n")
    cp = src.with_name("Cp_Ct_Cq.NREL5MW.txt")
    if not (folder / cp.name).exists():
        (folder / cp.name).write_text(cp.read_text())
    return lib, folder / "DISCON.IN"


# ------------------------------------------------------------------ runs
ESTIMATOR_NOISE = dict(gen_speed=0.5, accel=0.02, pitch=0.05, torque=100.0)     # SensorNoise (rpm, m/s², deg, N m)


def run(setup: Setup, kind: str, wind, tmax: float, *, tuning=None, preview: float | None = None,
        estimator: str | None = None, seed: int = 0, prediction=None, noise: bool = True, t_out=None,
        est_tuning=None, est_model=None, peak_shaving: bool = True):
    """One closed-loop run. ``kind``: "rosco", "baseline" (compiled loop), "nmpc", "baseline+est" (our
    baseline in the Python loop beside an estimator). Returns the result (statistics include the loop's)."""
    from mbsym.wind.control import BaselineController, DisconController
    from mbsym.wind.operation.controllers import baseline_in_loop, discon_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine

    t_out = np.round(np.arange(0.0, tmax + 1e-9, 0.05), 10) if t_out is None else t_out
    x0 = setup.x0(wind)
    if kind == "baseline":
        ctrl = baseline_in_loop(BaselineController(setup.deck.baseline_settings()))
        return simulate_turbine(setup.plant, wind, tmax, controller=ctrl, x0=x0, t_out=t_out, compile=True)
    if kind == "rosco":
        lib, infile = rosco_files(peak_shaving)
        with DisconController(lib, infile, dt=setup.deck.controller_dt) as handle:
            timed = _timed_law(discon_in_loop(handle))
            res = simulate_turbine(setup.plant, wind, tmax, controller=timed, x0=x0, t_out=t_out, compile=True)
        res.statistics.update(controller_step_median_s=float(np.median(timed.walls[1:])),
                              controller_step_max_s=float(np.max(timed.walls[1:])), controller_failures=0)
        return res
    from mbsym.wind.mpc import SensorNoise, TurbineEstimator, TurbineLoop, TurbineNMPC, simulate_with_loop

    prediction = setup.prediction if prediction is None else prediction
    est = None
    if estimator is not None:
        observed = setup.observed if est_model is None else est_model
        est = TurbineEstimator(observed, estimator, tuning=est_tuning,
                               x0=_initial_estimate(setup, x0, float(wind(0.0)), observed))
    nmpc = baseline = None
    if kind == "nmpc":
        refs = setup.references if prediction is setup.prediction else None
        nmpc = TurbineNMPC(prediction, setup.setpoints, tuning=tuning, references=refs)
    else:
        baseline = BaselineController(setup.deck.baseline_settings())
    sensor = SensorNoise(**ESTIMATOR_NOISE, seed=seed) if est is not None and noise else None
    loop = TurbineLoop(setup.plant, setup.deck.controller_dt, nmpc=nmpc, baseline=baseline, estimator=est,
                       preview=preview, wind=wind, noise=sensor)
    return simulate_with_loop(setup.plant, wind, tmax, loop, x0=x0, t_out=t_out, compile=True)


def _initial_estimate(setup: Setup, x0, wind0: float, prediction) -> np.ndarray:
    """The estimator's prior: the plant's initial state (the steady guess of the first wind) and that wind."""
    dyn = setup.plant.dynamics()
    return np.concatenate([[x0[dyn.states.index(s)] for s in prediction.estimation_states], [wind0]])


def _timed_law(ctrl):
    """The DISCON controller with its per-sample wall time recorded."""
    from mbsym.simulate.controller import DiscreteController

    law = ctrl.law
    walls: list[float] = []

    def timed(t, xc, y):
        t0 = time.perf_counter()
        out = law(t, xc, y)
        walls.append(time.perf_counter() - t0)
        return out

    new = DiscreteController(timed, ctrl.dt, measurements=ctrl.measurements, actuates=ctrl.actuates, name=ctrl.name)
    new.walls = walls
    return new


# ------------------------------------------------------------------ metrics
def metrics(setup: Setup, res, mean_wind: float) -> dict:
    """Closed-loop metrics after the spin-up (see the module docstring)."""
    from mbsym.sweep.stats import damage_equivalent_load

    t = np.asarray(res.t)
    keep = t >= SPIN_UP
    dur = float(t[keep][-1] - t[keep][0])
    dyn = setup.plant.dynamics()
    X = np.asarray(res.x)
    speed = res.output("GenSpeed")[keep]
    wind = res.output("Wind1VelX")[keep]
    ref = np.full_like(speed, RPM_RATED) if mean_wind > 11.4 else setup.references("GenSpeed", wind)
    rate = np.degrees(X[keep, dyn.states.index("BlPitch_d")])
    pitch = np.degrees(X[keep, dyn.states.index("BlPitch")])
    power = res.output("GenPwr")[keep]
    out = {"speed_rms_rpm": float(np.sqrt(np.mean((speed - ref) ** 2))), "speed_max_rpm": float(speed.max()),
           "power_mean_kw": float(power.mean()), "power_std_kw": float(power.std()),
           "pitch_travel_deg": float(np.sum(np.abs(np.diff(pitch)))),
           "pitch_rate_rms_degs": float(np.sqrt(np.mean(rate ** 2))),
           "del_twrbsmyt_knm": damage_equivalent_load(res.output("TwrBsMyt")[keep], dur, 4.0),
           "ttdspfa_std_m": float(res.output("TTDspFA")[keep].std())}
    st = res.statistics
    for k in ("controller_step_median_s", "controller_step_max_s", "controller_first_step_s", "controller_failures",
              "controller_build_s", "estimator_step_median_s", "estimator_step_max_s", "estimator_failures",
              "integration_wall_s"):
        if k in st:
            out[k] = st[k]
    if "Wind1VelX_est" in res.output_names:
        out.update(estimator_errors(res, keep))
    return out


def estimator_errors(res, keep) -> dict:
    """RMS error, correlation and the truth's standard deviation of the estimated channels."""
    out = {}
    for c, key in (("Wind1VelX", "wind"), ("RtVAvgxh", "rtvavg"), ("TTDspFA", "ttdspfa"), ("RotSpeed", "rotspeed")):
        a, b = res.output(c)[keep], res.output(c + "_est")[keep]
        out[f"est_{key}_rms"] = float(np.sqrt(np.mean((a - b) ** 2)))
        out[f"est_{key}_corr"] = float(np.corrcoef(a, b)[0, 1])
        out[f"est_{key}_std"] = float(a.std())
    return out


# ------------------------------------------------------------------ stages
KINDS = {                       # label -> run() options
    "ROSCO": dict(kind="rosco"),
    "ROSCO, no peak shaving": dict(kind="rosco", peak_shaving=False),
    "baseline": dict(kind="baseline"),
    "NMPC preview": dict(kind="nmpc", preview=5.0),
    "NMPC + MHE": dict(kind="nmpc", estimator="mhe"),
    "NMPC + EKF": dict(kind="nmpc", estimator="ekf"),
    "baseline + MHE": dict(kind="baseline+est", estimator="mhe"),
}


def _tuning(opts: dict):
    from mbsym.wind.mpc import NMPCTuning

    if opts.get("kind") != "nmpc":
        return None
    return NMPCTuning() if opts.get("preview") is not None else NMPCTuning.estimated_wind()


class Store:
    """Results as JSON lines (resumable): one record per (stage, label, wind, seed, variant)."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.rows = [json.loads(line) for line in path.read_text().splitlines()] if path.exists() else []

    def done(self, key: dict) -> dict | None:
        return next((r for r in self.rows if all(r.get(k) == v for k, v in key.items())), None)

    def add(self, row: dict) -> None:
        self.rows.append(row)
        with self.path.open("a") as fh:
            fh.write(json.dumps(row) + "\n")
        print(json.dumps({k: (round(v, 4) if isinstance(v, float) else v) for k, v in row.items()}), flush=True)


def closed_loop_stage(setup, store, speeds, seeds, tmax, labels) -> None:
    from mbsym.wind.inflow import kaimal_wind

    for u in speeds:
        for seed in seeds:
            wind = kaimal_wind(u, turbulence_intensity(u), seed, duration=tmax)
            for label in labels:
                key = {"stage": "closed_loop", "label": label, "wind": u, "seed": seed, "tmax": tmax}
                if store.done(key):
                    continue
                opts = dict(KINDS[label])
                t0 = time.perf_counter()
                res = run(setup, wind=wind, tmax=tmax, tuning=_tuning(opts), seed=seed, **opts)
                row = {**key, **metrics(setup, res, u), "wall_s": time.perf_counter() - t0,
                       "load": os.getloadavg()[0]}
                store.add(row)


TRADEOFF = {"NMPC preview": [1.0, 1.5, 2.5, 4.0, 8.0], "NMPC + MHE": [0.4, 0.5, 0.57, 0.7, 0.9]}


def tradeoff_stage(setup, store, seeds, tmax, wind_speed: float = 14.0) -> None:
    """NMPC tunings across the pitch-rate scale [deg/s] at 14 m/s."""
    from mbsym.wind.inflow import kaimal_wind
    from mbsym.wind.mpc import NMPCTuning

    for seed in seeds:
        wind = kaimal_wind(wind_speed, turbulence_intensity(wind_speed), seed, duration=tmax)
        for label, scales in TRADEOFF.items():
            for scale in scales:
                key = {"stage": "tradeoff", "label": label, "wind": wind_speed, "seed": seed, "tmax": tmax,
                       "pitch_rate_scale_degs": scale}
                if store.done(key):
                    continue
                opts = dict(KINDS[label])
                rate = math.radians(scale)
                tun = NMPCTuning(pitch_rate_scale=rate) if opts.get("preview") is not None \
                    else NMPCTuning.estimated_wind(pitch_rate_scale=rate)
                res = run(setup, wind=wind, tmax=tmax, tuning=tun, seed=seed, **opts)
                store.add({**key, **metrics(setup, res, wind_speed), "load": os.getloadavg()[0]})


LADDER_DOFS = (("GenDOF",), ("GenDOF", "DBEMT"), ("GenDOF", "TwFADOF1"), ("GenDOF", "TwFADOF1", "DBEMT"),
               ("GenDOF", "TwFADOF1", "TwSSDOF1", "DBEMT"))


def ladder_stage(setup, store, tmax: float, seed: int = 11, wind_speed: float = 14.0) -> None:
    """The prediction-model ladder: closed-loop ε (baseline in the loop) and the NMPC on each rung."""
    from mbsym.wind.analysis.prediction_ladder import prediction_ladder
    from mbsym.wind.inflow import kaimal_wind
    from mbsym.wind.mpc import NMPCTuning, PredictionModel

    wind = kaimal_wind(wind_speed, turbulence_intensity(wind_speed), seed, duration=tmax)
    key = {"stage": "ladder_eps", "wind": wind_speed, "seed": seed, "tmax": tmax}
    if not store.done(key):
        lad = prediction_ladder(setup.plant, wind, tmax, ladder=LADDER_DOFS)
        store.add({**key, "table": lad.table(), "smallest": lad.smallest().label,
                   "rungs": [{"label": r.label, "states": list(r.coordinates), "errors": dict(r.errors)}
                             for r in lad.rungs]})
        lad.plot(HERE / "figures" / "control_prediction_ladder.png",
                 title=f"prediction models in closed loop (baseline controller), Kaimal {wind_speed:g} m/s, "
                       f"{tmax:g} s")
    for rung in LADDER_DOFS:
        k = {"stage": "ladder_nmpc", "rung": list(rung), "wind": wind_speed, "seed": seed, "tmax": tmax}
        if store.done(k):
            continue
        dofs = tuple(f for f in rung if f != "DBEMT")
        pred = PredictionModel(setup.plant, dofs=dofs, dynamic_inflow="DBEMT" in rung)
        res = run(setup, "nmpc", wind, tmax, tuning=NMPCTuning(), preview=5.0, prediction=pred)
        store.add({**k, "states": len(pred.states), **metrics(setup, res, wind_speed), "load": os.getloadavg()[0]})


SIZES = {"6-state class (default: Gen + FA1 + DBEMT, 7 states)": ("GenDOF", "TwFADOF1"),
         "5 states (Gen + FA1, quasi-steady inflow)": ("GenDOF", "TwFADOF1", "-DBEMT"),
         "13 states (Gen + DrTr + FA1 + SS1 + FA2 + DBEMT)": ("GenDOF", "DrTrDOF", "TwFADOF1", "TwSSDOF1", "TwFADOF2"),
         "15 states (Gen + DrTr + FA1 + SS1 + FA2 + SS2 + DBEMT)": ("GenDOF", "DrTrDOF", "TwFADOF1", "TwSSDOF1",
                                                                   "TwFADOF2", "TwSSDOF2")}


def size_stage(setup, store, tmax: float = 120.0, seed: int = 11, wind_speed: float = 14.0) -> None:
    """Step and build times by model size (cold compilation cache), each against a plant with the same DOFs."""
    from mbsym.wind.inflow import kaimal_wind
    from mbsym.wind.mpc import (NMPCTuning, PredictionModel, TurbineLoop, TurbineNMPC, reference_table,
                                simulate_with_loop)
    from mbsym.wind.operation import OperatingTurbine

    wind = kaimal_wind(wind_speed, turbulence_intensity(wind_speed), seed, duration=tmax)
    for label, flags in SIZES.items():
        key = {"stage": "size", "label": label, "tmax": tmax}
        if store.done(key):
            continue
        dofs = [f for f in flags if not f.startswith("-")]
        inflow = "-DBEMT" not in flags
        plant = OperatingTurbine.nrel5mw(dofs=dofs)
        pred = PredictionModel(plant, dofs=dofs, dynamic_inflow=inflow)
        refs = reference_table(pred, setup.setpoints)
        with tempfile.TemporaryDirectory() as cache:
            old = os.environ.get("MBSYM_CACHE_DIR")
            os.environ["MBSYM_CACHE_DIR"] = cache
            try:
                t0 = time.perf_counter()
                nmpc = TurbineNMPC(pred, setup.setpoints, tuning=NMPCTuning(), references=refs)
                build = time.perf_counter() - t0
            finally:
                if old is None:
                    os.environ.pop("MBSYM_CACHE_DIR")
                else:
                    os.environ["MBSYM_CACHE_DIR"] = old
        from mbsym.wind.operation.steady import steady_guess

        loop = TurbineLoop(plant, 0.01, nmpc=nmpc, preview=5.0, wind=wind)
        c0 = time.process_time()
        simulate_with_loop(plant, wind, tmax, loop, x0=steady_guess(plant, float(wind(0.0))).state, compile=True)
        cpu = time.process_time() - c0
        st = nmpc.nmpc.stats[1:]
        walls = np.array([s.wall_s for s in st])
        store.add({**key, "states": len(pred.states), "rhs_instructions": pred.control.rhs.n_instructions(),
                   "build_s": build, "median_s": float(np.median(walls)), "max_s": float(walls.max()),
                   "p99_s": float(np.percentile(walls, 99)), "first_s": nmpc.nmpc.stats[0].wall_s,
                   "prep_median_s": float(np.median([s.preparation_s for s in st])),
                   "feedback_median_s": float(np.median([s.feedback_s for s in st])),
                   "qp_median_s": float(np.median([s.qp_solver_s for s in st])),
                   "failures": nmpc.nmpc.failures, "steps": len(st) + 1, "loop_cpu_s": cpu,
                   "load": os.getloadavg()[0]})


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tmax", type=float, default=600.0)
    ap.add_argument("--speeds", type=float, nargs="+", default=list(SPEEDS))
    ap.add_argument("--seeds", type=int, nargs="+", default=list(SEEDS))
    ap.add_argument("--labels", nargs="+", default=list(KINDS))
    ap.add_argument("--stages", nargs="+", default=["closed_loop", "tradeoff", "ladder", "size"])
    ap.add_argument("--results", default=str(HERE / "figures" / "control_results.jsonl"))
    ap.add_argument("--report-only", action="store_true", help="write the README section from the stored results")
    ap.add_argument("--no-readme", action="store_true")
    args = ap.parse_args(argv)
    store = Store(Path(args.results))
    if not args.report_only:
        setup = Setup()
        if "size" in args.stages:
            size_stage(setup, store)
        if "ladder" in args.stages:
            ladder_stage(setup, store, min(args.tmax, 300.0))
        if "closed_loop" in args.stages:
            closed_loop_stage(setup, store, args.speeds, args.seeds, args.tmax, args.labels)
        if "tradeoff" in args.stages:
            tradeoff_stage(setup, store, args.seeds[:1], args.tmax)
    from control_report import report

    text = report(store.rows, args.tmax)
    print(text)
    if not args.no_readme:
        from _report import write_section

        write_section("control-turbine", text)


if __name__ == "__main__":
    main()
