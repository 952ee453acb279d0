"""Individual pitch control (IPC) of our baseline controller against the real ROSCO 2.10.6 library, open loop.

Reference: ROSCO's ``libdiscon.so`` through :class:`DisconController` (individual pitch, records 42-44) with
identical measurement sequences (``ipc_sweep``: the region 2 → 3 → 2 sweep of the collective tests plus 1P- and
2P-modulated blade-root moments and a rotating azimuth), on variants of the NREL 5 MW DISCON.IN with
IPC_ControlMode 1 and 2 and every IPC_SatMode, azimuth offsets and the IPC low-pass filter.

Gains: ROSCO ships no IPC gains for the NREL 5 MW (its DISCON.IN has IPC_KP = IPC_KI = 0). We take the 1P
integral gain of ROSCO's own IPC example, the NREL 2.8 MW (Examples/Tune_Cases/NREL2p8.yaml: IPC_Ki1p = 5.2e-9,
IPC_Kp1p = 0, used by Examples/12_tune_ipc.py), half of it for 2P, and small proportional gains (1e-9, 5e-10)
so that the P path is exercised too. Open loop the integrators wind up against their limits (IPC_IntSat
0.3 rad or the soft limits of IPC_SatMode 2 and 3), so the saturation paths are exercised as well.

Tolerance: as for the collective controller (test_baseline_vs_rosco.py), |Δpitch| < 1e-4 deg per blade and
|Δtorque| < 0.05 N m at every step. ROSCO reads its inputs in single precision; the azimuth's float32
resolution below 2π is 4.8e-7 rad, which on an IPC amplitude of at most 0.3 rad is 1.4e-7 rad = 8e-6 deg;
the moments' relative resolution 6e-8 enters the integrators proportionally. Observed: 3.4e-6 deg and
3.0e-3 N m (80 s, 6401 steps per case). In the 1P + 2P case with offsets, shifting our azimuth by 1 mrad,
flipping the sign of the azimuth offset, dropping the root-moment band-pass or feeding ROSCO's unset 2P yaw
input with the real 2P yaw moment changes the commands by 0.011, 2.4, 8.3 and 0.30 deg: the tolerance
resolves each convention.
"""

from __future__ import annotations


import numpy as np
import pytest
from _ctrl_data import DECK, discon_variant, need
from _measurements import ipc_sweep

from mbsym.exceptions import ControllerError, DimensionError, OpenFASTFormatError
from mbsym.wind.control import BaselineController, DisconController
from mbsym.wind.control.ipc import coleman, coleman_inverse
from mbsym.wind.control.swap import COMMAND_RECORDS, MEASUREMENT_RECORDS

PITCH_TOL_DEG, TORQUE_TOL = 1e-4, 0.05
GAINS = {"IPC_KP": "1e-9 5e-10", "IPC_KI": "5.2e-9 2.6e-9"}


def _variant(tmp_path, changes):
    """The shared NREL 5 MW DISCON.IN with the values of some keys replaced (vectors as one string)."""
    return discon_variant(tmp_path, changes)


def _rosco(lib, discon, t, y, names, commands, dt):
    out = np.empty((t.size, len(commands)))
    with DisconController(lib, discon, dt=dt, individual_pitch=True) as ctrl:
        for k in range(t.size):
            u = ctrl.step(t[k], dict(zip(names, y[k])))
            out[k] = [u[name] for name in commands]
    return out


@pytest.mark.parametrize("changes", [
    {"IPC_ControlMode": 1, "IPC_SatMode": 2, "IPC_KP": "0.0 0.0", "IPC_KI": "5.2e-9 0.0"},
    {"IPC_ControlMode": 2, "IPC_SatMode": 0, **GAINS, "IPC_aziOffset": "0.1 -0.2", "IPC_CornerFreqAct": 2.0},
    {"IPC_ControlMode": 2, "IPC_SatMode": 1, **GAINS},
    {"IPC_ControlMode": 1, "IPC_SatMode": 3, **GAINS, "IPC_CornerFreqAct": 1.0},
], ids=["1P-soft-PC_MinPit", "1P2P-no-sat-offsets-filter", "1P2P-hard-sat", "1P-soft-peak-shaving-filter"])
def test_ipc_open_loop_tracks_rosco(rosco_lib, tmp_path, changes):
    discon = _variant(tmp_path, {k: str(v) for k, v in changes.items()})
    dt = 0.0125
    t, y = ipc_sweep(dt, t_end=80.0)
    ctrl = BaselineController.from_discon(discon, dt=float(np.float32(dt)))
    assert ctrl.commands == ("BlPitchCom1", "BlPitchCom2", "BlPitchCom3", "GenTqCom")
    ours, _ = ctrl.run(y)
    rosco = _rosco(rosco_lib, discon, t, y, ctrl.measurements, ctrl.commands, dt)
    dp, dq = np.rad2deg(ours[:, :3] - rosco[:, :3]), ours[:, 3] - rosco[:, 3]
    stats = {"pitch_max_deg": float(np.max(np.abs(dp))), "torque_max": float(np.max(np.abs(dq)))}
    assert stats["pitch_max_deg"] < PITCH_TOL_DEG, stats
    assert stats["torque_max"] < TORQUE_TOL, stats
    # the case exercises IPC: the blades' commands differ by far more than the tolerance (observed 0.29 deg
    # with the soft peak-shaving limit, which keeps IPC within the collective's small margin above the minimum
    # pitch, 6.8 to 14 deg otherwise), and not at the first call (ROSCO's initialization)
    spread = np.rad2deg(np.max(rosco[:, :3], axis=1) - np.min(rosco[:, :3], axis=1))
    assert spread.max() > 0.2 and spread[0] == 0.0


def test_coleman_transform_recovers_tilt_and_yaw():
    # a 1P moment A cos(ψ_k − θ) on blade k at ψ_k = ψ + (k − 1)·120° has tilt A cos θ and yaw A sin θ;
    # a 2P moment A cos(2ψ_k − θ) has 2P axes A cos θ, A sin θ; the inverse transform gives back the moments.
    # ROSCO's π (3.14159265359) differs from π by 2e-13: the tolerance (1e-9 relative).
    amp, theta = 2.0e6, 0.7
    for psi in np.linspace(0.0, 2 * np.pi, 7):
        for n in (1, 2):
            m = [amp * np.cos(n * (psi + 2 * np.pi * k / 3) - theta) for k in range(3)]
            tilt, yaw = (float(v) for v in coleman(m, psi, n))
            assert tilt == pytest.approx(amp * np.cos(theta), rel=1e-9)
            assert yaw == pytest.approx(amp * np.sin(theta), rel=1e-9)
            back = [float(v) for v in coleman_inverse(tilt, yaw, psi, n, 0.0)]
            np.testing.assert_allclose(back, m, rtol=0, atol=1e-9 * amp)


def test_zero_ipc_gains_reproduce_the_collective_controller(tmp_path):
    # IPC on with zero gains: every blade gets the collective command (the controller's pitch is then the
    # mean of three equal commands: equal to one of them up to one rounding, 1e-15 relative)
    discon = _variant(tmp_path, {"IPC_ControlMode": "2", "IPC_CornerFreqAct": "1.0"})
    collective = BaselineController.from_discon(need(DECK / "DISCON.IN"), dt=0.0125)
    ipc = BaselineController.from_discon(discon, dt=0.0125)
    _, y = ipc_sweep(0.0125, t_end=40.0)
    a, _ = collective.run(y[:, :5])
    b, _ = ipc.run(y)
    assert np.max(np.abs(b[:, :3] - a[:, [0]])) < 1e-12 and np.max(np.abs(b[:, 3] - a[:, 1])) < 1e-6
    assert np.ptp(np.rad2deg(a[:, 0])) > 0.5                  # the pitch moves: the comparison is not vacuous


def test_names_wire_the_plant_to_the_discon_records(discon_in, tmp_path):
    off = BaselineController.from_discon(discon_in, dt=0.0125)
    assert off.measurements == off.measurement_names == BaselineController.measurement_names == \
        ("GenSpeed", "RotSpeed", "BldPitch1", "GenPwr", "Wind1VelX")
    assert off.commands == ("BlPitchCom", "GenTqCom") and off.function.size1_in(1) == 5
    on = BaselineController.from_discon(_variant(tmp_path, {"IPC_ControlMode": "1"}), dt=0.0125)
    assert on.measurements == off.measurements + ("RootMyc1", "RootMyc2", "RootMyc3", "Azimuth")
    assert set(on.measurements) <= set(MEASUREMENT_RECORDS) and set(on.commands) <= set(COMMAND_RECORDS)
    assert on.function.size1_in(1) == 9 and on.function.size1_out(1) == 4
    assert len(on.diagnostic_names) == on.diagnostics.size1_out(0)
    with pytest.raises(DimensionError, match="RootMyc1"):
        on.run(np.zeros((3, 5)))


def test_ipc_values_the_baseline_does_not_model_are_refused(tmp_path):
    with pytest.raises(ControllerError, match=r"line 72, key 'IPC_Vramp'.*start < end"):
        BaselineController.from_discon(_variant(tmp_path, {"IPC_ControlMode": "1", "IPC_Vramp": "11.4 9.12"}),
                                       dt=0.0125)
    with pytest.raises(OpenFASTFormatError, match=r"line 73, key 'IPC_SatMode'"):
        BaselineController.from_discon(_variant(tmp_path, {"IPC_ControlMode": "1", "IPC_SatMode": "4"}), dt=0.0125)
    with pytest.raises(OpenFASTFormatError, match=r"line 76, key 'IPC_KI'"):
        BaselineController.from_discon(_variant(tmp_path, {"IPC_ControlMode": "1", "IPC_KI": "-1e-9 0"}),
                                       dt=0.0125)
    with pytest.raises(ControllerError, match="Y_ControlMode = 2"):
        BaselineController.from_discon(_variant(tmp_path, {"IPC_ControlMode": "1", "Y_ControlMode": "2"}),
                                       dt=0.0125)
