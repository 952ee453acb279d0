"""Exact recovery of known parameters from noise-free synthetic data.

References: the oscillator's closed-form free decay (independent of the integrator), and the
turbine's trajectory from CVODES at tight tolerances (a different integrator from the RK4 of the
fit). Tolerances: the discretization error of the fit's RK4 (frequency error (ωh/m)^4/120).
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb

from .conftest import exact_decay

TURBINE = ["tower_fa1_damping_ratio", "tower_fa1_stiffness_tuner", "tower_ss1_stiffness_tuner"]


def test_oscillator_from_its_closed_form(osc):
    """k, c from 25 % off; 4 RK4 sub-steps of 0.05 s: (ωh/4)^4/120 ~ 1e-9 relative frequency error."""
    t = np.arange(0.0, 12.0, 0.05)
    q = exact_decay(t, 5.0, 0.2)
    res = mb.identify(osc, {"time": t, "pos": q}, ["k", "c"], initial={"k": 3.75, "c": 0.15}, substeps=4,
                      compile=False)
    assert res.success, res.message
    assert res.parameters["k"] == pytest.approx(5.0, rel=1e-7)
    assert res.parameters["c"] == pytest.approx(0.2, rel=1e-6)
    assert res.eps["pos"] < 1e-7
    assert res.iterations < 15


def test_oscillator_initial_state_and_parameter_channel(osc):
    """Estimating x0 too; a channel that depends on a parameter (k q); a record that starts at t = 3 s."""
    t = np.arange(3.0, 15.0, 0.05)
    q = exact_decay(t, 5.0, 0.2)                     # state at t = 3 s is not the default x0
    wd, s = np.sqrt(5.0 - 0.01), 0.1
    v = np.exp(-s * t) * (-s * (np.cos(wd * t) + s / wd * np.sin(wd * t)) + (-wd * np.sin(wd * t) + s * np.cos(wd * t)))
    res = mb.identify(osc, {"time": t, "pos": q, "spring_force": 5.0 * q}, ["k", "c"], estimate_x0=True,
                      initial={"k": 4.5}, substeps=4, compile=False)
    assert res.parameters["k"] == pytest.approx(5.0, rel=1e-7)
    assert res.parameters["c"] == pytest.approx(0.2, rel=1e-6)
    assert res.initial_states[0]["q"] == pytest.approx(q[0], abs=1e-8)
    assert res.initial_states[0]["v"] == pytest.approx(v[0], abs=1e-7)


def _turbine_record(model, p, t_end=20.0, dt=0.05, x0=None):
    out = mb.simulate(model, t_end, x0=x0, p=p, method="cvodes", dt=dt, rtol=1e-11, atol=1e-12)
    names = ["Q_TFA1", "QD_TFA1", "Q_TSS1", "QD_TSS1"]
    return {"time": out.t, **{n: out.y[:, out.output_names.index(n)] for n in names}}


def test_turbine_tower_parameters_from_cvodes_data(tower_model):
    """Three tower parameters of the NREL 5 MW from 20 % off, two records (different initial states)."""
    dyn = mb.as_dynamics(tower_model)
    truth = {"tower_fa1_damping_ratio": 0.02, "tower_fa1_stiffness_tuner": 1.1, "tower_ss1_stiffness_tuner": 0.95}
    x0b = dyn.x0.copy()
    x0b[:2] = [-0.4, 0.8]
    data = [_turbine_record(tower_model, truth, t_end=12.0), _turbine_record(tower_model, truth, t_end=12.0, x0=x0b)]
    res = mb.identify(tower_model, data, TURBINE, x0=[dyn.x0, x0b], substeps=2, compile=False,
                      initial={k: 0.8 * v for k, v in truth.items()})
    assert res.success, res.message
    for k, v in truth.items():
        assert res.parameters[k] == pytest.approx(v, rel=2e-6), k
    assert max(res.eps.values()) < 1e-6


def test_turbine_keys_are_reported_in_deck_units(tower_model):
    """ElastoDyn keys through the model's resolve_parameter hook: TwrFADmp(1) in %, NacMass in kg."""
    truth = {"tower_fa1_damping_ratio": 0.015, "nacelle_mass": 2.6e5}
    data = _turbine_record(tower_model, truth, t_end=10.0)
    res = mb.identify(tower_model, data, ["TwrFADmp(1)", "NacMass"], substeps=2, compile=False,
                      initial={"TwrFADmp(1)": 1.2, "NacMass": 2.2e5})
    assert res.names == ("TwrFADmp(1)", "NacMass")
    assert res.units == {"TwrFADmp(1)": "%", "NacMass": "kg"}
    assert res.initial == {"TwrFADmp(1)": 1.2, "NacMass": 2.2e5}
    assert res.parameters["TwrFADmp(1)"] == pytest.approx(1.5, rel=2e-6)
    assert res.parameters["NacMass"] == pytest.approx(2.6e5, rel=2e-6)
