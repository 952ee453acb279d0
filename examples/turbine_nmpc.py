"""NMPC with an MHE of the state and the rotor-effective wind on the built-in NREL 5 MW, against our
ROSCO-scheme baseline, in the same turbulent wind (docs/turbine_nmpc.md).

Plant: the operating turbine (generator, first fore-aft and side-side tower modes, rotor
aerodynamics with dynamic inflow, pitch and torque actuators). NMPC: RTI, 0.1 s, 40 stages, on the
7-state prediction model (generator, first fore-aft tower mode, dynamic inflow, actuators as rates),
no preview. MHE: 20 Hz from generator speed (GenSpeed), tower-top acceleration, pitch and torque with sensor
noise. Wind: Kaimal, 14 m/s mean, IEC class B turbulence, 180 s (statistics after 30 s).

Run: ``python examples/turbine_nmpc.py`` (about a minute). The last line is JSON; its keys are
``<channel>_<statistic>_<unit>`` with OpenFAST's channel names and units (docs/units.md).
"""

from __future__ import annotations

import json
import time

import numpy as np

from mbsym.sweep.stats import damage_equivalent_load
from mbsym.wind.control import BaselineController
from mbsym.wind.inflow import kaimal_wind
from mbsym.wind.mpc import (NMPCTuning, PredictionModel, SensorNoise, SetPoints, TurbineEstimator, TurbineLoop,
                            TurbineNMPC, estimation_model, simulate_with_loop)
from mbsym.wind.operation.controllers import baseline_in_loop
from mbsym.wind.operation.deck import builtin_deck
from mbsym.wind.operation.simulation import simulate_turbine
from mbsym.wind.operation.steady import steady_guess

MEAN, TMAX, SPIN_UP = 14.0, 180.0, 30.0
SIGMA = 0.14 * (0.75 * MEAN + 5.6)                 # IEC 61400-1 normal turbulence, class B [m/s]

deck = builtin_deck()
plant = deck.model()
wind = kaimal_wind(MEAN, SIGMA / MEAN, 7, duration=TMAX)
x0 = steady_guess(plant, float(wind(0.0))).state
t_out = np.round(np.arange(0.0, TMAX + 1e-9, 0.05), 10)

t0 = time.perf_counter()
prediction = PredictionModel(plant)
observed = estimation_model(plant)
setpoints = SetPoints.from_settings(deck.baseline_settings(), plant.rotor)
nmpc = TurbineNMPC(prediction, setpoints, tuning=NMPCTuning.estimated_wind())
states = dict(zip(plant.dynamics().states, x0))
mhe = TurbineEstimator(observed, "mhe", x0=[states[s] for s in observed.estimation_states] + [float(wind(0.0))])
build_s = time.perf_counter() - t0
loop = TurbineLoop(plant, deck.controller_dt, nmpc=nmpc, estimator=mhe, noise=SensorNoise(seed=7))
res = simulate_with_loop(plant, wind, TMAX, loop, x0=x0, t_out=t_out, compile=True)
base = simulate_turbine(plant, wind, TMAX, controller=baseline_in_loop(BaselineController(deck.baseline_settings())),
                        x0=x0, t_out=t_out, compile=True)


def summary(r) -> dict:
    keep = np.asarray(r.t) >= SPIN_UP
    gen_speed = r.output("GenSpeed")[keep]                                     # [rpm]
    rated_rpm = setpoints.rated_generator_speed * 30 / np.pi                   # [rad/s] -> [rpm]
    return {"GenSpeed_rms_err_rpm": float(np.sqrt(np.mean((gen_speed - rated_rpm) ** 2))),
            "GenPwr_mean_kW": float(r.output("GenPwr")[keep].mean()),
            "BldPitch1_rate_rms_deg/s": float(np.sqrt(np.mean(np.gradient(r.output("BldPitch1")[keep], 0.05) ** 2))),
            "TwrBsMyt_DEL_MN-m": damage_equivalent_load(r.output("TwrBsMyt")[keep], TMAX - SPIN_UP, 4.0) / 1e3}


keep = np.asarray(res.t) >= SPIN_UP
wind_err = res.output("Wind1VelX_est")[keep] - res.output("Wind1VelX")[keep]          # [m/s]
out = {"nmpc_mhe": summary(res), "baseline": summary(base),
       "Wind1VelX_est_rms_err_m/s": float(np.sqrt(np.mean(wind_err ** 2))),
       "controller_step_median_s": res.statistics["controller_step_median_s"],
       "controller_step_max_s": res.statistics["controller_step_max_s"],
       "controller_failures": res.statistics["controller_failures"],
       "estimator_step_median_s": res.statistics["estimator_step_median_s"], "build_s": build_s}
for name in ("nmpc_mhe", "baseline"):
    s = out[name]
    print(f"{name:9s} GenSpeed RMS err {s['GenSpeed_rms_err_rpm']:6.1f} rpm, GenPwr {s['GenPwr_mean_kW']:6.0f} kW, "
          f"BldPitch1 rate RMS {s['BldPitch1_rate_rms_deg/s']:.2f} deg/s, TwrBsMyt DEL {s['TwrBsMyt_DEL_MN-m']:.1f} "
          "MN-m")
print(f"Wind1VelX_est RMS error {out['Wind1VelX_est_rms_err_m/s']:.3f} m/s; NMPC step median "
      f"{1e3 * out['controller_step_median_s']:.2f} ms, max {1e3 * out['controller_step_max_s']:.1f} ms; "
      f"MHE step median {1e3 * out['estimator_step_median_s']:.2f} ms")
print(json.dumps(out))
