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
* ``NMPC preview``: the NMPC (``mbsym.wind.control.TurbineNMPC``, RTI, 0.1 s, N = 40) with the
  plant's true state and an ideal 5 s preview of the hub wind (a perfect lidar);
* ``NMPC + MHE`` / ``NMPC + EKF``: the same NMPC with the state and the rotor-effective wind estimated
  at 20 Hz from generator speed, tower-top acceleration, pitch and torque; no preview.

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
        from mbsym.wind.mpc.prediction import PredictionModel
        from mbsym.wind.mpc.setpoints import SetPoints, reference_table
        from mbsym.wind.operation.deck import builtin_deck

        self.deck = builtin_deck()
        self.plant = self.deck.model()
        self.plant.dynamics()
        self.prediction = PredictionModel(self.plant)
        self.setpoints = SetPoints.from_settings(self.deck.baseline_settings(), self.plant.rotor)
        self.references = reference_table(self.prediction, self.setpoints)

    def x0(self, wind) -> np.ndarray:
        from mbsym.wind.operation.steady import steady_guess

        return steady_guess(self.plant, float(wind(0.0))).state


def rosco_files() -> tuple[Path, Path] | None:
    """ROSCO's library and its NREL 5 MW DISCON.IN with logging off (copied next to its Cp table)."""
    sys.path.insert(0, str(HERE.parent / "tests" / "wind" / "control"))
    import _rosco

    lib = _rosco.rosco_library()
    src = _rosco.rosco_nrel5mw_discon()
    if lib is None or src is None:
        return None
    folder = Path(tempfile.gettempdir()) / "mbsym_rosco_nrel5mw"
    folder.mkdir(exist_ok=True)
    text = src.read_text().splitlines()
    text = [("0" + line[1:] if "LoggingLevel" in line and line.lstrip().startswith("1") else line) for line in text]
    (folder / "DISCON.IN").write_text("\n".join(text) + "\n")
    cp = src.with_name("Cp_Ct_Cq.NREL5MW.txt")
    if not (folder / cp.name).exists():
        (folder / cp.name).write_text(cp.read_text())
    return lib, folder / "DISCON.IN"


# ------------------------------------------------------------------ runs
def run(setup: Setup, kind: str, wind, tmax: float, *, tuning=None, preview: float | None = 5.0,
        estimator: str | None = None, est_tuning=None, t_out=None):
    """One closed-loop run: ``kind`` in {"rosco", "baseline", "nmpc"}. Returns (result, wall seconds)."""
    from mbsym.wind.control import BaselineController, DisconController
    from mbsym.wind.operation.controllers import baseline_in_loop, discon_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine

    t_out = np.round(np.arange(0.0, tmax + 1e-9, 0.05), 10) if t_out is None else t_out
    x0 = setup.x0(wind)
    t0 = time.perf_counter()
    if kind == "baseline":
        ctrl = baseline_in_loop(BaselineController(setup.deck.baseline_settings()))
        res = simulate_turbine(setup.plant, wind, tmax, controller=ctrl, x0=x0, t_out=t_out, compile=True)
        return res, time.perf_counter() - t0
    if kind == "rosco":
        lib, infile = rosco_files()
        with DisconController(lib, infile, dt=setup.deck.controller_dt) as handle:
            timed = _timed_law(discon_in_loop(handle))
            res = simulate_turbine(setup.plant, wind, tmax, controller=timed, x0=x0, t_out=t_out, compile=True)
        res.statistics.update(controller_step_median_s=float(np.median(timed.walls)),
                              controller_step_max_s=float(np.max(timed.walls)))
        return res, time.perf_counter() - t0
    from mbsym.wind.mpc.estimator import TurbineEstimator
    from mbsym.wind.mpc.loop import TurbineLoop
    from mbsym.wind.mpc.simulation import simulate_with_loop
    from mbsym.wind.mpc.nmpc import TurbineNMPC

    mpc = TurbineNMPC(setup.prediction, setup.setpoints, tuning=tuning, references=setup.references)
    est = None
    if estimator is not None:
        z0 = _initial_estimate(setup, x0, float(wind(0.0)))
        est = TurbineEstimator(setup.prediction, estimator, tuning=est_tuning, x0=z0)
    loop = TurbineLoop(setup.plant, setup.deck.controller_dt, nmpc=mpc, estimator=est,
                       preview=preview if estimator is None or preview is not None else None, wind=wind)
    res = simulate_with_loop(setup.plant, wind, tmax, loop, x0=x0, t_out=t_out, compile=True)
    return res, time.perf_counter() - t0


def _initial_estimate(setup: Setup, x0, wind0: float) -> np.ndarray:
    dyn = setup.plant.dynamics()
    names = setup.prediction.estimation_states
    return np.concatenate([[x0[dyn.states.index(s)] for s in names], [wind0]])


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
    from mbsym.sweep.stats import damage_equivalent_load

    t = np.asarray(res.t)
    keep = t >= SPIN_UP
    dur = float(t[keep][-1] - t[keep][0])
    dyn = setup.plant.dynamics()
    X = np.asarray(res.x)
    speed = res.output("GenSpeed")[keep]
    wind = res.output("Wind1VelX")[keep]
    if mean_wind > 11.4:
        ref = np.full_like(speed, RPM_RATED)
    else:
        ref = setup.references("GenSpeed", wind)
    rate = np.degrees(X[keep, dyn.states.index("BlPitch_d")])
    pitch = res.output("BldPitch1")[keep]
    power = res.output("GenPwr")[keep]
    out = {"speed_rms_rpm": float(np.sqrt(np.mean((speed - ref) ** 2))),
           "speed_max_rpm": float(speed.max()),
           "power_mean_kw": float(power.mean()), "power_std_kw": float(power.std()),
           "pitch_travel_deg": float(np.sum(np.abs(np.diff(pitch)))),
           "pitch_rate_rms_degs": float(np.sqrt(np.mean(rate ** 2))),
           "del_twrbsmyt_knm": damage_equivalent_load(res.output("TwrBsMyt")[keep], dur, 4.0),
           "ttdspfa_std_m": float(res.output("TTDspFA")[keep].std())}
    st = res.statistics
    for k in ("controller_step_median_s", "controller_step_max_s", "controller_first_step_s", "controller_failures",
              "estimator_step_median_s", "estimator_step_max_s", "estimator_failures"):
        if k in st:
            out[k] = st[k]
    if "Wind1VelX_est" in res.output_names:
        out.update(estimator_errors(res, keep))
    return out


def estimator_errors(res, keep) -> dict:
    out = {}
    for c, key in (("Wind1VelX", "wind"), ("RtVAvgxh", "rtvavg"), ("TTDspFA", "ttdspfa"), ("RotSpeed", "rotspeed")):
        a, b = res.output(c)[keep], res.output(c + "_est")[keep]
        out[f"est_{key}_rms"] = float(np.sqrt(np.mean((a - b) ** 2)))
        out[f"est_{key}_corr"] = float(np.corrcoef(a, b)[0, 1])
        out[f"est_{key}_std"] = float(a.std())
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tmax", type=float, default=600.0)
    ap.add_argument("--speeds", type=float, nargs="+", default=list(SPEEDS))
    ap.add_argument("--seeds", type=int, nargs="+", default=list(SEEDS))
    ap.add_argument("--kinds", nargs="+", default=["rosco", "baseline", "nmpc-preview", "nmpc-mhe", "nmpc-ekf"])
    ap.add_argument("--json", help="write the raw results here")
    ap.add_argument("--no-readme", action="store_true")
    args = ap.parse_args(argv)
    from mbsym.wind.inflow import kaimal_wind

    setup = Setup()
    results = []
    for u in args.speeds:
        for seed in args.seeds:
            wind = kaimal_wind(u, turbulence_intensity(u), seed, duration=args.tmax)
            for kind in args.kinds:
                base, _, est = kind.partition("-")
                opts = {}
                if base == "nmpc":
                    opts = {"preview": 5.0} if est == "preview" else {"preview": None, "estimator": est}
                res, wall = run(setup, base, wind, args.tmax, **opts)
                m = metrics(setup, res, u)
                m.update(kind=kind, wind=u, seed=seed, wall_s=wall, load=os.getloadavg()[0])
                results.append(m)
                print(json.dumps(m), flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
