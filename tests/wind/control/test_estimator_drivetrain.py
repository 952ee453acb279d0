"""The turbine EKF on plants that ring: drivetrain torsion in its model, its start from the measured hub wind.

References, each independent of the code under test:
- the drivetrain's torsional mode carries no angular momentum (an eigenvector of the estimation model's own
  Jacobian): the rigid speed ``GeAz_d + w DrTr_d`` with ``w = I_r / (I_r + I_g)`` from ElastoDyn's mass summary
  must vanish in it;
- OpenFAST v5's own record of the NREL 5 MW with flexible blades and drivetrain on full-field turbulence
  (``../shared/openfast/aero/ff14_flex``, ROSCO in the loop): the EKF's wind against AeroDyn's disk-averaged wind
  ``RtVAvgxh``;
- :func:`steady_estimate` (the plant's steady guess) for the start table, and the EKF step itself for the start.
"""

from __future__ import annotations

import csv
import dataclasses
import functools
import math
from pathlib import Path

import numpy as np
import pytest
from _mpc_setup import turbine

SHARED = Path(__file__).resolve().parents[3].parent / "shared" / "openfast" / "aero"
FLEX_DOFS = ("GenDOF", "TwFADOF1", "TwSSDOF1", "DrTrDOF")


@functools.lru_cache(maxsize=None)
def _flex_builtin():
    from mbsym.wind.mpc import estimation_model
    from mbsym.wind.operation.deck import builtin_deck

    plant = builtin_deck().model(dofs=FLEX_DOFS)
    return plant, estimation_model(plant)


def test_estimator_models_the_drivetrain_where_the_plant_has_it():
    from mbsym.wind.mpc import ESTIMATOR_DOFS
    from mbsym.wind.mpc.estimator import rigid_speed_weight

    plant, observed = _flex_builtin()
    assert "DrTrDOF" in ESTIMATOR_DOFS
    assert {"DrTr", "DrTr_d"} <= set(observed.estimation_states)
    assert rigid_speed_weight(turbine().prediction) == 0.0             # a rigid drivetrain: nothing to weigh


def test_rigid_speed_carries_no_torsion():
    # The torsional mode (the fastest of the estimation model, 2.2 Hz on the NREL 5 MW) moves generator and rotor
    # against each other with zero angular momentum: GeAz_d + w DrTr_d = 0 in its eigenvector. The tower's
    # side-side mode couples to it through the nacelle's roll; tolerance 2 % of DrTr_d (observed 0.3 %).
    from mbsym.wind.mpc.estimator import rigid_speed_weight, steady_estimate

    plant, observed = _flex_builtin()
    w = rigid_speed_weight(observed)
    assert 0.85 < w < 0.92                        # NREL/TP-500-38060: 38.76e6 / (38.76e6 + 534.116 * 97^2) = 0.885
    dyn = observed.estimation
    z = steady_estimate(observed, 14.0)
    u = np.array([14.0, math.radians(8.6), 43.09e3])
    n = len(dyn.states)
    J = np.zeros((n, n))
    for j in range(n):
        h = 1e-6 * max(1.0, abs(z[j]))
        a, b = z[:n].copy(), z[:n].copy()
        a[j] += h
        b[j] -= h
        J[:, j] = (np.asarray(dyn.rhs_value(a, u)) - np.asarray(dyn.rhs_value(b, u))) / (2 * h)
    lam, vec = np.linalg.eig(J)
    k = int(np.argmax(np.abs(lam.imag)))
    assert 1.5 < abs(lam[k].imag) / (2 * math.pi) < 3.5, lam[k]
    v = vec[:, k]
    i_g, i_d = dyn.states.index("GeAz_d"), dyn.states.index("DrTr_d")
    assert abs(v[i_g] + w * v[i_d]) < 0.02 * abs(v[i_d]), (v[i_g], v[i_d], w)
    assert abs(v[i_g] + 1.0 * v[i_d]) > 0.05 * abs(v[i_d])           # the rotor speed alone does ring


def test_control_state_gives_the_rigid_speed():
    from mbsym.wind.mpc import PredictionModel, TurbineEstimator

    plant, observed = _flex_builtin()
    est = TurbineEstimator(observed, "ekf", compile=False)
    z = dict(zip(est.names, est.x))
    z.update(GeAz_d=1.2, DrTr_d=0.1)
    est.x = np.array([z[n] for n in est.names])
    nmpc_states = PredictionModel(plant).states
    x = dict(zip(nmpc_states, est.control_state(0.1, 4e4, nmpc_states)))
    assert x["GeAz_d"] == pytest.approx(1.2 + est.rigid_speed_weight * 0.1, rel=1e-12)
    assert x["BlPitch"] == 0.1 and x["GenTq"] == 4e4
    full = dict(zip(observed.estimation_states, est.control_state(0.1, 4e4, observed.estimation_states)))
    assert full["GeAz_d"] == 1.2                                          # a model with the drivetrain: as estimated


def _read(case: str) -> dict[str, np.ndarray]:
    with open(SHARED / f"{case}.csv", newline="") as f:
        rows = list(csv.reader(f))
    data = np.array(rows[1:], dtype=float)
    return {name.split("_[")[0]: data[:, j] for j, name in enumerate(rows[0])}


def _ekf_on_record(dofs, col, seconds: float) -> np.ndarray:
    """The EKF of the deck's rotor-effective model with ``dofs`` on the record's 20 Hz measurements."""
    from mbsym.wind.mpc import TurbineEstimator, estimation_model
    from mbsym.wind.mpc.estimator import steady_estimate
    from mbsym.wind.operation.deck import operating_deck

    deck = operating_deck(str(SHARED / "openfast_inputs" / "ff14_flex" / "ff14_flex.fst"))
    model = dataclasses.replace(deck, inflow=None).model(dofs=list(dofs), aero="rotor")
    observed = estimation_model(model, dofs)
    est = TurbineEstimator(observed, "ekf", x0=steady_estimate(observed, float(col["Wind1VelX"][0]),
                                                                settings=deck.baseline_settings()))
    winds = []
    for k in range(1, int(round(seconds / 0.05)) + 1):        # the record is at 0.05 s: the EKF's own sample time
        pitch = math.radians(0.5 * (col["BldPitch1"][k] + col["BldPitch1"][k - 1]))
        torque = 500.0 * (col["GenTq"][k] + col["GenTq"][k - 1])
        winds.append(est.step(col["GenSpeed"][k], col["YawBrTAxp"][k], pitch, torque)[-1])
    return np.array(winds)


@pytest.mark.skipif(not (SHARED / "ff14_flex.csv").is_file(), reason="needs ../shared/openfast/aero (ff14_flex)")
def test_ekf_follows_openfasts_flexible_turbine_in_turbulence():
    # OpenFAST's ff14_flex record (660 s, 14 m/s full field, flexible blades and drivetrain, ROSCO): the EKF on its
    # generator speed, tower-top acceleration, pitch and torque, 0-200 s. With the drivetrain in its model the wind
    # estimate follows AeroDyn's disk-averaged wind (RMS error 0.53 m/s over 60-200 s, measured; the rigid-drivetrain
    # record ff14_rigid gives 0.49 m/s with the rigid model); without it the start's ±30 rpm drivetrain ringing is
    # taken for wind and the estimate is lost for good (below 0 m/s within 0.2 s, measured).
    col = _read("ff14_flex")
    ref = col["RtVAvgxh"][1:4001]
    keep = col["Time"][1:4001] >= 60.0
    wind = _ekf_on_record(FLEX_DOFS, col, 200.0)
    err = wind[keep] - ref[keep]
    assert np.sqrt(np.mean(err ** 2)) < 0.8, np.sqrt(np.mean(err ** 2))
    assert np.corrcoef(wind[keep], ref[keep])[0, 1] > 0.8
    rigid = _ekf_on_record(FLEX_DOFS[:3], col, 20.0)
    assert np.min(rigid) < 5.0                                            # what the drivetrain state fixes


# ---------------------------------------------------------------------------------------------- start, restarts

@functools.lru_cache(maxsize=None)
def _functions(initial: str = "hub-wind"):
    from mbsym.wind.mpc import NMPCTuning, TurbineEstimator, TurbineNMPC, estimation_model
    from mbsym.wind.mpc.sample import sample_functions

    t = turbine()
    est = TurbineEstimator(estimation_model(t.plant), "ekf")
    nmpc = TurbineNMPC(t.prediction, t.setpoints, tuning=NMPCTuning.estimated_wind(), references=t.references,
                       deadline=math.inf)
    return sample_functions(nmpc, est, t.deck.controller_dt, initial=initial, settings=t.deck.baseline_settings()), est


def test_start_table_is_the_steady_estimate():
    from mbsym.wind.mpc.estimator import steady_estimate

    f, est = _functions("hub-wind")
    s = turbine().deck.baseline_settings()
    for u in (6.0, 11.0, 14.0):                                           # table nodes (every INIT_STEP = 1 m/s)
        np.testing.assert_allclose(np.asarray(f.init(u)).ravel(), steady_estimate(est.prediction, u, settings=s),
                                   rtol=1e-12, atol=1e-12)
    mid = np.asarray(f.init(14.5)).ravel()
    np.testing.assert_allclose(mid, 0.5 * (np.asarray(f.init(14.0)).ravel() + np.asarray(f.init(15.0)).ravel()),
                               rtol=1e-12, atol=1e-12)
    assert np.asarray(f.init(80.0)).ravel()[-1] == 30.0                   # clipped to the reference winds
    lo, hi = f.wind_range
    assert lo == 1.5 and hi == 45.0


def test_sampled_loop_starts_from_the_measured_hub_wind():
    from mbsym.exceptions import ControlDefinitionError
    from mbsym.wind.mpc.sample import SampledLoop

    f, _ = _functions("hub-wind")
    y, u = [1173.7, 0.01], [math.radians(8.6), 43.09e3]
    loop = SampledLoop(f)
    assert loop.step(0.0, *y, *u, hub_wind=15.2) is not None
    z, _ = f.ekf(f.init(15.2), f.P0, y, u, 0.0)
    np.testing.assert_allclose(loop.z, np.asarray(z).ravel(), rtol=1e-14, atol=1e-14)
    with pytest.raises(ControlDefinitionError, match="hub_wind"):
        SampledLoop(f).step(0.0, *y, *u)
    fixed = dataclasses.replace(f, initial="fixed")                      # the same Functions, the fixed prior
    z, _ = fixed.ekf(fixed.z0, fixed.P0, y, u, 0.0)
    loop = SampledLoop(fixed)
    loop.step(0.0, *y, *u, hub_wind=15.2)                                 # the hub wind is not read
    np.testing.assert_allclose(loop.z, np.asarray(z).ravel(), rtol=1e-14, atol=1e-14)


def test_implausible_estimate_restarts_the_estimator():
    # A generator speed of 3000 rpm at one estimator sample (a sensor fault) drives the wind estimate beyond
    # 1.5x the highest reference wind: the estimator restarts from the hub wind, the sample and those up to the
    # next NMPC sample return None (the library's baseline), and the NMPC starts again after that.
    from mbsym.wind.mpc.sample import SampledLoop

    f, _ = _functions("hub-wind")
    loop = SampledLoop(f)
    out = []
    for k in range(40):
        gen = 3000.0 if k == 15 else 1173.7
        out.append(loop.step(0.01 * k, gen, 0.0, math.radians(8.6), 43.09e3, hub_wind=14.0))
    assert loop.restarts == [pytest.approx(0.15)], loop.restarts
    assert all(o is not None for o in out[:15])
    assert all(o is None for o in out[15:20])                              # until the NMPC sample at k = 20
    assert all(o is not None for o in out[20:])
    assert np.all(np.isfinite(loop.z)) and f.wind_range[0] <= loop.z[-1] <= f.wind_range[1]
