"""DOF sets other than the default, steady-state guesses, and typed errors of the operating-turbine API.

References: a steady state is a zero of the right-hand side (every derivative but the azimuth's, which is
the rotor speed) — checked to 1e-8 of the state scale on the model's own rhs; with DrTrDOF the
low-speed-shaft torque is the drivetrain spring's and equals the aerodynamic torque at equilibrium;
with GenDOF off the rotor turns at the parameter ``rotor_speed``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from _op_data import AERO, need
from mbsym.exceptions import ControllerError, OpenFASTFormatError, ParameterError, SimulationOptionError
from mbsym.wind.operation import OperatingTurbine, simulate_turbine, steady_guess


def _steady_residual(model, wind):
    dyn = model.dynamics()
    g = steady_guess(model, wind)
    xd = dyn.rhs_value(g.state, [wind, g.pitch, g.torque])
    skip = [dyn.states.index("GeAz")]
    return g, np.delete(xd, skip)


def test_drivetrain_flexibility_steady_state_and_shaft_torque():
    model = OperatingTurbine.nrel5mw(dofs=["GenDOF", "DrTrDOF", "TwFADOF1"])
    g, residual = _steady_residual(model, 12.0)
    assert np.max(np.abs(residual)) < 1e-8
    dyn = model.dynamics()
    y = dict(zip(dyn.output_names, dyn.output_value(g.state, [12.0, g.pitch, g.torque])))
    assert y["RotTorq"] == pytest.approx(y["RtAeroMxh"] / 1e3, rel=1e-9)
    assert y["RotTorq"] == pytest.approx(97 * y["GenTq"], rel=1e-9)


def test_prescribed_rotor_speed_without_gendof():
    model = OperatingTurbine.nrel5mw(dofs=["TwFADOF1"])
    dyn = model.dynamics()
    assert "rotor_speed" in dyn.parameters and "GeAz" in dyn.states and not model.spins_freely
    omega = 12.1 * math.pi / 30
    x0 = model.initial_state(12.0, pitch=math.radians(4.0), p={"rotor_speed": omega})
    res = simulate_turbine(model, 12.0, 1.0, x0=x0, p={"rotor_speed": omega}, t_out=np.linspace(0, 1, 11))
    np.testing.assert_allclose(res.output("RotSpeed"), 12.1, rtol=1e-12)
    with pytest.raises(ParameterError, match="rotor_speed"):
        model.initial_state(12.0, rotor_speed=1.0)


def test_first_order_inflow_lag_option_starts_at_equilibrium():
    model = OperatingTurbine.nrel5mw(dynamic_inflow=False, inflow_lag=True)
    dyn = model.dynamics()
    assert dyn.states[-2:] == ("RotThrustLag", "RotTorqLag")
    g, residual = _steady_residual(model, 12.0)
    assert np.max(np.abs(residual)) < 1e-6 * max(abs(g.state[-2]), 1.0)
    y = dict(zip(dyn.output_names, dyn.output_value(g.state, [12.0, g.pitch, g.torque])))
    assert y["RtAeroFxh"] == pytest.approx(g.state[-2], rel=1e-12)     # the applied thrust is the lag state


def test_blade_dofs_warn_that_they_get_no_aerodynamic_load():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        OperatingTurbine.nrel5mw(dofs=["GenDOF", "FlapDOF1"])
    assert any("FlapDOF1" in str(w.message) and "no aerodynamic load" in str(w.message) for w in caught)


def test_steady_guess_of_the_default_model_is_steady(operating):
    for wind in (6.0, 11.4, 18.0):
        g, residual = _steady_residual(operating, wind)
        assert np.max(np.abs(residual)) < 1e-8, (wind, residual)
    assert g.rotor_speed == pytest.approx(12.1 * math.pi / 30, rel=1e-4)          # rated speed above rated


def test_typed_errors(operating, tmp_path):
    from mbsym.simulate import DiscreteController
    from mbsym.wind import nrel5mw
    from mbsym.wind.operation.deck import builtin_deck, operating_deck

    with pytest.raises(TypeError, match="TurbineParameters"):
        OperatingTurbine("nrel5mw.fst")
    with pytest.raises(TypeError, match="RotorAero"):
        OperatingTurbine(nrel5mw(), rotor="table.txt")
    with pytest.raises(ParameterError, match="one inflow model"):
        OperatingTurbine(nrel5mw(), dofs=["GenDOF"], dynamic_inflow=True, inflow_lag=True)
    with pytest.raises(ParameterError, match="saturation_width"):
        OperatingTurbine(nrel5mw(), dofs=["GenDOF"], saturation_width=0.5)
    with pytest.raises(ParameterError, match="wind_speed"):
        steady_guess(operating, -3.0)
    with pytest.raises(TypeError, match="DiscreteController"):
        simulate_turbine(operating, 12.0, 1.0, controller="baseline")
    python_law = DiscreteController(lambda t, xc, y: (xc, [0.07, 4e4]), 0.01,
                                    measurements=["GenSpeed"], actuates=["BlPitchCom", "GenTqCom"])
    with pytest.raises(SimulationOptionError, match="cannot follow"):
        simulate_turbine(operating, 12.0, 1.0, controller=python_law, accuracy=1e-3)
    deck = builtin_deck()
    with pytest.raises(ControllerError, match="not found: tried .*libnothing.so"):
        deck.discon_paths(tmp_path / "libnothing.so", tmp_path / "DISCON.IN")
    with pytest.raises(OpenFASTFormatError, match="CompAero"):
        operating_deck(need(AERO.parent / "cases" / "paper44_fa_gen" / "paper44_fa_gen.fst"))
