"""Turbine state and rotor-effective wind estimators (EKF, MHE) on the prediction model's estimation form.

Reference: the truth of the simulation itself — the plant (GenDOF, TwFADOF1, TwSSDOF1, dynamic inflow)
held at its steady state in a constant wind, its noise-free measurements (generator speed, tower-top
acceleration, pitch, torque) fed to the estimator started from a wrong wind (11 instead of 14 m/s) and
a deflected tower. The estimation model has no side-side mode; that mode carries no fore-aft
information, so the constant wind and the tower's static deflection must be recovered exactly up to the
plant's steady-state residual.
"""

from __future__ import annotations

import numpy as np
import pytest

from _mpc_setup import turbine


def _steady_run(wind: float, tmax: float):
    from mbsym.wind.operation.simulation import simulate_turbine
    from mbsym.wind.operation.steady import steady_guess

    t = turbine()
    x0 = steady_guess(t.plant, wind).state
    dt = 0.05
    res = simulate_turbine(t.plant, wind, tmax, x0=x0, t_out=np.arange(0.0, tmax + 1e-9, dt))
    return res, dt


@pytest.mark.parametrize("kind", ["ekf", "mhe"])
def test_estimator_recovers_a_constant_wind_from_noise_free_measurements(kind):
    from mbsym.wind.mpc.estimator import EstimatorTuning, TurbineEstimator

    t = turbine()
    res, dt = _steady_run(14.0, 30.0)
    dyn = t.plant.dynamics()
    truth = dict(zip(dyn.states, np.asarray(res.x)[-1]))
    est_states = t.prediction.estimation_states
    z0 = {s: truth[s] for s in est_states}
    z0.update(Wind1VelX=11.0, TFA1=truth["TFA1"] + 0.1)          # wrong wind, deflected tower
    est = TurbineEstimator(t.prediction, kind, tuning=EstimatorTuning(dt=dt, window=10), x0=[*z0.values()],
                           compile=False)
    pitch, torque = np.radians(res.output("BldPitch1")), res.output("GenTq") * 1e3
    for k in range(len(res.t)):
        z = est.step(res.output("GenSpeed")[k], res.output("YawBrTAxp")[k], pitch[k], torque[k])
    got = dict(zip(est.names, z))
    assert got["Wind1VelX"] == pytest.approx(14.0, abs=0.02)                 # m/s
    assert got["TFA1"] == pytest.approx(truth["TFA1"], abs=1e-3)               # m
    assert got["GeAz_d"] == pytest.approx(truth["GeAz_d"], rel=1e-4)           # rad/s
    assert est.summary()["failures"] == 0


def test_estimator_options_are_checked():
    from mbsym.exceptions import ControlDefinitionError
    from mbsym.wind.mpc.estimator import EstimatorTuning, TurbineEstimator

    t = turbine()
    with pytest.raises(ControlDefinitionError, match="ekf"):
        TurbineEstimator(t.prediction, "ukf")
    with pytest.raises(ControlDefinitionError, match="window"):
        EstimatorTuning(window=0)
    with pytest.raises(ControlDefinitionError, match="wind_walk"):
        EstimatorTuning(wind_walk=float("nan"))
    with pytest.raises(TypeError, match="EstimatorTuning"):
        TurbineEstimator(t.prediction, "ekf", tuning={"dt": 0.05})
