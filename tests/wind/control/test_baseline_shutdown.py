"""The baseline's shut-down (``SD_Mode 1``) and start-up (``SU_Mode 1``) against ROSCO 2.10.6.

Cases (the shared NREL 5 MW DISCON.IN with the mode switched on in a copy):

* ``sd-time``: ``SD_EnableTime`` at 10.004 s, ``SD_Method 1``, two timed stages (5 s at 0.0218 rad/s and
  2000 N m/s, then 0.1 rad/s and 10 kN m/s);
* ``sd-pitch-stages``: ``SD_EnablePitch`` above 0.2 rad, ``SD_Method 2`` (stages at 0.3 and 0.5 rad);
* ``sd-speed``: ``SD_EnableGenSpeed`` above 123 rad/s, armed from ``SD_TimeActivate`` 2 s;
* ``sd-yaw``: ``SD_EnableYawError`` above 25° (the yaw error, record 24, swinging ±0.7 rad);
* ``startup``: ``SU_Mode 1`` from 0.2 rad/s: pre-start until 2 s, free-wheeling at 0.6 rad/s for 4 s, loads
  0.3 and 1.0 in 4 and 5 s, held 3 and 4 s.

References, tolerances and the check that the mode acts are those of test_baseline_modes.py: open loop,
the library and our Function on the same measurements (the shut-downs on the region-3 part of its sweep,
which trips them all; the start-up on a rotor speed rising from 0.2 rad/s); closed loop, both controllers
around the built-in NREL 5 MW (GenDOF, TwFADOF1, RK4 at 0.01 s), the shut-down tripped by the overspeed of a
10 → 14 m/s step, the start-up from rest-like 0.3 rad/s at 9 m/s. Observed open loop ≤ 1.3e-5 deg and
0.015 N m (the start-up), closed loop ≤ 3.1e-6 deg, 2.8e-3 N m and 3.9e-7 rpm. Skips without the ROSCO
wheel or the shared deck.
"""

from __future__ import annotations

import numpy as np
import pytest

from _ctrl_data import discon_variant
from mbsym.wind.control import BaselineController

from test_baseline_modes import PITCH_TOL_DEG, SPEED_TOL_RPM, TORQUE_TOL, _closed_loops, _folder, _library

STAGES = {"SD_Stage_N": 2, "SD_StageTime": "5.0  100.0", "SD_MaxTorqueRate": "2000  10000",
          "SD_MaxPitchRate": "0.0218  0.1", "SD_StagePitch": "0.3  0.5"}
ONE_STAGE = {"SD_Stage_N": 1, "SD_MaxTorqueRate": "3000", "SD_MaxPitchRate": "0.05"}
STARTUP = {"SU_Mode": 1, "SU_StartTime": 2.0, "SU_FW_MinDuration": 4.0, "SU_RotorSpeedThresh": 0.6,
           "SU_LoadStages": "0.3  1.0", "SU_LoadRampDuration": "4.0  5.0", "SU_LoadHoldDuration": "3.0  4.0"}
CASES = {
    "sd-time": {"SD_Mode": 1, "SD_EnableTime": 1, "SD_Time": 10.004, **STAGES},
    "sd-pitch-stages": {"SD_Mode": 1, "SD_EnablePitch": 1, "SD_MaxPit": 0.2, "SD_Method": 2, **STAGES},
    "sd-speed": {"SD_Mode": 1, "SD_EnableGenSpeed": 1, "SD_MaxGenSpd": 123.0, "SD_TimeActivate": 2.0, **ONE_STAGE},
    "sd-yaw": {"SD_Mode": 1, "SD_EnableYawError": 1, "SD_MaxYawError": 25.0, **ONE_STAGE},
    "startup": STARTUP,
}


def _measurements(case: str, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Shut-downs: the region-3 part (from 40 s) of the synthetic sweep (below rated ROSCO's estimator switches
    off on pitch residuals of 1e-18 rad that we count as inside its table: see baseline.py), with a yaw error
    [rad] for ``sd-yaw``. Start-up: rotor speed 0.2 → 0.8 → 1.1 → 1.0 rad/s (0-15-30-45 s, ±0.01 at 2.1 rad/s),
    wind 9 ± 0.3 m/s, power 0 → 2.6 MW, pitch 0.05 rad at the first call."""
    from _measurements import synthetic_sweep

    if case == "startup":
        t = np.arange(0.0, 45.0 + 1e-9, dt)
        rotor = np.interp(t, [0.0, 15.0, 30.0, 45.0], [0.2, 0.8, 1.1, 1.0]) + 0.01 * np.sin(2.1 * t)
        power = np.interp(t, [0.0, 16.0, 35.0, 45.0], [0.0, 2e5, 2.5e6, 2.6e6])
        return t, np.column_stack([97.0 * rotor, rotor, np.full(t.size, 0.05), power, 9.0 + 0.3 * np.sin(0.9 * t)])
    t, y = synthetic_sweep(dt, t_end=80.0)
    t, y = t[:3000], y[3200:6200]
    if case == "sd-yaw":
        y = np.column_stack([y, 0.7 * np.sin(0.05 * t)])
    return t, y


@pytest.mark.parametrize("case", list(CASES))
def test_open_loop_against_the_library(rosco_lib, tmp_path, case):
    dt = 0.0125
    discon = discon_variant(tmp_path, CASES[case])
    ctrl = BaselineController.from_discon(discon, dt=float(np.float32(dt)))
    t, y = _measurements(case, dt)
    assert ctrl.measurements == BaselineController.measurement_names + (("YawErr",) if case == "sd-yaw" else ())
    ours, states = ctrl.run(y)
    rosco = _library(rosco_lib, discon, t, y, ctrl.measurements, dt)
    dp, dq = np.rad2deg(np.abs(ours[:, 0] - rosco[:, 0])), np.abs(ours[:, 1] - rosco[:, 1])
    print(f"{case}: max |dpitch| {dp.max():.2e} deg, max |dtorque| {dq.max():.2e} N m")
    assert dp.max() < PITCH_TOL_DEG and dq.max() < TORQUE_TOL
    diag = dict(zip(ctrl.diagnostic_names, np.asarray(ctrl.diagnostics.map(t.size)(states[:-1].T, y.T))))
    if case == "startup":        # every stage is passed through: -1, 1 (free-wheeling), 2, 3 (loads), 0
        assert list(dict.fromkeys(diag["SU_Stage"])) == [-1.0, 1.0, 2.0, 3.0, 0.0]
    else:                        # it trips with the trigger named and stays tripped
        code = {"sd-pitch-stages": 1.0, "sd-yaw": 2.0, "sd-speed": 3.0, "sd-time": 4.0}[case]
        trip = np.flatnonzero(diag["SD_Trigger"])[0]
        assert np.all(diag["SD_Trigger"][trip:] == code) and np.rad2deg(rosco[-1, 0]) > 60.0   # feathering
    off = BaselineController.from_discon(discon_variant(_folder(tmp_path / "off"), {}),
                                         dt=float(np.float32(dt))).run(y[:, :5])[0]
    assert np.rad2deg(np.abs(off[:, 0] - rosco[:, 0])).max() > 100 * PITCH_TOL_DEG, "the mode changes nothing"


def test_closed_loop_shutdown_on_overspeed(rosco_lib, tmp_path):
    # The 10 -> 14 m/s step overspeeds the generator past 124.5 rad/s (filtered): the turbine shuts down
    case = {"SD_Mode": 1, "SD_EnableGenSpeed": 1, "SD_MaxGenSpd": 124.5, **STAGES, "SD_StageTime": "3.0  100.0",
            "SD_MaxTorqueRate": "4000  10000", "SD_MaxPitchRate": "0.03  0.1"}
    mine, theirs, off = _closed_loops(rosco_lib, discon_variant(tmp_path, case),
                                      discon_variant(_folder(tmp_path / "off"), {}), tmax=25.0)
    _assert_close("shut-down", mine, theirs, off)
    assert theirs.output("BldPitch1")[-1] > 89.0 and theirs.output("GenTq")[-1] == 0.0


def test_closed_loop_startup_from_low_rotor_speed(rosco_lib, tmp_path):
    # From 0.3 rad/s, pitch 0.05 rad, no torque, at 9 m/s (11 m/s from 25 s): pre-start to 1 s, free-wheeling at
    # 0.6 rad/s, the loads 0.4 and 1.0 in 3 and 4 s held 2 and 3 s, then normal operation
    from mbsym.wind import OperatingTurbine
    from mbsym.wind.inflow import StepWind
    from mbsym.wind.operation.controllers import baseline_in_loop, discon_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine

    from mbsym.wind.control import DisconController

    case = {**STARTUP, "SU_StartTime": 1.0, "SU_FW_MinDuration": 3.0, "SU_LoadStages": "0.4  1.0",
            "SU_LoadRampDuration": "3.0  4.0", "SU_LoadHoldDuration": "2.0  3.0"}
    dt, tmax = 0.01, 35.0
    model = OperatingTurbine.nrel5mw(dofs=["GenDOF", "TwFADOF1"])
    x0, wind = model.initial_state(rotor_speed=0.3, pitch=0.05, torque=0.0), StepWind(9.0, 11.0, 25.0)
    t = np.round(np.arange(0.0, tmax + 1e-9, 0.05), 12)

    def run(controller):
        return simulate_turbine(model, wind, tmax, x0=x0, t_out=t, controller=controller, method="rk4", dt=dt)

    discon = discon_variant(tmp_path, case)
    mine = run(baseline_in_loop(BaselineController.from_discon(discon, dt=dt)))
    with DisconController(rosco_lib, discon, dt=dt) as lib:
        theirs = run(discon_in_loop(lib, model=model))
    off = run(baseline_in_loop(BaselineController.from_discon(discon_variant(_folder(tmp_path / "off"), {}), dt=dt)))
    _assert_close("start-up", mine, theirs, off)
    torque = theirs.output("GenTq")
    assert np.all(torque[t < 10.0] == 0.0) and torque[-1] > 20.0        # free-wheeling, then loaded [kN m]


def _assert_close(name, mine, theirs, off):
    dp = np.abs(mine.output("BldPitch1") - theirs.output("BldPitch1"))
    dq = np.abs(mine.output("GenTq") - theirs.output("GenTq")) * 1e3
    dw = np.abs(mine.output("RotSpeed") - theirs.output("RotSpeed"))
    print(f"{name}: closed loop max |dpitch| {dp.max():.2e} deg, |dtorque| {dq.max():.2e} N m, "
          f"|drotor speed| {dw.max():.2e} rpm")
    assert dp.max() < PITCH_TOL_DEG and dq.max() < TORQUE_TOL and dw.max() < SPEED_TOL_RPM
    assert np.abs(off.output("BldPitch1") - theirs.output("BldPitch1")).max() > 100 * PITCH_TOL_DEG


def test_written_discon_in_carries_shutdown_and_startup(tmp_path):
    # write_discon_in writes SD_* and SU_* (SD_MaxYawError back in deg) and reads them back as the same settings
    import json
    from importlib import resources

    from mbsym.wind.control import BaselineSettings, write_discon_in
    from mbsym.wind.deck.discon_in import read_discon_in
    from mbsym.wind.deck.performance import read_performance_table

    settings = BaselineSettings.from_discon(discon_variant(tmp_path, {**CASES["sd-yaw"], **STARTUP,
                                                                      "SD_EnableTime": 1}), dt=0.01)
    other = json.loads(resources.files("mbsym.wind.operation").joinpath("data/nrel5mw_discon.json")
                       .read_text(encoding="utf-8"))["other"]
    other = {k: v for k, v in other.items() if not k.startswith(("SD_", "SU_"))}
    path = write_discon_in(settings, _folder(tmp_path / "written") / "DISCON.IN",
                           performance=read_performance_table(tmp_path / "Cp_Ct_Cq.NREL5MW.txt"), other=other)
    d = read_discon_in(path)
    assert (d["SD_Mode"], d["SU_Mode"], d["SD_EnableYawError"], d["SD_EnableTime"], d["SU_LoadStages_N"]) == \
        (1, 1, 1, 1, 2)
    assert d["SD_MaxYawError"] == pytest.approx(25.0, abs=1e-10)
    assert BaselineSettings.from_discon(path, dt=0.01).startup_loads == (0.3, 1.0)


def test_bad_stages_are_refused(tmp_path):
    from mbsym.exceptions import ControllerError

    for changes, what in (({**STARTUP, "SU_LoadRampDuration": "0.0  5.0"}, "startup_ramp_durations"),
                          ({"SD_Mode": 1, **ONE_STAGE, "SD_MaxPitchRate": "0.5"}, "shutdown_pitch_rates")):
        with pytest.raises(ControllerError, match=what):
            BaselineController.from_discon(discon_variant(_folder(tmp_path / what), changes), dt=0.01)


def test_yaw_error_trigger_needs_a_plant_measuring_it(tmp_path):
    # The operating plants do not measure the yaw error (record 24): the loop says so instead of a KeyError
    from mbsym.exceptions import ControllerError
    from mbsym.wind.operation.controllers import baseline_in_loop

    ctrl = BaselineController.from_discon(discon_variant(tmp_path, CASES["sd-yaw"]), dt=0.01)
    with pytest.raises(ControllerError, match="YawErr"):
        baseline_in_loop(ctrl)


def test_linearized_in_normal_operation_as_without_the_modes():
    # The step count (ROSCO's clock) advances at a fixed point and the stages are logic: the linearization about
    # a 16 m/s trim, after the start-up has ended and with no trigger tripped, is the plain controller's
    import dataclasses
    import math

    pytest.importorskip("control")
    from mbsym.wind import OperatingTurbine
    from mbsym.wind.analysis.closed_loop import closed_loop_sweep
    from mbsym.wind.control.linear import linearize_controller
    from mbsym.wind.operation.nrel5mw import nrel5mw_baseline_settings

    s = nrel5mw_baseline_settings()
    plain = BaselineController(s)
    sweep = closed_loop_sweep(OperatingTurbine.nrel5mw(dofs=["GenDOF"]), [16.0], plain)
    assert sweep.success, sweep.messages
    op = sweep.models[0].controller.operating_point
    modes = BaselineController(dataclasses.replace(
        s, shutdown_mode=1, shutdown_on_generator_speed=True, shutdown_max_generator_speed=140.0,
        shutdown_generator_speed_corner=0.4, shutdown_on_time=True, shutdown_time=9999.0, shutdown_pitch_rates=(0.05,),
        shutdown_torque_rates=(2000.0,), shutdown_stage_times=(10.0,), startup_mode=1, startup_time=1.0,
        startup_freewheel_duration=2.0, startup_rotor_speed=0.6, startup_rotor_speed_corner=0.4,
        startup_loads=(0.5, 1.0), startup_ramp_durations=(3.0, 3.0), startup_hold_durations=(2.0, 2.0)))
    a = linearize_controller(plain, op["y"], op["u"]).to_statespace()
    b = linearize_controller(modes, op["y"], op["u"]).to_statespace()
    assert a.nstates == b.nstates
    for f in (1e-3, 1e-2, 0.1, 1.0, 10.0):
        z = np.exp(2j * math.pi * f * plain.dt)
        assert np.max(np.abs(a(z) - b(z))) <= 1e-9 * np.max(np.abs(a(z))), f
