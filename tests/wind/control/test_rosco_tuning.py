"""ROSCO-style tuning: the gains of the NREL 5 MW DISCON.IN recomputed from the same Cp table.

References: ROSCO 2.10.6's NREL 5 MW ``DISCON.IN`` (written by ROSCO's tuning from ``Cp_Ct_Cq.NREL5MW.txt``)
and the tuning inputs of ROSCO's ``Tune_Cases/NREL5MW.yaml`` (public, NREL/ROSCO repository): rotor inertia
38 677 040.613 kg m² + generator inertia 534.116 kg m² × 97² (= WE_Jtot of the file), rated rotor speed
1.26711 rad/s, cut-in/rated/cut-out 3/11.4/25 m/s, pitch loop ω = 0.6 rad/s and ζ = 0.7, torque loop
ω = 0.15 rad/s and ζ = 0.7, peak shaving at 80 % of the maximum thrust; R = 63 m, ρ = 1.225 kg/m³.

Tolerances are the file's printing precision: PC_GS_angles has 3 decimals (±5e-4 rad), PC_GS_KP/KI and
WE_FOPoles 4 significant digits (±5e-4 relative), PS_BldPitchMin 4 decimals, VS_KP/KI and VS_Rgn2K 6
significant digits.
"""

from __future__ import annotations

import numpy as np
import pytest

from _measurements import synthetic_sweep
from _ctrl_data import DECK, need
from mbsym.wind.control import BaselineController
from mbsym.wind.control.tuning import pi_gains, tune_rosco
from mbsym.wind.deck.discon_in import read_discon_in
from mbsym.wind.deck.performance import read_performance_table


@pytest.fixture(scope="module")
def reference():
    d = read_discon_in(need(DECK / "DISCON.IN"))
    table = read_performance_table(d.performance_file)
    tuned = tune_rosco(table, rotor_radius=63.0, drivetrain_inertia=38677040.613 + 534.116 * 97.0**2,
                       gearbox_ratio=97.0, rated_rotor_speed=1.26711, rated_power=5.0e6, air_density=1.225,
                       cut_in=3.0, rated_wind_speed=11.4, cut_out=25.0, pitch_frequency=0.6, pitch_damping=0.7,
                       torque_frequency=0.15, torque_damping=0.7, peak_shaving=0.8)
    return d, tuned


def test_pitch_gain_schedule_reproduces_discon_in(reference):
    d, tuned = reference
    assert tuned.schedule_pitch.size == d["PC_GS_n"] == 30
    assert np.max(np.abs(tuned.schedule_pitch - d["PC_GS_angles"])) <= 6e-4   # ±5e-4 printing + 1e-4
    for ours, key in ((tuned.schedule_kp, "PC_GS_KP"), (tuned.schedule_ki, "PC_GS_KI")):
        assert np.max(np.abs(ours / d[key] - 1.0)) <= 5e-4, key


def test_torque_gains_k_and_estimator_poles_reproduce_discon_in(reference):
    d, tuned = reference
    assert tuned.torque_kp == pytest.approx(d["VS_KP"][0], rel=1e-5)
    assert tuned.torque_ki == pytest.approx(d["VS_KI"][0], rel=1e-5)
    assert tuned.region2_gain == pytest.approx(d["VS_Rgn2K"], rel=1e-5)
    assert tuned.optimal_tsr == d["VS_TSRopt"] and tuned.fine_pitch == d["PC_FinePit"]
    assert np.max(np.abs(tuned.wind_speed - d["WE_FOPoles_v"])) <= 5e-4
    assert np.max(np.abs(tuned.A / d["WE_FOPoles"] - 1.0)) <= 5e-4


def test_peak_shaving_schedule_reproduces_discon_in(reference):
    d, tuned = reference
    assert np.max(np.abs(tuned.wind_speed - d["PS_WindSpeeds"])) <= 5e-5
    assert np.max(np.abs(tuned.min_pitch_schedule - d["PS_BldPitchMin"])) <= 5e-5


@pytest.mark.parametrize("A, B, zeta, omega", [(-0.06, -2.15e-4, 0.7, 0.15), (0.02, -40.0, 0.7, 0.6),
                                               (-0.3, 3.0, 1.2, 2.0)])
def test_pi_gains_place_the_closed_loop_poles(A, B, zeta, omega):
    # plant x' = A x + B u, u = kp e + ki z, z' = e, e = -x: characteristic s^2 + (B kp - A) s + B ki
    kp, ki = pi_gains(A, B, zeta, omega)
    closed = np.array([[A - B * kp, B * ki], [-1.0, 0.0]])
    poles = np.linalg.eigvals(closed)
    wn = np.sqrt(np.prod(np.abs(poles)))
    assert wn == pytest.approx(omega, rel=1e-12)
    assert -np.sum(poles.real) / (2 * wn) == pytest.approx(zeta, rel=1e-12)


def test_tuned_settings_drive_the_controller_like_the_file(reference, discon_in):
    d, tuned = reference
    from_file = BaselineController.from_discon(discon_in, dt=0.0125)
    retuned = BaselineController(tuned.settings(from_file.settings))
    _, y = synthetic_sweep(0.0125, t_end=40.0)
    a, _ = from_file.run(y)
    b, _ = retuned.run(y)
    # the gains differ by the file's rounding (< 5e-4 relative): the commands by far less than their range
    assert np.max(np.abs(np.rad2deg(a[:, 0] - b[:, 0]))) < 0.01
    assert np.max(np.abs(a[:, 1] - b[:, 1])) < 0.001 * 43093.0
