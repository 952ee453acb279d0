"""The baseline controller's floating feedback (ROSCO ``Fl_Mode 2`` and ``1``) and pitch actuator model (``PA_Mode 2``).

References:

* the floating feedback chain against an independent construction: scipy's bilinear transform of the
  continuous filters ROSCO names (second-order low-pass ω²/(s² + 2ζωs + ω²), high-pass s/(s + ω), notch
  (s² + 2β_num ω s + ω²)/(s² + 2β_den ω s + ω²)), ``lfilter``, a forward-Euler sum for ROSCO's integrator
  and ``−Kp``; both in double precision, so 1e-12 rad absolute (rounding) is required;
* the whole controller, open loop, against the ROSCO 2.10.6 library with the IEA 15 MW VolturnUS-S
  ``DISCON.IN`` (TSR tracking, peak shaving, Fl_Mode 2, PA_Mode 2; and the same file with Fl_Mode 1, the
  translational feedback of the tower top's acceleration turned by the nacelle yaw), same measurement
  sequence; ROSCO works
  on a float32 swap array, so the tolerances of test_baseline_vs_rosco.py apply (|Δpitch| < 1e-4 deg).
  Skips without the library.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from _ctrl_data import SHARED, need
from mbsym.wind.control import BaselineController, DisconController

DISCON = SHARED / "openfast" / "floating" / "IEA-15-240-RWT-UMaineSemi" / "IEA-15-240-RWT-UMaineSemi_DISCON.IN"
DT = float(np.float32(0.025))              # the deck's ServoDyn DLL_DT = "default" = the .fst's DT
PITCH_TOL_DEG = 1e-4                       # float32 ROSCO vs double (test_baseline_vs_rosco.py)


def _measurements(n: int) -> np.ndarray:
    """Rated operation at 13 m/s with a generator-speed wobble and a platform pitching acceleration of the
    pitch (28.9 s) and tower (≈ 2 s) periods, as the floating feedback sees in a run."""
    t = DT * np.arange(n)
    gen = 0.7917 * (1.0 + 0.01 * np.sin(2 * np.pi * t / 40.0))
    acc = 2e-3 * np.sin(2 * np.pi * t / 28.9) + 5e-4 * np.sin(2 * np.pi * t / 2.0)
    return np.column_stack([gen, gen, np.full(n, np.deg2rad(8.2)), np.full(n, 15.0e6), np.full(n, 13.0), acc])


def test_floating_feedback_is_rosco_filter_chain():
    from scipy.signal import bilinear, lfilter

    ctrl = BaselineController.from_discon(need(DISCON), dt=DT)
    s = ctrl.settings
    assert s.floating_mode == 2 and ctrl.measurements[-1] == "NcIMURAys"
    y = _measurements(3000)
    _, states = ctrl.run(y)
    diag = np.asarray(ctrl.diagnostics.map(y.shape[0])(states[:-1].T, y.T)).T
    fl = diag[:, ctrl.diagnostic_names.index("Fl_PitCom")]
    fs = 1.0 / DT
    u = y[:, -1].copy()
    u[0] = 0.0                                            # ROSCO zeroes the acceleration at its first call
    w, z = s.floating_filter_corner, s.floating_filter_damping
    u = lfilter(*bilinear([w * w], [1.0, 2 * z * w, w * w], fs), u)
    u = lfilter(*bilinear([1.0, 0.0], [1.0, s.floating_highpass_corner], fs), u)
    for wn, bn, bd in zip(s.tower_notch_freqs, s.tower_notch_beta_num, s.tower_notch_beta_den):
        u = lfilter(*bilinear([1.0, 2 * bn * wn, wn * wn], [1.0, 2 * bd * wn, wn * wn], fs), u)
    velocity = DT * np.cumsum(u)
    expected = -velocity * s.floating_kp[0]
    assert len(s.tower_notch_freqs) == 1 and np.ptp(expected) > 1e-3          # the chain is exercised
    assert np.max(np.abs(fl - expected)) < 1e-12


def _check_against_library(rosco_lib, discon: Path, y: np.ndarray) -> None:
    """Our controller and the ROSCO library on the same measurements: |Δpitch| < PITCH_TOL_DEG; and the case
    moves the pitch through the feedback (without it the command would differ by more than 100× that)."""
    ctrl = BaselineController.from_discon(discon, dt=DT)
    ours, _ = ctrl.run(y)
    rosco = np.empty_like(ours)
    with DisconController(rosco_lib, discon, dt=DT) as lib:
        for k in range(y.shape[0]):
            u = lib.step(k * DT, dict(zip(ctrl.measurements, y[k])))
            rosco[k] = u["BlPitchCom1"], u["GenTqCom"]
    dp = np.rad2deg(ours[:, 0] - rosco[:, 0])
    print(f"max |dpitch| {np.max(np.abs(dp)):.2e} deg, max |dtorque| {np.max(np.abs(ours[:, 1] - rosco[:, 1])):.2e} "
          "N m")
    assert np.max(np.abs(dp)) < PITCH_TOL_DEG, np.max(np.abs(dp))
    no_fl = BaselineController(ctrl.settings.replace(floating_mode=0)).run(y[:, :5])[0]
    assert np.max(np.abs(np.rad2deg(no_fl[:, 0] - rosco[:, 0]))) > 100 * PITCH_TOL_DEG


def test_floating_controller_matches_rosco_library(rosco_lib):
    _check_against_library(rosco_lib, need(DISCON), _measurements(4000))


def _translational(tmp_path) -> Path:
    """The VolturnUS-S DISCON.IN with Fl_Mode 1 (its table path made absolute)."""
    text = need(DISCON).read_text().replace("2                   ! Fl_Mode", "1                   ! Fl_Mode")
    assert text != DISCON.read_text()
    table = DISCON.parent.parent / "IEA-15-240-RWT" / "Cp_Ct_Cq.IEA15MW.txt"
    (tmp_path / "DISCON.IN").write_text(text.replace('"../IEA-15-240-RWT/Cp_Ct_Cq.IEA15MW.txt"', f'"{table}"'))
    return tmp_path / "DISCON.IN"


def _translational_measurements(n: int) -> np.ndarray:
    """As :func:`_measurements`, with the tower top's fore-aft and side-side accelerations [m/s²] (platform pitch
    and tower periods) and a nacelle yaw of 8° (ROSCO turns the two into the nacelle's fore-aft one)."""
    t = DT * np.arange(n)
    base = _measurements(n)[:, :5]
    ax = 0.05 * np.sin(2 * np.pi * t / 28.9) + 0.02 * np.sin(2 * np.pi * t / 2.0)
    ay = 0.03 * np.sin(2 * np.pi * t / 9.0)
    return np.column_stack([base, ax, ay, np.full(n, np.deg2rad(8.0))])


def test_translational_feedback_is_rosco_filter_chain(tmp_path):
    """Fl_Mode 1: the same chain on ``ax cos(yaw) + ay sin(yaw)`` (ROSCO's FA_Acc_Nac); rounding: 1e-12 of the
    feedback's range (here 1.7 rad: the Fl_Mode 2 gain on an acceleration in m/s²)."""
    from scipy.signal import bilinear, lfilter

    ctrl = BaselineController.from_discon(_translational(tmp_path), dt=DT)
    s = ctrl.settings
    assert s.floating_mode == 1 and ctrl.measurements[-3:] == ("YawBrTAxp", "YawBrTAyp", "NacYaw")
    assert ctrl.diagnostic_names[-3:] == ("FA_AccF", "FA_vel", "Fl_PitCom")
    y = _translational_measurements(3000)
    _, states = ctrl.run(y)
    diag = np.asarray(ctrl.diagnostics.map(y.shape[0])(states[:-1].T, y.T)).T
    fl = diag[:, ctrl.diagnostic_names.index("Fl_PitCom")]
    fs = 1.0 / DT
    u = y[:, -3] * np.cos(y[:, -1]) + y[:, -2] * np.sin(y[:, -1])
    u[0] = 0.0
    w, z = s.floating_filter_corner, s.floating_filter_damping
    u = lfilter(*bilinear([w * w], [1.0, 2 * z * w, w * w], fs), u)
    u = lfilter(*bilinear([1.0, 0.0], [1.0, s.floating_highpass_corner], fs), u)
    for wn, bn, bd in zip(s.tower_notch_freqs, s.tower_notch_beta_num, s.tower_notch_beta_den):
        u = lfilter(*bilinear([1.0, 2 * bn * wn, wn * wn], [1.0, 2 * bd * wn, wn * wn], fs), u)
    expected = -DT * np.cumsum(u) * s.floating_kp[0]
    assert np.ptp(expected) > 1e-3
    assert np.max(np.abs(fl - expected)) < 1e-12 * max(1.0, np.ptp(expected))
    units = dict(zip(ctrl.state_names, ctrl.state_units))
    assert units["floating_integral"] == "m/s" and units["floating_lowpass[0]"] == "m/s^2"


def test_translational_controller_matches_rosco_library(rosco_lib, tmp_path):
    """Fl_Mode 1 against the library (records 53, 54 and 37 filled from the measurements), |Δpitch| < 1e-4°."""
    _check_against_library(rosco_lib, _translational(tmp_path), _translational_measurements(4000))


def test_unsupported_modes_are_refused(tmp_path):
    from mbsym.exceptions import ControllerError, ParameterError

    ctrl = BaselineController.from_discon(need(DISCON), dt=DT)
    with pytest.raises(ParameterError, match="floating_mode must be 0"):
        ctrl.settings.replace(floating_mode=3)
    text = need(DISCON).read_text().replace("0                   ! TRA_Mode", "1                   ! TRA_Mode")
    assert text != DISCON.read_text()
    table = DISCON.parent.parent / "IEA-15-240-RWT" / "Cp_Ct_Cq.IEA15MW.txt"
    (tmp_path / "DISCON.IN").write_text(text.replace('"../IEA-15-240-RWT/Cp_Ct_Cq.IEA15MW.txt"', f'"{table}"'))
    with pytest.raises(ControllerError, match=r"line \d+, key 'TRA_Mode': TRA_Mode = 1 is not supported"):
        BaselineController.from_discon(tmp_path / "DISCON.IN", dt=DT)
