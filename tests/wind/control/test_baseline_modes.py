"""The baseline's generator-speed notch filters, tower damper and power reference against ROSCO 2.10.6.

Modes (the shared NREL 5 MW DISCON.IN with the mode switched on in a copy):

* ``notch``: two generator-speed notch filters (``F_GenSpdNotch_N 2``; 3P at 3.8 rad/s, deep, and a shallow one
  at 12 rad/s);
* ``tower-damper``: ``TD_Mode 1`` (``FA_KI`` 0.05 rad s/m, ``FA_HPFCornerFreq`` 0.1 rad/s, ``FA_IntSat`` 0.05 rad);
* ``prc-table``: ``PRC_Mode 1`` (generator speed 110 rad/s from 3 to 12 m/s, 105 rad/s at 25 m/s);
* ``prc-ratings``: ``PRC_Mode 2``, ``PRC_Comm 0``, ratings speed 0.9, torque 0.85, pitch 0.7 (and the same with
  ``VS_ControlMode 1`` constant torque, whose torque limit the rating scales).

References: (1) open loop, the library through :class:`DisconController` and our Function on the same
measurement sequence (the synthetic sweep of test_baseline_vs_rosco.py, with tower-top accelerations for the
damper); (2) closed loop, both controllers around the same plant (the built-in NREL 5 MW, generator and first
tower fore-aft DOFs, RK4 at the controller's 0.01 s) in the same wind (10 → 14 m/s step at 5 s, 20 s), the library
in mbsym's DISCON loop, our controller compiled into the loop. (3) The notch filters' discretization against
scipy's bilinear transform of ROSCO's continuous notch.

Tolerances: those of test_baseline_vs_rosco.py — ROSCO works on a float32 swap array (measurements, time
step and commands in single precision), we in double; |Δpitch| < 1e-4 deg and |Δtorque| < 0.05 N m at every
step; closed loop also |Δrotor speed| < 1e-5 rpm. Observed open loop: ≤ 3.6e-6 deg and 2.9e-3 N m; closed
loop ≤ 5.0e-6 deg, 6.5e-3 N m and 2.8e-7 rpm (the float32 rounding fed back through the plant). Every case
must move the commands by more than 100× the pitch tolerance against the same
controller with the mode off (so the comparison can fail). Skips without the ROSCO wheel or the shared deck.
"""

from __future__ import annotations

import numpy as np
import pytest

from _ctrl_data import discon_variant
from _measurements import synthetic_sweep
from mbsym.wind.control import BaselineController, DisconController

PITCH_TOL_DEG, TORQUE_TOL, SPEED_TOL_RPM = 1e-4, 0.05, 1e-5
NOTCH = {"F_NumNotchFilts": 2, "F_NotchFreqs": "3.8  12.0", "F_NotchBetaNum": "0.0  0.05",
         "F_NotchBetaDen": "0.25  0.3", "F_GenSpdNotch_N": 2, "F_GenSpdNotch_Ind": "1  2"}
TOWER_DAMPER = {"TD_Mode": 1, "FA_KI": 0.05, "FA_HPFCornerFreq": 0.1, "FA_IntSat": 0.05}
PRC_TABLE = {"PRC_Mode": 1, "PRC_n": 3, "PRC_WindSpeeds": "3.0  12.0  25.0", "PRC_GenSpeeds": "110.0  110.0  105.0"}
PRC_RATINGS = {"PRC_Mode": 2, "PRC_R_Speed": 0.9, "PRC_R_Torque": 0.85, "PRC_R_Pitch": 0.7}
CASES = {"notch": NOTCH, "tower-damper": TOWER_DAMPER, "prc-table": PRC_TABLE, "prc-ratings": PRC_RATINGS,
         "prc-ratings-constant-torque": {**PRC_RATINGS, "VS_ControlMode": 1, "VS_ConstPower": 0}}
OFF = {"notch": {}, "tower-damper": {}, "prc-table": {}, "prc-ratings": {},
       "prc-ratings-constant-torque": {"VS_ControlMode": 1, "VS_ConstPower": 0}}


def _sweep_with_tower_top(dt: float, t_end: float) -> tuple[np.ndarray, np.ndarray]:
    """The synthetic sweep and the tower top's accelerations (fore-aft: the first tower mode, 0.32 Hz, and a
    1.1 Hz component [m/s²]; side-side [m/s²]) with the nacelle yawed by 0.05 rad."""
    t, y = synthetic_sweep(dt, t_end=t_end)
    ax = 0.3 * np.sin(2 * np.pi * 0.32 * t) + 0.05 * np.sin(2 * np.pi * 1.1 * t)
    return t, np.column_stack([y, ax, 0.1 * np.cos(t), np.full(t.size, 0.05)])


def _library(lib, discon, t, y, names, dt):
    out = np.empty((t.size, 2))
    with DisconController(lib, discon, dt=dt) as ctrl:
        for k in range(t.size):
            u = ctrl.step(t[k], dict(zip(names, y[k])))
            out[k] = u["BlPitchCom1"], u["GenTqCom"]
    return out


@pytest.mark.parametrize("case", list(CASES))
def test_open_loop_against_the_library(rosco_lib, tmp_path, case):
    dt = 0.0125
    discon = discon_variant(tmp_path, CASES[case])
    ctrl = BaselineController.from_discon(discon, dt=float(np.float32(dt)))
    t, y = _sweep_with_tower_top(dt, 80.0)
    if case != "tower-damper":
        y = y[:, :5]
    else:           # region 3 only: below rated the damper's pitch is saturated away at fine pitch
        t, y = t[:3000] - t[0], y[3200:6200]
    assert ctrl.measurements == BaselineController.measurement_names + (
        ("YawBrTAxp", "YawBrTAyp", "NacYaw") if case == "tower-damper" else ())
    ours = ctrl.run(y)[0]
    rosco = _library(rosco_lib, discon, t, y, ctrl.measurements, dt)
    dp, dq = np.rad2deg(np.abs(ours[:, 0] - rosco[:, 0])), np.abs(ours[:, 1] - rosco[:, 1])
    print(f"{case}: max |dpitch| {dp.max():.2e} deg, max |dtorque| {dq.max():.2e} N m")
    assert dp.max() < PITCH_TOL_DEG and dq.max() < TORQUE_TOL
    off = BaselineController.from_discon(discon_variant(_folder(tmp_path / "off"), OFF[case]),
                                         dt=float(np.float32(dt))).run(y[:, :5])[0]
    assert np.rad2deg(np.abs(off[:, 0] - rosco[:, 0])).max() > 100 * PITCH_TOL_DEG, "the mode changes nothing"


def _folder(path):
    path.mkdir()
    return path


def test_generator_speed_notches_are_rosco_discretization(tmp_path):
    # GenSpeedF = notch2(notch1(first-order low-pass(GenSpeed))), each filter the bilinear (Tustin) transform of
    # ROSCO's continuous one without prewarping, at the controller's sample time; both in double precision, so
    # only rounding separates them (1e-9 rad/s on ~120 rad/s).
    from scipy.signal import bilinear, lfilter

    dt = 0.0125
    ctrl = BaselineController.from_discon(discon_variant(tmp_path, NOTCH), dt=dt)
    s = ctrl.settings
    assert s.speed_notch_freqs == (3.8, 12.0) and s.speed_notch_beta_den == (0.25, 0.3)
    t, y = synthetic_sweep(dt, t_end=30.0)
    y[:, 0] += 2.0 * np.sin(3.8 * t) + 0.5 * np.sin(12.0 * t)
    _, states = ctrl.run(y)
    diag = np.asarray(ctrl.diagnostics.map(t.size)(states[:-1].T, y.T)).T
    gen_f = diag[:, ctrl.diagnostic_names.index("GenSpeedF")]
    fs, w = 1.0 / dt, s.speed_filter_corner
    assert s.speed_filter_order == 1
    u = y[:, 0]
    b, a = bilinear([w], [1.0, w], fs)
    u = lfilter(b, a, u, zi=u[0] * _steady_zi(b, a))[0]
    for wn, bn, bd in zip(s.speed_notch_freqs, s.speed_notch_beta_num, s.speed_notch_beta_den):
        b, a = bilinear([1.0, 2 * bn * wn, wn * wn], [1.0, 2 * bd * wn, wn * wn], fs)
        u = lfilter(b, a, u, zi=u[0] * _steady_zi(b, a))[0]
    assert np.max(np.abs(gen_f - u)) < 1e-9
    plain = BaselineController(s.replace(speed_notch_freqs=(), speed_notch_beta_num=(), speed_notch_beta_den=()))
    _, plain_states = plain.run(y)
    plain_f = np.asarray(plain.diagnostics.map(t.size)(plain_states[:-1].T, y.T)).T[:, 0]
    assert np.max(np.abs(plain_f - gen_f)) > 0.5                                  # the notches remove the 3P wobble


def _steady_zi(b, a):
    """lfilter's initial state for a unit input held since ever (ROSCO starts its filters at their input; a unit
    steady-state gain, which the low-pass and the notches have)."""
    from scipy.signal import lfilter_zi

    return lfilter_zi(b, a)


def test_refused_power_reference_inputs_and_yaw_control_by_name(tmp_path):
    from mbsym.exceptions import ControllerError

    for changes, key in (({"PRC_Mode": 2, "PRC_Comm": 1}, "PRC_Comm"), ({"Y_ControlMode": 1}, "Y_ControlMode")):
        folder = tmp_path / key
        folder.mkdir()
        with pytest.raises(ControllerError, match=rf"line \d+, key '{key}': {key} = 1 is not supported"):
            BaselineController.from_discon(discon_variant(folder, changes), dt=0.01)


# ---------------------------------------------------------------------------------------------- closed loop
def _closed_loops(rosco_lib, discon, off_discon, tmax=20.0):
    """The built-in NREL 5 MW (GenDOF, TwFADOF1) in a 10 -> 14 m/s step at 5 s, RK4 at 0.01 s, closed by our
    compiled controller and by the ROSCO library with the same DISCON.IN. The land plant measures the tower
    top's accelerations and the nacelle yaw (records 53, 54, 37, as ServoDyn fills them), which the tower damper
    reads. Returns our run, the library's run and our run with the mode off (``off_discon``)."""
    from mbsym.wind import OperatingTurbine
    from mbsym.wind.inflow import StepWind
    from mbsym.wind.operation.controllers import baseline_in_loop, discon_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine
    from mbsym.wind.operation.steady import steady_guess

    dt = 0.01
    model = OperatingTurbine.nrel5mw(dofs=["GenDOF", "TwFADOF1"])
    x0, wind = steady_guess(model, 10.0).state, StepWind(10.0, 14.0, 5.0)
    t = np.round(np.arange(0.0, tmax + 1e-9, 0.05), 12)

    def ours(path):
        return baseline_in_loop(BaselineController.from_discon(path, dt=dt))

    def run(controller):
        return simulate_turbine(model, wind, tmax, x0=x0, t_out=t, controller=controller, method="rk4", dt=dt)

    with DisconController(rosco_lib, discon, dt=dt) as lib:
        theirs = run(discon_in_loop(lib, model=model))
    return run(ours(discon)), theirs, run(ours(off_discon))


@pytest.mark.parametrize("case", ["notch", "tower-damper", "prc-table", "prc-ratings"])
def test_closed_loop_on_the_same_plant_and_wind(rosco_lib, tmp_path, case):
    mine, theirs, off = _closed_loops(rosco_lib, discon_variant(tmp_path, CASES[case]),
                                      discon_variant(_folder(tmp_path / "off"), OFF[case]))
    dp = np.abs(mine.output("BldPitch1") - theirs.output("BldPitch1"))
    dq = np.abs(mine.output("GenTq") - theirs.output("GenTq")) * 1e3
    dw = np.abs(mine.output("RotSpeed") - theirs.output("RotSpeed"))
    print(f"{case}: closed loop max |dpitch| {dp.max():.2e} deg, |dtorque| {dq.max():.2e} N m, "
          f"|drotor speed| {dw.max():.2e} rpm")
    assert dp.max() < PITCH_TOL_DEG and dq.max() < TORQUE_TOL and dw.max() < SPEED_TOL_RPM
    assert np.abs(off.output("BldPitch1") - theirs.output("BldPitch1")).max() > 100 * PITCH_TOL_DEG
    assert np.ptp(theirs.output("BldPitch1")) > 1.0                      # the step pitches the blades


def test_written_discon_in_carries_the_modes(tmp_path):
    # write_discon_in writes the notches, the damper and the ratings, and reads them back as the same settings
    # (write_discon_in checks the round trip itself; here also that the modes are on in the file)
    import json
    from importlib import resources

    from mbsym.wind.control import BaselineSettings, write_discon_in
    from mbsym.wind.deck.discon_in import read_discon_in
    from mbsym.wind.deck.performance import read_performance_table

    settings = BaselineSettings.from_discon(discon_variant(tmp_path, {**NOTCH, **TOWER_DAMPER, **PRC_RATINGS}),
                                            dt=0.01)
    other = json.loads(resources.files("mbsym.wind.operation").joinpath("data/nrel5mw_discon.json")
                       .read_text(encoding="utf-8"))["other"]
    held = ("PRC_", "FA_", "TD_", "F_Notch", "F_NumNotch", "F_GenSpd")
    other = {k: v for k, v in other.items() if not k.startswith(held)}
    path = write_discon_in(settings, _folder(tmp_path / "written") / "DISCON.IN",
                           performance=read_performance_table(tmp_path / "Cp_Ct_Cq.NREL5MW.txt"), other=other)
    d = read_discon_in(path)
    assert (d["TD_Mode"], d["PRC_Mode"], d["F_GenSpdNotch_N"], list(d["F_GenSpdNotch_Ind"])) == (1, 2, 2, [1, 2])
    assert BaselineSettings.from_discon(path, dt=0.01).speed_notch_beta_num == (0.0, 0.05)
