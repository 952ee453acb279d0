"""Actuators, dynamic inflow, controllers in the loop, package data of the operating turbine.

References:
- smooth saturation: its definition (identity on the allowed interval, the limit ± δ beyond the blend,
  C¹ at the blend edges) and the invariance of the limits (to δ) along a simulated step demand (pitch
  rate, pitch, torque, torque rate);
- second-order pitch actuator inside its limits: the closed form of a step response
  (ω = 50 rad/s, ζ = 0.7) within 1e-6 rad;
- dynamic inflow: actuator-disk momentum theory (Betz a = 1/3 at ct = 8/9; Buhl's line from ct = 0.96);
  at equilibrium its loads equal the quasi-steady surfaces (resampling error, 0.1 %); after a pitch step
  at frozen induction the thrust overshoots and relaxes to the quasi-steady value (the DBEMT signature);
- the baseline controller in the loop converts the OpenFAST-unit channels exactly (same commands as
  BaselineController.function fed SI measurements);
- the baseline in the loop tracks the real ROSCO library on the same plant (12 m/s, 20 s): pitch within
  0.01 deg, torque within 1 N m (float32 swap array; see tests/wind/control);
- the built-in controller data equals BaselineSettings.from_discon of the shared DISCON.IN.
"""

from __future__ import annotations

import json
import math

import casadi as ca
import numpy as np
import pytest

from _op_data import DECK, baseline_settings_data, need
from mbsym.exceptions import ParameterError
from mbsym.wind.operation import ActuatorSettings, smooth_clip
from mbsym.wind.operation.dynamic_inflow import DynamicInflow, dbemt_settings, momentum_induction


def test_smooth_clip_definition():
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [smooth_clip(x, -1.0, 3.0, 0.01)])
    d = 0.04
    for v in (-1.0, -0.5, 0.0, 2.9, 3.0):                        # the identity on the allowed interval
        assert float(f(v)) == v
    for v in (-1.0 - 2 * d, -5.0):
        assert float(f(v)) == pytest.approx(-1.0 - d, abs=1e-15)
    for v in (3.0 + 2 * d, 7.0):
        assert float(f(v)) == pytest.approx(3.0 + d, abs=1e-15)
    J = ca.Function("J", [x], [ca.jacobian(smooth_clip(x, -1.0, 3.0, 0.01), x)])
    for edge in (-1.0 - 2 * d, -1.0, 3.0, 3.0 + 2 * d):          # C¹ at the blend edges
        assert float(J(edge - 1e-9)) == pytest.approx(float(J(edge + 1e-9)), abs=1e-6)


def test_actuator_settings_check_and_sources():
    with pytest.raises(ParameterError, match="pitch_rate_min < 0 < pitch_rate_max"):
        ActuatorSettings(pitch_rate_min=0.1)
    with pytest.raises(ParameterError, match="generator_efficiency"):
        ActuatorSettings(generator_efficiency=1.5)
    a = ActuatorSettings.nrel5mw().replace(pitch_frequency=30.0)
    assert a.sources["pitch_frequency"] == "given" and "PC_MaxRat" in a.sources["pitch_rate_max"]
    assert "invented" in ActuatorSettings.nrel5mw().sources["torque_time_constant"]
    assert a.bounds()["GenTq_d"] == (-40000.0, 40000.0)


def test_actuators_from_the_deck_name_file_and_line():
    a = ActuatorSettings.from_deck(need(DECK / "NRELOffshrBsline5MW_Onshore_ServoDyn.dat"), DECK / "DISCON.IN")
    assert a.generator_efficiency == pytest.approx(0.944)
    assert a.torque_max == pytest.approx(47402.9) and a.pitch_rate_max == pytest.approx(0.1745)
    assert "line 84" in a.sources["torque_max"] and "GenEff" in a.sources["generator_efficiency"]


def test_actuator_limits_hold_along_a_step_demand(operating):
    from mbsym.simulate.api import simulate

    dyn = operating.dynamics()
    x0 = operating.initial_state(12.0, pitch=math.radians(2.0))
    t = np.linspace(0.0, 4.0, 2001)                           # the RK4 steps themselves (no interpolation)
    res = simulate(dyn, 4.0, x0=x0, t_out=t, method="rk4", dt=0.002,
                   inputs={"Wind1VelX": 12.0, "BlPitchCom": (np.array([0.0, 0.5, 0.5001, 4.0]),
                                                              np.array([0.0349, 0.0349, 0.6, 0.6])),
                           "GenTqCom": (np.array([0.0, 0.5, 0.5001, 4.0]), np.array([4e4, 4e4, 9e4, 9e4]))})
    a, w = operating.actuators, operating.saturation_width
    rate, pitch, torque = res.state("BlPitch_d"), res.state("BlPitch"), res.state("GenTq")
    d_rate, d_torque = 2 * w * a.pitch_rate_max, 2 * w * a.torque_rate_max     # the saturation's δ
    assert rate.max() <= (a.pitch_rate_max + d_rate) * (1 + 1e-9) and rate.max() > 0.99 * a.pitch_rate_max   # saturated
    assert pitch.max() <= a.pitch_max and torque.max() <= a.torque_max + w * (a.torque_max - a.torque_min)
    torque_rate = np.diff(torque) / np.diff(t)
    assert torque_rate.max() <= (a.torque_rate_max + d_torque) * (1 + 1e-9) and torque_rate.max() > 0.99 * a.torque_rate_max


def test_pitch_actuator_step_inside_its_limits_is_the_second_order_closed_form(operating):
    from mbsym.simulate.api import simulate

    dyn = operating.dynamics()
    b0, db = math.radians(8.0), math.radians(0.2)             # small: the rate limit is not reached
    x0 = operating.initial_state(14.0, pitch=b0)
    t = np.linspace(0.0, 0.3, 301)
    res = simulate(dyn, 0.3, x0=x0, t_out=t, method="rk4", dt=1e-4,
                   inputs={"Wind1VelX": 14.0, "BlPitchCom": b0 + db, "GenTqCom": x0[dyn.states.index("GenTq")]})
    w, z = operating.actuators.pitch_frequency, operating.actuators.pitch_damping
    wd = w * math.sqrt(1 - z * z)
    exact = b0 + db * (1 - np.exp(-z * w * t) * (np.cos(wd * t) + z / math.sqrt(1 - z * z) * np.sin(wd * t)))
    np.testing.assert_allclose(res.state("BlPitch"), exact, atol=1e-6)


def test_momentum_induction_closed_forms():
    assert float(momentum_induction(8 / 9)) == pytest.approx(1 / 3, rel=1e-12)          # Betz
    a = float(momentum_induction(0.96))
    assert a == pytest.approx(0.4, rel=1e-12)
    b = float(momentum_induction(0.96 + 1e-9))
    assert b == pytest.approx(a, abs=1e-7)                                             # continuous at the switch
    ct = 1.5
    a = float(momentum_induction(ct))                                                  # on Buhl's line
    assert 8 / 9 + (4 - 40 / 9) * a + (50 / 9 - 4) * a * a == pytest.approx(ct, rel=1e-12)


def test_dbemt_settings_follow_openfast_v4_semantics():
    from mbsym.wind.deck.aerodyn import read_aerodyn

    ad = read_aerodyn(need(DECK / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"))
    assert ad.wake_model == 1 and dbemt_settings(ad) == (2, 4.0)      # Wake_Mod 1 + DBEMT_Mod 2: dynamic BEMT
    old = type("AD", (), {"wake_model": 1, "extra": {"DBEMT_Mod": "2", "tau1_const": "4"}})()
    assert dbemt_settings(old) is None                                # pre-v4 file: WakeMod 1 is plain BEMT


def test_dynamic_inflow_equilibrium_and_overshoot():
    from mbsym.wind.aero import nrel5mw_rotor

    rotor = nrel5mw_rotor()
    d = DynamicInflow(rotor)
    u, om, b = ca.SX.sym("u"), ca.SX.sym("om"), ca.SX.sym("b")
    state = ca.SX.sym("s", 2)
    rhs, loads = d.rhs(state, u, om, b, 1.225)
    qs = rotor.loads(u, om, b, 1.225)
    f = ca.Function("f", [state, u, om, b], [rhs, loads["thrust"], loads["torque"], qs["thrust"], qs["torque"]])
    eq = ca.Function("eq", [u, om, b], [ca.vertcat(*d.steady_state(u, om, b))])
    for speed, tsr, pitch in ((8.0, 7.6, 0.0), (11.4, 7.0, 3.0), (14.0, 5.7, 8.6), (24.0, 3.3, 22.0)):
        omega, beta = tsr * speed / rotor.radius, math.radians(pitch)
        s0 = eq(speed, omega, beta)
        r, T, Q, Tq, Qq = f(s0, speed, omega, beta)
        assert np.allclose(np.asarray(r), 0.0, atol=1e-9)
        assert float(T) == pytest.approx(float(Tq), rel=1e-3) and float(Q) == pytest.approx(float(Qq), rel=1e-3)
    # pitch step 8 -> 10 deg at 14 m/s, frozen induction: the thrust drops below the quasi-steady value, then relaxes
    speed, omega = 14.0, 5.7 * 14.0 / rotor.radius
    s = np.asarray(eq(speed, omega, math.radians(8.0)), dtype=float).reshape(-1)
    b1 = math.radians(10.0)
    T0, Tq = (float(v) for v in np.asarray(f(s, speed, omega, b1)[1:4:2]).reshape(-1))
    assert T0 < Tq
    z = ca.SX.sym("z", 2)                                     # 40 s of explicit Euler, dt = 5 ms (tau2 > 1 s)
    euler = ca.Function("euler", [z], [z + 5e-3 * f(z, speed, omega, b1)[0]]).mapaccum("run", 8000)
    s = np.asarray(euler(s), dtype=float)[:, -1]
    assert float(f(s, speed, omega, b1)[1]) == pytest.approx(Tq, rel=2e-3)


def test_baseline_in_the_loop_converts_units_exactly():
    from mbsym.wind.control import BaselineController
    from mbsym.wind.operation.controllers import TO_SI, baseline_in_loop
    from mbsym.wind.operation.nrel5mw import nrel5mw_baseline_settings

    ctrl = BaselineController(nrel5mw_baseline_settings())
    loop = baseline_in_loop(ctrl)
    y_of = np.array([1173.7, 12.1, 3.9, 4951.4, 12.0])          # rpm, rpm, deg, kW, m/s
    x1, u1 = loop.law(ctrl.x0, y_of)
    x2, u2 = ctrl.function(ctrl.x0, y_of * np.array(TO_SI))
    np.testing.assert_array_equal(np.asarray(u1), np.asarray(u2))
    np.testing.assert_array_equal(np.asarray(x1), np.asarray(x2))
    assert loop.measurements == ("GenSpeed", "RotSpeed", "BldPitch1", "GenPwr", "Wind1VelX")
    assert loop.actuates == ("BlPitchCom", "GenTqCom")


def test_builtin_controller_data_matches_the_discon_in():
    from importlib import resources

    packaged = json.loads(resources.files("mbsym.wind.operation").joinpath("data/nrel5mw_baseline.json")
                          .read_text(encoding="utf-8"))
    generated = baseline_settings_data(need(DECK / "DISCON.IN"))
    assert packaged["settings"] == json.loads(json.dumps(generated["settings"]))


def test_baseline_tracks_the_rosco_library_in_the_loop(operating, rosco_lib):
    from mbsym.wind.control import BaselineController, DisconController
    from mbsym.wind.operation.controllers import baseline_in_loop, discon_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine

    discon_in = need(DECK / "DISCON.IN")
    x0 = steady_state(operating, 12.0)
    t = np.linspace(0.0, 20.0, 401)
    ours = simulate_turbine(operating, 12.0, 20.0, x0=x0, t_out=t, controller=baseline_in_loop(
        BaselineController.from_discon(discon_in, dt=float(np.float32(0.01)))))
    with DisconController(rosco_lib, discon_in, dt=0.01) as lib:
        theirs = simulate_turbine(operating, 12.0, 20.0, x0=x0, t_out=t, controller=discon_in_loop(lib))
    assert np.max(np.abs(ours.output("BldPitch1") - theirs.output("BldPitch1"))) < 0.01
    assert np.max(np.abs(ours.output("GenTq") - theirs.output("GenTq"))) * 1e3 < 1.0


def steady_state(model, wind):
    from mbsym.wind.operation.steady import steady_guess

    return steady_guess(model, wind).state
