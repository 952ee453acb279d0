"""One unit convention across outputs (issue 22 item 7; docs/units.md).

References: the numbers themselves. Where a simulation carries the same quantity twice, as a state or
input in SI and as an OpenFAST channel in OpenFAST's unit (pitch: the actuator state ``BlPitch`` and the
channel ``BldPitch1``; rotor speed: ``GeAz_d`` and ``RotSpeed``; generator torque: the state ``GenTq``
and the channel ``GenTq``; the wind: the input and the channel ``Wind1VelX``), the ratio of the two
time series must be the conversion factor between the two *stated* units (deg/rad = 180/π,
rpm/(rad/s) = 30/π, kN-m/(N m) = 1e-3, exactly up to rounding: rtol 1e-12). A wrong or missing label
fails. A linear model's operating-point outputs (SI) against the trim's channels (OpenFAST units) by the
same factors; OpenFAST's own channel units from the headers of the shared reference CSV.
"""

from __future__ import annotations

import ast
import csv
import math
from pathlib import Path

import numpy as np
import pytest

from _op_data import AERO, need
from mbsym.exceptions import DimensionError, OptionError

#: Factor from the first unit to the second (the conversion a correct pair of labels implies).
FACTORS = {("rad", "deg"): 180.0 / math.pi, ("rad/s", "rpm"): 30.0 / math.pi, ("N m", "kN-m"): 1e-3,
           ("m/s", "m/s"): 1.0, ("rad", "rad"): 1.0, ("rad/s", "rad/s"): 1.0, ("N m", "N m"): 1.0,
           ("W", "kW"): 1e-3, ("N", "kN"): 1e-3, ("N m", "N m"): 1.0}
#: The same quantity as (state or input, OpenFAST channel) of the operating turbine.
PAIRS = (("state", "BlPitch", "BldPitch1"), ("state", "GeAz_d", "RotSpeed"), ("state", "GenTq", "GenTq"),
         ("input", "Wind1VelX", "Wind1VelX"))
#: Channels that are ratios (OpenFAST writes "-"), the controller's flags and the Kalman gain on the speed.
DIMENSIONLESS = {"RtTSR", "RtAeroCp", "RtAeroCt", "RtAeroCq", "baseline.first", "baseline.estimator_on",
                 "baseline.ekf_K[0]"}


@pytest.fixture(scope="module")
def result(operating):
    from mbsym.wind.control import BaselineController
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.nrel5mw import nrel5mw_baseline_settings
    from mbsym.wind.operation.simulation import simulate_turbine
    from mbsym.wind.operation.steady import steady_guess

    x0 = steady_guess(operating, 14.0).state
    law = baseline_in_loop(BaselineController(nrel5mw_baseline_settings()))
    return simulate_turbine(operating, lambda t: 14.0 + t, 1.0, x0=x0, controller=law,
                            t_out=np.linspace(0.0, 1.0, 21))


def test_every_state_input_and_channel_has_its_unit(result):
    for kind, names in (("state", result.states), ("input", result.inputs)):
        missing = [n for n in names if result.unit(n, kind) in ("", "-")]
        assert not missing, f"{kind}s without a unit: {missing}"
    dash = {n for n in result.output_names if result.unit(n, "output") in ("", "-")}
    assert dash == DIMENSIONLESS
    assert result.unit("BlPitch", "state") == "rad" and result.unit("BlPitchCom", "input") == "rad"
    assert "BlPitch [rad]" in repr(result) and "BlPitchCom [rad]" in repr(result) and "[-]" not in repr(result)


def test_the_same_quantity_in_si_and_in_openfast_units_differs_by_its_unit_factor(result):
    for kind, si_name, channel in PAIRS:
        si = result.state(si_name) if kind == "state" else result.u[:, result.inputs.index(si_name)]
        key = (result.unit(si_name, kind), result.unit(channel, "output"))
        assert key in FACTORS, f"{si_name} [{key[0]}] vs {channel} [{key[1]}]: no known conversion"
        np.testing.assert_allclose(result.output(channel), si * FACTORS[key], rtol=1e-12, atol=1e-12,
                                   err_msg=f"{si_name} vs {channel}")
    assert result.unit("GenTq") == "kN-m" and result.unit("GenTq", "state") == "N m"       # outputs first
    with pytest.raises(OptionError, match="kind must be one of"):
        result.unit("GenTq", "channel")


def test_channel_units_are_openfasts(result):
    with open(need(AERO / "step_10_14.csv")) as fh:
        header = next(csv.reader(fh))
    theirs = dict(h.rstrip("]").split("_[") for h in header if "_[" in h)
    common = [n for n in result.output_names if n in theirs]
    assert len(common) >= 20
    assert {n: result.unit(n, "output") for n in common} == {n: theirs[n] for n in common}


@pytest.fixture(scope="module")
def points(operating):
    from mbsym.wind.analysis.operating_points import operating_points
    from mbsym.wind.operation import SteadyControl

    return operating_points(operating, [8.0, 16.0], SteadyControl.nrel5mw())


def test_linear_model_states_and_inputs_have_the_simulations_units(points, result):
    from mbsym.wind.analysis.trim_linear import linearize_point, to_si

    point = points.points[1]
    lin = linearize_point(points.trimmer, point, keep_azimuth=True)
    assert {s: lin.units[s] for s in lin.states} == {s: result.unit(s, "state") for s in lin.states}
    assert lin.input_units == tuple(result.unit(n, "input") for n in lin.inputs)
    assert lin.output_units == tuple(to_si(result.unit(n, "output"))[1] for n in lin.outputs)
    for name, unit, y in zip(lin.outputs, lin.output_units, lin.operating_point["y"]):
        key = (unit, point.units[name])              # SI in the linear model, OpenFAST's at the trim
        assert key in FACTORS or unit == point.units[name], (name, key)
        np.testing.assert_allclose(y * FACTORS.get(key, 1.0), point[name], rtol=1e-12, err_msg=name)


def test_operating_points_table_and_plot_show_the_channels_in_the_same_units(points, result):
    from mbsym.wind.analysis.trim_plot import PLOT_CHANNELS

    table_head = points.table().splitlines()[0]
    for name, label, scale in PLOT_CHANNELS:
        unit = result.unit(name, "output")
        assert points.units()[name] == unit and f"{name} [{unit}]" in table_head
        assert label == f"{name} [{unit}]" and scale == 1.0, (name, label, scale)


def test_dynamics_state_and_input_units_are_checked():
    import casadi as ca

    from mbsym import Dynamics

    x, u, p = ca.SX.sym("x", 1), ca.SX.sym("u", 1), ca.SX.sym("p", 0)
    f = ca.Function("f", [x, u, p], [-x + u])
    dyn = Dynamics(f, states=["theta"], inputs=["tau"], state_units=["rad"], input_units=["N m"])
    assert dyn.state_units == ("rad",) and dyn.input_units == ("N m",)
    with pytest.raises(DimensionError, match="state_units has 2 entries; expected 1"):
        Dynamics(f, states=["theta"], inputs=["tau"], state_units=["rad", "m"])


def test_nmpc_example_names_its_numbers_by_channel(operating):
    """The example's JSON keys start with the OpenFAST channel they summarize (no bare "speed")."""
    source = Path(__file__).resolve().parents[3] / "examples" / "turbine_nmpc.py"
    tree = ast.parse(source.read_text())
    summary = next(n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef) and n.name == "summary")
    keys = [k.value for d in ast.walk(summary) if isinstance(d, ast.Dict) for k in d.keys]
    channels = set(operating.dynamics().output_names)
    assert keys and all(k.split("_")[0] in channels for k in keys), keys
    assert "speed" not in {k.split("_")[0] for k in keys}


def test_structural_turbine_inputs_have_units_in_results_and_linear_models():
    """The ElastoDyn-equivalent structure alone: its load inputs are SI in a simulation and a linear model.
    Physics of the labels: the generalized force per unit input, Q, is what the stated units imply: a
    generator torque [N m] on the HSS moves the rotor azimuth [rad] by -GBRatio (97, exactly), the rotor
    torque [N m] by 1, and the thrust [N] the first fore-aft tower mode (tip-normalized, [m]) by the
    mode's value at the hub, 1 within 10 % (the hub sits above and upwind of the tower top)."""
    import mbsym as mb
    from mbsym.wind import TurbineModel
    from mbsym.wind.deck.nrel5mw import nrel5mw

    turbine = TurbineModel(nrel5mw(), dofs=["TwFADOF1", "GenDOF"])
    res = mb.simulate(turbine, 0.05, inputs={"GenTq": 4e4})
    lin = mb.linearize(turbine, method="exact")
    assert lin.input_units == tuple(res.unit(n, "input") for n in lin.inputs) == ("N m", "N m", "N")
    assert "GenTq [N m]" in repr(res) and "RotThrust [N]" in repr(lin)
    Q = dict(zip(lin.inputs, lin.Q.T))
    i_az, i_fa = lin.coordinates.index("GeAz"), lin.coordinates.index("TFA1")
    assert Q["GenTq"][i_az] == pytest.approx(-97.0, rel=1e-12) and Q["RotTorq"][i_az] == pytest.approx(1.0, rel=1e-12)
    assert 0.9 < Q["RotThrust"][i_fa] < 1.1
