"""The DISCON bridge with the real ROSCO 2.10.6 library: protocol, life cycle, instances, errors.

References: OpenFAST v5's own run with ROSCO in the loop (``shared/openfast/aero/step_10_14.csv``): fed
OpenFAST's measurements, the library called through our swap array must give back the pitch and torque
OpenFAST applied; ROSCO's documented initialization (torque k·ω² below 0.98 rated speed, pitch = measured).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import casadi as ca

import numpy as np
import pytest

from _measurements import openfast_measurements, read_openfast_csv, synthetic_sweep
from _ctrl_data import AERO, DECK, need
from mbsym.exceptions import ControllerError, ParameterError
from mbsym.wind.control import DisconController
from mbsym.wind.control.baseline import MEASUREMENTS

NAMES = tuple(MEASUREMENTS)
DT = 0.00625


def _run(ctrl: DisconController, t, y):
    out = np.empty((t.size, 2))
    for k in range(t.size):
        u = ctrl.step(t[k], dict(zip(NAMES, y[k])))
        out[k] = u["BlPitchCom1"], u["GenTqCom"]
    return out


def test_swap_protocol_reproduces_what_openfast_applied(rosco_lib, discon_in):
    # OpenFAST called ROSCO every 0.00625 s with its measurements; the CSV keeps them every 0.05 s. Fed the
    # linearly interpolated measurements, ROSCO must return the commands OpenFAST recorded (BldPitch1, GenTq:
    # no pitch actuator, so pitch = command). Interpolating the measurements (and record 15 being the previous
    # step's power in ServoDyn) leaves differences of a few 1e-3 deg and a few N m (observed 0.0043 deg, 6.3 N m).
    csv = need(AERO / "step_10_14.csv")
    t, y = openfast_measurements(csv, DT)
    with DisconController(rosco_lib, discon_in, dt=DT) as ctrl:
        commands = _run(ctrl, t, y)
    of = read_openfast_csv(csv)
    pitch = np.interp(of["Time"], t, np.rad2deg(commands[:, 0]))
    torque = np.interp(of["Time"], t, commands[:, 1])
    assert np.max(np.abs(pitch - of["BldPitch1"])) < 0.02            # deg, pitch range 13 deg
    assert np.max(np.abs(torque - of["GenTq"] * 1e3)) < 30.0         # N m, torque range 12.4 kN m


def test_initialization_call_follows_rosco(rosco_lib, discon_in):
    y = {"GenSpeed": 110.0, "RotSpeed": 110.0 / 97, "BldPitch1": 0.02, "GenPwr": 3.0e6, "Wind1VelX": 9.0}
    with DisconController(rosco_lib, discon_in, dt=DT) as ctrl:
        assert not ctrl.started
        u = ctrl.step(0.0, y)
        assert ctrl.started and "Running ROSCO-2.10.6" in ctrl.messages[0]   # banner captured, not printed
    assert u["GenTqCom"] == pytest.approx(2.31055 * 110.0**2, rel=1e-6)      # VS_Rgn2K ω², ω < 0.98 PC_RefSpd
    assert u["BlPitchCom1"] == pytest.approx(0.02, rel=1e-6) == u["BlPitchCom3"]
    assert u["GenState"] == 1.0 and u["BrakeStatus"] == 0.0


def test_instances_have_their_own_state(rosco_lib, discon_in):
    t, y1 = synthetic_sweep(DT, t_end=6.0, seed=1)
    _, y2 = synthetic_sweep(DT, t_end=6.0, seed=2)
    y2[:, 4] += 2.0
    alone1 = _run(DisconController(rosco_lib, discon_in, dt=DT), t, y1)
    alone2 = _run(DisconController(rosco_lib, discon_in, dt=DT), t, y2)
    a, b = DisconController(rosco_lib, discon_in, dt=DT), DisconController(rosco_lib, discon_in, dt=DT)
    both = np.empty((t.size, 4))
    for k in range(t.size):                              # interleaved calls
        ua = a.step(t[k], dict(zip(NAMES, y1[k])))
        ub = b.step(t[k], dict(zip(NAMES, y2[k])))
        both[k] = ua["BlPitchCom1"], ua["GenTqCom"], ub["BlPitchCom1"], ub["GenTqCom"]
    a.close()
    b.close()
    assert np.array_equal(both[:, :2], alone1) and np.array_equal(both[:, 2:], alone2)
    assert not np.array_equal(alone1, alone2)


def test_in_place_loading_allows_one_live_instance(rosco_lib, discon_in):
    first = DisconController(rosco_lib, discon_in, dt=DT, private_copy=False)
    with pytest.raises(ControllerError, match="already in use by another controller"):
        DisconController(rosco_lib, discon_in, dt=DT, private_copy=False)
    first.close()
    second = DisconController(rosco_lib, discon_in, dt=DT, private_copy=False)
    second.close()


def test_life_cycle_errors(rosco_lib, discon_in):
    y = {"GenSpeed": 110.0, "RotSpeed": 1.13, "BldPitch1": 0.0, "GenPwr": 3.0e6, "Wind1VelX": 9.0}
    ctrl = DisconController(rosco_lib, discon_in, dt=DT)
    with pytest.raises(ParameterError, match=r"unknown \['GenSped'\], missing \['GenSpeed'\]"):
        ctrl.step(0.0, {**{k: v for k, v in y.items() if k != "GenSpeed"}, "GenSped": 1.0})
    with pytest.raises(ParameterError, match="'Wind1VelX' must be finite"):
        ctrl.step(0.0, {**y, "Wind1VelX": float("nan")})
    ctrl.step(0.0, y)
    ctrl.finish()
    with pytest.raises(ControllerError, match="has been finished"):
        ctrl.step(DT, y)
    ctrl.close()
    ctrl.close()                                          # idempotent
    with pytest.raises(ControllerError, match="is closed"):
        ctrl.step(2 * DT, y)
    assert "closed" in repr(ctrl)


def test_library_failure_raises_with_roscos_message(rosco_lib, tmp_path):
    bad = tmp_path / "DISCON.IN"
    text = need(DECK / "DISCON.IN").read_text().replace("1.57080             ! F_LPFCornerFreq", "")
    bad.write_text(text)
    shutil.copy(DECK / "Cp_Ct_Cq.NREL5MW.txt", tmp_path)
    y = {"GenSpeed": 110.0, "RotSpeed": 1.13, "BldPitch1": 0.0, "GenPwr": 3.0e6, "Wind1VelX": 9.0}
    with DisconController(rosco_lib, bad, dt=DT) as ctrl:
        with pytest.raises(ControllerError, match=r"failed at t = 0 s \(aviFAIL = -1\).*F_LPFCornerFreq"):
            ctrl.step(0.0, y)


def test_bad_library_paths_and_symbols(discon_in, tmp_path):
    with pytest.raises(ControllerError, match="DISCON library not found"):
        DisconController(tmp_path / "nope.so", discon_in, dt=DT)
    not_a_library = tmp_path / "fake.so"
    not_a_library.write_text("not a shared library")
    with pytest.raises(ControllerError, match="cannot load the DISCON library"):
        DisconController(not_a_library, discon_in, dt=DT)
    other = Path(ca.__file__).parent / "libcasadi.so"          # a real shared library without DISCON
    if not other.is_file():
        pytest.skip(f"no shared library at {other} to test a library without DISCON")
    with pytest.raises(ControllerError, match="has no function 'DISCON'"):
        DisconController(other, discon_in, dt=DT, private_copy=False)     # already loaded: no copy needed
    with pytest.raises(ControllerError, match="controller input file not found"):
        DisconController(other, tmp_path / "missing.IN", dt=DT)


def test_from_servodyn_uses_the_deck(rosco_lib, tmp_path):
    servo = tmp_path / "servo.dat"
    text = need(DECK / "NRELOffshrBsline5MW_Onshore_ServoDyn.dat").read_text()
    servo.write_text(text.replace('"../rosco/lib/libdiscon.so"', f'"{rosco_lib}"')
                     .replace('"DISCON.IN"    DLL_InFile', f'"{DECK / "DISCON.IN"}"    DLL_InFile'))
    with pytest.raises(ControllerError, match="give glue_time_step"):
        DisconController.from_servodyn(servo)
    with DisconController.from_servodyn(servo, glue_time_step=DT) as ctrl:
        assert ctrl.dt == DT and ctrl.individual_pitch
        u = ctrl.step(0.0, {"GenSpeed": 110.0, "RotSpeed": 1.13, "BldPitch1": 0.01, "GenPwr": 3e6,
                            "Wind1VelX": 9.0})
        assert u["BlPitchCom2"] == pytest.approx(0.01, rel=1e-6)


def test_vector_callable_for_simulation_loops(rosco_lib, discon_in):
    y = np.array([110.0, 1.13, 0.01, 3.0e6, 9.0])
    with DisconController(rosco_lib, discon_in, dt=DT) as a, DisconController(rosco_lib, discon_in, dt=DT) as b:
        f = a.callable()
        u = f(0.0, y)
        ref = b.step(0.0, dict(zip(NAMES, y)))
        assert u.tolist() == [ref["BlPitchCom1"], ref["GenTqCom"]]
        with pytest.raises(ParameterError, match="expected 5"):
            f(DT, y[:4])
    with pytest.raises(ParameterError, match="unknown measurement or command names \\['Pitch'\\]"):
        a.callable(commands=("Pitch",))
