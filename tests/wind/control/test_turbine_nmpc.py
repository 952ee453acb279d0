"""The turbine NMPC (``mbsym.wind.mpc``): prediction model, references, closed loop on the full plant.

References: the actuator equations in closed form (docs/operation.md §4: inside its limits the pitch
actuator is ``β̈ = ω²(β_c − β) − 2ζωβ̇``, the torque actuator ``Ṫ = (T_c − T)/τ``); the rated operation
of the NREL 5 MW from ROSCO 2.10.6's settings (``PC_RefSpd`` 122.90967 rad/s, ``VS_RtPwr`` 5 MW,
``VS_GenEff`` 94.4 %: ``P = η T ω``); the rotor's steady torque from its own performance surfaces
(``RotorAero.steady``, independent of the composed graph and the dynamic inflow); the trim of the full
plant under ROSCO's steady laws (``mbsym.wind.operation.trim``, separate code: Newton on the composed
model with the controller's regime conditions); the plant's actuator limits (``OperatingTurbine.bounds()``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from _mpc_setup import nmpc_default, turbine

RATED_RPM = 122.90967 * 30.0 / math.pi


def test_control_form_moves_the_plant_actuators_exactly_at_the_rates():
    """With β̇ = r and β_c = β + (2ζ/ω) r the pitch actuator has β̈ = 0; with T_c = T + τ r_T, Ṫ = r_T."""
    t = turbine()
    pred, full = t.prediction, t.prediction.full
    x = dict(zip(full.states, full.x0))
    x.update(TFA1=0.21, TFA1_d=-0.03, GeAz_d=1.21, GeAz=0.7, BlPitch=0.12, GenTq=41000.0, DBEMT_w=0.4,
             DBEMT_v=1.1)
    rb, rt = 0.05, -2500.0
    x["BlPitch_d"] = rb
    p = dict(zip(full.parameters, full.parameter_vector()))
    demand = [13.0, x["BlPitch"] + 2 * p["pitch_damping"] / p["pitch_frequency"] * rb,
              x["GenTq"] + p["torque_time_constant"] * rt]
    xd_full = dict(zip(full.states, full.rhs_value([x[s] for s in full.states], demand)))
    # the plant's actuator equations in closed form (inside the limits)
    w, z, tau = p["pitch_frequency"], p["pitch_damping"], p["torque_time_constant"]
    assert w ** 2 * (demand[1] - x["BlPitch"]) - 2 * z * w * rb == pytest.approx(0.0, abs=1e-12)
    assert xd_full["BlPitch_dd" if "BlPitch_dd" in xd_full else "BlPitch_d"] == pytest.approx(0.0, abs=1e-9)
    assert xd_full["GenTq"] == pytest.approx((demand[2] - x["GenTq"]) / tau, rel=1e-12)
    xr = [x[s] for s in pred.states]
    xd = dict(zip(pred.states, pred.control.rhs_value(xr, [13.0, rb, rt])))
    assert xd["BlPitch"] == rb and xd["GenTq"] == rt
    for s in ("TFA1", "TFA1_d", "GeAz_d", "DBEMT_w", "DBEMT_v"):      # the structure and inflow as in the plant
        assert xd[s] == pytest.approx(xd_full[s], rel=1e-12, abs=1e-12)


def test_reference_state_is_the_rated_equilibrium_at_14_mps():
    t = turbine()
    x = t.references.state(14.0)
    dyn = t.prediction.control
    assert np.max(np.abs(dyn.rhs_value(x, [14.0, 0.0, 0.0]))) < 1e-7          # an equilibrium of the model
    y = dict(zip(dyn.output_names, dyn.output_value(x, [14.0, 0.0, 0.0])))
    assert y["GenSpeed"] == pytest.approx(RATED_RPM, rel=1e-9)
    assert y["GenPwr"] == pytest.approx(5000.0, rel=1e-9)                      # η T ω = VS_RtPwr
    assert y["GenTq"] * 1e3 * 0.944 * 122.90967 == pytest.approx(5e6, rel=1e-6)
    # the rotor's own steady surfaces: aerodynamic torque = N T_gen at the relative wind, speed and pitch
    steady = t.plant.rotor.steady(y["RtVAvgxh"], y["RotSpeed"] * math.pi / 30, math.radians(y["BldPitch1"]))
    assert float(steady["torque"]) == pytest.approx(97.0 * y["GenTq"] * 1e3, rel=1e-3)   # DBEMT at rest: 0.04 %
    assert 7.0 < y["BldPitch1"] < 10.0


def test_region_2_reference_is_the_best_tip_speed_ratio_at_fine_pitch():
    t = turbine()
    sp = t.setpoints
    tsr = np.linspace(5, 10, 501)
    cp = t.plant.rotor.steady(8.0, tsr * 8.0 / sp.radius, 0.0)["cp"]
    assert sp.optimal_tsr == pytest.approx(tsr[np.argmax(cp)], abs=0.02)
    assert t.references("BldPitch1", 8.0) == 0.0
    rot = t.references("GenSpeed", 8.0) * math.pi / 30 / sp.gearbox_ratio
    assert rot * sp.radius / 8.0 == pytest.approx(sp.optimal_tsr, rel=1e-9)


def test_peak_shaving_reference_holds_the_controllers_minimum_pitch_near_rated():
    # With peak_shaving the steady reference keeps the pitch at or above ROSCO's PS_BldPitchMin (PS_Mode 1 in the
    # built-in deck's DISCON.IN), interpolated at the wind; where the fine-pitch operation already pitches more
    # (region 3) or the minimum is fine pitch (region 2) the reference is unchanged. The reference is still an
    # equilibrium of the model, at less power and less thrust (tower-base moment) than the fine-pitch one.
    from mbsym.wind.mpc.setpoints import reference_table

    t = turbine()
    sp = t.setpoints
    assert t.deck.baseline_settings().peak_shaving and len(sp.min_pitch_winds) == len(sp.min_pitch_values) > 1
    winds = np.array([7.0, 11.0, 11.5, 16.0])
    shaved = reference_table(t.prediction, sp, winds=winds, peak_shaving=True)
    plain = reference_table(t.prediction, sp, winds=winds)
    dyn = t.prediction.control
    for i, u in enumerate(winds):
        assert np.max(np.abs(dyn.rhs_value(shaved.states[i], [u, 0.0, 0.0]))) < 1e-7
    minimum = np.degrees(np.interp(winds, sp.min_pitch_winds, sp.min_pitch_values))
    assert minimum[1] > 1.0 and minimum[2] > 1.0                    # ROSCO's table pitches there
    for name in ("BldPitch1", "GenPwr", "TwrBsMyt"):
        assert shaved(name, 7.0) == pytest.approx(plain(name, 7.0), rel=1e-9, abs=1e-9)
        assert shaved(name, 16.0) == pytest.approx(plain(name, 16.0), rel=1e-9)
    for u, b in zip(winds[1:3], minimum[1:3]):
        assert shaved("BldPitch1", u) == pytest.approx(max(b, plain("BldPitch1", u)), abs=1e-6)
        if b > plain("BldPitch1", u) + 0.1:
            assert shaved("GenPwr", u) < plain("GenPwr", u) and shaved("TwrBsMyt", u) < plain("TwrBsMyt", u)
    assert sp.min_pitch(7.0) == max(sp.fine_pitch, float(np.interp(7.0, sp.min_pitch_winds, sp.min_pitch_values)))


def _closed_loop(wind, tmax, **loop):
    from mbsym.wind.mpc.loop import TurbineLoop
    from mbsym.wind.mpc.simulation import simulate_with_loop
    from mbsym.wind.operation.steady import steady_guess

    t = turbine()
    mpc = nmpc_default()
    mpc.reset()
    lp = TurbineLoop(t.plant, t.deck.controller_dt, nmpc=mpc, wind=wind, **loop)
    x0 = steady_guess(t.plant, float(wind(0.0))).state
    return simulate_with_loop(t.plant, wind, tmax, lp, x0=x0, t_out=np.arange(0, tmax + 1e-9, 0.05), compile=False)


def test_nmpc_holds_the_rated_state_in_a_steady_14_mps_wind():
    from mbsym.wind.inflow import parse_wind_spec

    from mbsym.wind.operation import SteadyControl, trim

    t = turbine()
    point = trim(t.plant, 14.0, SteadyControl.nrel5mw())              # region 3: rated speed and power
    assert point.success and point.region == "3"
    res = _closed_loop(parse_wind_spec("steady:14"), 15.0, preview=5.0)
    late = res.t > 10.0
    assert np.max(np.abs(res.output("GenSpeed")[late] - point["GenSpeed"])) < 0.05      # rpm
    assert np.max(np.abs(res.output("GenPwr")[late] - point["GenPwr"])) < 1.0            # kW
    assert np.max(np.abs(res.output("BldPitch1")[late] - point["BldPitch1"])) < 0.01     # deg
    assert np.max(np.abs(res.output("TTDspFA")[late] - point["TTDspFA"])) < 1e-3         # m
    assert np.max(np.abs(res.output("TwrBsMyt")[late] / point["TwrBsMyt"] - 1)) < 1e-3
    assert point["GenSpeed"] == pytest.approx(RATED_RPM, rel=1e-6)
    assert res.statistics["controller_failures"] == 0


def test_nmpc_respects_pitch_and_torque_limits_and_rates_in_a_wind_step():
    """A 10 -> 20 m/s step asks for more pitch rate than the actuator has: rates saturate, never pass."""
    from mbsym.wind.inflow import parse_wind_spec

    t = turbine()
    b = t.plant.bounds()
    res = _closed_loop(parse_wind_spec("step:10:20:2"), 10.0, preview=1.0)
    dyn = t.plant.dynamics()
    X = np.asarray(res.x)
    rate = X[:, dyn.states.index("BlPitch_d")]
    pitch = X[:, dyn.states.index("BlPitch")]
    torque = X[:, dyn.states.index("GenTq")]
    tol = 1e-3 * (b["BlPitch_d"][1] - b["BlPitch_d"][0])               # the smooth saturation's blend (δ)
    assert rate.max() > 0.9 * b["BlPitch_d"][1]                        # the limit is reached ...
    assert rate.max() <= b["BlPitch_d"][1] + tol and rate.min() >= b["BlPitch_d"][0] - tol   # ... not passed
    assert pitch.min() >= b["BlPitch"][0] - 1e-4 and pitch.max() <= b["BlPitch"][1]
    assert torque.min() >= b["GenTq"][0] and torque.max() <= b["GenTq"][1] + 1.0
    torque_rate = np.diff(torque) / np.diff(res.t)
    assert np.max(np.abs(torque_rate)) <= b["GenTq_d"][1] * 1.001
    plan = nmpc_default().nmpc.stats                                   # every QP solved
    assert all(s.success for s in plan)
    assert abs(res.output("GenSpeed")[-1] / RATED_RPM - 1) < 0.01      # back at rated 8 s after the step


def test_bad_tuning_and_loop_options_are_typed_errors():
    from mbsym.exceptions import ControlDefinitionError, ModelDefinitionError, SimulationOptionError
    from mbsym.wind.mpc.loop import SensorNoise, TurbineLoop
    from mbsym.wind.mpc.nmpc import NMPCTuning, TurbineNMPC
    from mbsym.wind.mpc.prediction import PredictionModel

    t = turbine()
    with pytest.raises(ControlDefinitionError, match="horizon"):
        NMPCTuning(horizon=0)
    with pytest.raises(ControlDefinitionError, match="speed_scale"):
        NMPCTuning(speed_scale=-1.0)
    with pytest.raises(ModelDefinitionError, match="GenDOF"):
        PredictionModel(t.plant, dofs=["TwFADOF1"])
    with pytest.raises(TypeError, match="PredictionModel"):
        TurbineNMPC(t.plant, t.setpoints)
    with pytest.raises(SimulationOptionError, match="preview .* or an estimator"):
        TurbineLoop(t.plant, 0.01, nmpc=nmpc_default())
    with pytest.raises(SimulationOptionError, match="multiple"):
        TurbineLoop(t.plant, 0.03, nmpc=nmpc_default(), preview=1.0, wind=lambda s: 12.0)
    with pytest.raises(SimulationOptionError, match="finite number"):
        TurbineLoop(t.plant, 0.01, nmpc=nmpc_default(), preview=-2.0, wind=lambda s: 12.0)
    with pytest.raises(SimulationOptionError, match="standard deviation"):
        SensorNoise(gen_speed=-1.0)
    nmpc = nmpc_default()
    with pytest.raises(ControlDefinitionError, match="stages 0..N"):
        nmpc.step(np.zeros(len(t.prediction.states)), np.full(3, 12.0))
    with pytest.raises(ControlDefinitionError, match="NaN"):
        nmpc.step(np.zeros(len(t.prediction.states)), float("nan"))


def test_tuning_for_another_turbine_scales_with_its_rated_values():
    """The cost scales are given for the NREL 5 MW (1173.7 rpm, 5 MW, 43.09 kN m at the generator): on the NREL
    5 MW ``for_turbine`` is the identity; on the IEA 15 MW (7.56 rpm direct drive, 15 MW) the speed scale becomes
    the same fraction of its rated speed (20 rpm of 1173.7 → 0.129 rpm of 7.56), the power scale three times the
    5 MW's, the torque scales the same fraction of its rated torque; angles, velocities and the horizon stay."""
    from mbsym.wind.mpc import NMPCTuning, SetPoints

    nrel = SetPoints(1173.7 * math.pi / 30, 670 * math.pi / 30, 5.0e6, 0.944, 7.5, 0.48, 63.0, 97.0, 0.0)
    tuning = NMPCTuning.estimated_wind()
    assert tuning.for_turbine(nrel) == tuning
    iea = SetPoints(7.56 * math.pi / 30, 5.0 * math.pi / 30, 15.0e6, 0.9655, 9.0, 0.49, 120.97, 1.0, 0.0)
    scaled = tuning.for_turbine(iea)
    assert scaled.speed_scale / 7.56 == pytest.approx(tuning.speed_scale / 1173.7, rel=1e-12)
    assert scaled.power_scale == pytest.approx(3.0 * tuning.power_scale, rel=1e-12)
    ratio = iea.rated_torque / 43093.55
    assert scaled.torque_scale == pytest.approx(ratio * tuning.torque_scale, rel=1e-12)
    assert scaled.torque_rate_scale == pytest.approx(ratio * tuning.torque_rate_scale, rel=1e-12)
    assert (scaled.pitch_rate_scale, scaled.tower_velocity_scale, scaled.horizon) == \
        (tuning.pitch_rate_scale, tuning.tower_velocity_scale, tuning.horizon)
    assert math.isinf(NMPCTuning().platform_pitch_rate_scale) and NMPCTuning.floating().platform_pitch_rate_scale == 5e-4


def test_pitch_acceleration_term_starts_the_plan_from_the_rate_applied_before():
    """``pitch_acceleration_scale`` costs the change of the pitch rate per sample, the first stage's from the rate
    applied before (the OCP's augmented state). In a gust from rated operation (14 -> 18 m/s) the NMPC without
    the term pitches at once; with a scale of 1e-3 rad/s² (a 0.01 rad/s jump costs 1e4 units against O(1) for
    the tracking terms) its first rate stays at the previous one, whatever that was."""
    from mbsym.wind.mpc import NMPCTuning, TurbineNMPC
    from mbsym.wind.operation.steady import steady_guess

    t = turbine()
    x_plant = steady_guess(t.plant, 14.0).state
    x = t.prediction.state_from_plant(x_plant, t.plant.dynamics().states)
    free = TurbineNMPC(t.prediction, t.setpoints, references=t.references, compile=False, deadline=math.inf)
    free.nmpc.reset(u_prev=np.zeros(2))
    jump = free.step(x, 18.0)[0]
    assert jump > 0.01                                                  # rad/s: pitching into the gust at once
    held = TurbineNMPC(t.prediction, t.setpoints, references=t.references, compile=False, deadline=math.inf,
                       tuning=NMPCTuning(pitch_acceleration_scale=1e-3))
    for before in (0.0, 0.02):
        held.nmpc.reset(u_prev=np.array([before, 0.0]))
        assert held.step(x, 18.0)[0] == pytest.approx(before, abs=0.02 * jump)
