"""Linear models of the operating turbine as a control designer uses them (issue 22, items 3 and 4).

References (independent of the code under test):
- the transfer functions without the free azimuth equal those with it at every frequency (removing a
  state that nothing depends on is exact): |ΔG(jω)| <= 1e-9 |G(jω)| at ω = 1e-3 … 10 rad/s (round-off
  of two (jωI - A)⁻¹ solves, condition ~1e6);
- ``dcgain`` equals the frequency response at ω = 1e-7 rad/s within 1e-4 (the slowest pole is
  0.097 rad/s: the first-order term of G(jω) - G(0) is jω Σ r/λ², relative size ~ a few ω/0.097 ~ 1e-5);
- one unit per quantity: the pitch actuator has unit static gain, so ``dcgain(BldPitch1, BlPitchCom)``
  is 1 (57.3 with rad in and deg out), and ``RotSpeed`` is the state ``GeAz_d`` (C entry 1, rad/s both);
- the modes are the eigenvalues of A (numpy, to 1e-9 relative); the pitch actuator's mode has the
  actuator's own natural frequency and damping (ActuatorSettings, closed form: a decoupled second-order
  lag) and the torque actuator's the rate 1/τ, to 1e-6; tower modes 0.31-0.34 Hz (NREL/TP-500-38060
  Table 9-1: 0.3240 and 0.3120 Hz, within the 3 % of test_trim_linear).
"""

from __future__ import annotations

import io
import json
import math
from contextlib import redirect_stdout

import numpy as np
import pytest

from mbsym.exceptions import ModelDefinitionError
from mbsym.wind.analysis.trim_linear import mode_label

control = pytest.importorskip("control")


@pytest.fixture(scope="module")
def point(trimmed_14):
    return trimmed_14


@pytest.fixture(scope="module")
def lin(point):
    return point.linearize()[0]


def test_azimuth_left_out_and_transfer_functions_unchanged(point, lin):
    kept = point.linearize(keep_azimuth=True)[0]
    assert "GeAz" in kept.states and "GeAz" not in lin.states and "GeAz_d" in lin.states
    assert lin.operating_point["removed_states"].keys() == {"GeAz"}
    full, reduced = kept.to_statespace(), lin.to_statespace()
    for w in (1e-3, 1e-1, 2.0, 10.0):
        g_full, g_red = full(1j * w), reduced(1j * w)
        assert np.max(np.abs(g_full - g_red)) <= 1e-9 * np.max(np.abs(g_full)), w


def test_campbell_labels_with_or_without_the_azimuth(point, lin):
    """The Campbell labelling (structural block by state name) gives the same modes either way (the eigenvalues
    of the tower modes do not depend on the integrator state GeAz: 1e-9)."""
    from mbsym.wind.analysis.campbell_diagram import DOF_LABELS
    from mbsym.wind.analysis.trim_linear import _labelled_modes

    coords = point.trimmer.model.structure.eom.coordinates
    kept = _labelled_modes(point.linearize(keep_azimuth=True)[0], coords, DOF_LABELS)
    reduced = _labelled_modes(lin, coords, DOF_LABELS)
    assert sorted(kept[0]) == sorted(reduced[0]) and {"1st tower fore-aft", "1st tower side-side"} <= set(kept[0])
    order_k, order_r = np.argsort(kept[0]), np.argsort(reduced[0])
    np.testing.assert_allclose(np.asarray(kept[1])[order_k], np.asarray(reduced[1])[order_r], rtol=1e-9)
    np.testing.assert_allclose(np.asarray(kept[2])[order_k], np.asarray(reduced[2])[order_r], rtol=1e-7)


def test_dcgain_matches_the_low_frequency_response(lin):
    ss = lin.to_statespace()
    for out, inp in (("RotSpeed", "BlPitchCom"), ("GenPwr", "GenTqCom"), ("TTDspFA", "Wind1VelX")):
        g0 = ss[out, inp].dcgain()
        g_low = ss[out, inp](1e-7j)
        assert np.isfinite(g0) and g0 != 0.0, (out, inp)
        assert abs(g_low - g0) <= 1e-4 * abs(g0), (out, inp, g0, g_low)
    assert ss["RotSpeed", "BlPitchCom"].dcgain() < 0          # more pitch, less torque, slower rotor


def test_one_unit_per_quantity(lin):
    units = dict(zip(lin.outputs, lin.output_units))
    inputs = dict(zip(lin.inputs, lin.input_units))
    assert inputs["BlPitchCom"] == units["BldPitch1"] == lin.units["BlPitch"] == "rad"
    assert units["RotSpeed"] == lin.units["GeAz_d"] == "rad/s" and units["GenPwr"] == "W"
    ss = lin.to_statespace()
    assert ss["BldPitch1", "BlPitchCom"].dcgain() == pytest.approx(1.0, rel=1e-9)
    assert lin.Cy[lin.outputs.index("RotSpeed"), lin.states.index("GeAz_d")] == pytest.approx(1.0, rel=1e-12)
    text = repr(lin)
    assert "BlPitchCom [rad]" in text and "BldPitch1 [rad]" in text and "RotSpeed [rad/s]" in text
    assert all(f"{s} [{lin.units[s]}]" in text for s in lin.states)           # every state, with its unit
    assert "and their speeds" not in text


def test_every_mode_labelled_by_its_state(operating, lin):
    modes = lin.modes()
    lam = np.linalg.eigvals(lin.A)
    lam = lam[lam.imag >= 0]
    assert len(modes) == lam.size
    np.testing.assert_allclose(sorted(m.freq_hz for m in modes), sorted(np.abs(lam) / (2 * math.pi)), rtol=1e-9)
    for m in modes:
        assert sum(m.participation.values()) == pytest.approx(1.0, abs=1e-12)
    by = {mode_label(m): m for m in modes}
    act = operating.actuators
    pitch, torque = by["pitch actuator"], by["generator-torque actuator"]
    assert pitch.freq_hz == pytest.approx(act.pitch_frequency / (2 * math.pi), rel=1e-6)
    assert pitch.damping_ratio == pytest.approx(act.pitch_damping, rel=1e-6)
    assert torque.freq_hz == pytest.approx(1 / act.torque_time_constant / (2 * math.pi), rel=1e-6)
    assert 0.31 < by["1st tower fore-aft"].freq_hz < 0.34 and 0.30 < by["1st tower side-side"].freq_hz < 0.34
    assert {"rotor speed", "dynamic inflow (DBEMT_w)", "dynamic inflow (DBEMT_v)"} <= set(by)
    assert len(by) == len(modes)                                              # one label per mode
    labels = lin.frequencies().labels
    assert "BlPitch" in labels and "GenTq" in labels and labels.count("TFA1") == 1


def test_state_that_matters_is_not_dropped(lin):
    A = np.zeros((len(lin.states), len(lin.states)))
    A[0, lin.states.index("GeAz_d")] = 1.0                 # TFA1 depends on the rotor speed state
    model = lin.__class__(**{**lin.__dict__, "A": A})
    with pytest.raises(ModelDefinitionError, match="GeAz_d"):
        model.without_states(["GeAz_d"])


def test_linearize_wind_json_contract():
    from mbsym.cli import main

    out = io.StringIO()
    with redirect_stdout(out):
        assert main(["linearize", "--wind", "14", "--json"]) == 0
    report = json.loads(out.getvalue().strip().splitlines()[-1])
    n, m, p = len(report["states"]), len(report["inputs"]), len(report["outputs"])
    assert {"BlPitchCom", "GenTqCom", "Wind1VelX"} <= set(report["inputs"])
    assert {"RotSpeed", "GenPwr", "TTDspFA"} <= set(report["outputs"])
    assert "GeAz" not in report["states"]
    assert np.shape(report["A"]) == (n, n) and np.shape(report["B"]) == (n, m)
    assert np.shape(report["C"]) == (p, n) and np.shape(report["D"]) == (p, m)
    lam = np.linalg.eigvals(np.array(report["A"]))
    assert len(report["modes"]) == int(np.sum(lam.imag >= 0))
    for mode in report["modes"]:
        assert {"freq_hz", "damping_ratio", "dominant_dof", "label"} <= set(mode)
    labels = [mode["label"] for mode in report["modes"]]
    assert "pitch actuator" in labels and "1st tower fore-aft" in labels
    assert len(set(labels)) == len(labels)                      # numbered where one state leads several modes
    assert report["units"]["inputs"][report["inputs"].index("BlPitchCom")] == "rad"
    assert report["units"]["outputs"][report["outputs"].index("BldPitch1")] == "rad"


def test_linearize_wind_refuses_structural_flags():
    from mbsym.cli import main

    err = io.StringIO()
    from contextlib import redirect_stderr

    with redirect_stderr(err):
        assert main(["linearize", "--wind", "14", "--rpm", "10"]) == 2
    assert "--rpm" in err.getvalue()
    with redirect_stderr(err):
        assert main(["linearize", "--wind", "8,14"]) == 2
    assert "one wind speed" in err.getvalue()
    with redirect_stderr(err):
        assert main(["linearize", "--keep-azimuth"]) == 2


def test_linearize_wind_on_a_full_field_deck_with_flexible_blades():
    """The shared ff14_flex deck (flexible blades, drivetrain, 2 tower modes; a TurbSim field in its InflowWind):
    the trim at --wind U ignores the deck's field (before: refused, "takes a hub-height wind"), and the blades make
    the model depend on the azimuth, so it is averaged over 12 azimuths in multi-blade coordinates (before: refused,
    the azimuth could not be left out). References: the cyclic flap modes in the fixed frame are the rotating-frame
    mode shifted by ±Ω (backward and forward whirl): their frequencies differ by 2Ω = 0.403 Hz at 12.1 rpm, here to
    2 % (the rotor's coupling moves them a little); the modes are the eigenvalues of A."""
    from _op_data import INPUTS, need
    from mbsym.cli import main

    from contextlib import redirect_stderr

    fst = need(INPUTS / "ff14_flex" / "ff14_flex.fst")
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        assert main(["linearize", str(fst), "--wind", "14", "--json"]) == 0
    assert "no aerodynamic load on blade" in err.getvalue()                # the rung is said
    report = json.loads(out.getvalue().strip().splitlines()[-1])
    states = report["states"]
    assert "GeAz" not in states and {"F1_coll", "F1_cos", "F1_sin", "E1_coll", "DrTr"} <= set(states)
    lam = np.linalg.eigvals(np.array(report["A"]))
    lam = lam[lam.imag >= 0]
    np.testing.assert_allclose(sorted(m["freq_hz"] for m in report["modes"]), sorted(np.abs(lam) / (2 * math.pi)),
                               rtol=1e-9, atol=1e-12)
    flap = sorted(m["freq_hz"] for m in report["modes"] if m["label"].startswith("1st flap cyclic"))
    assert len(flap) == 2 and flap[1] - flap[0] == pytest.approx(2 * 12.1 / 60, rel=0.02)
    whirl = {m["label"]: m["freq_hz"] for m in report["modes"] if m["label"].startswith("1st flap cyclic")}
    assert whirl == {"1st flap cyclic (backward whirl)": flap[0], "1st flap cyclic (forward whirl)": flap[1]}
    labels = {m["label"] for m in report["modes"]}
    assert {"1st flap collective", "1st tower fore-aft", "drivetrain torsion", "pitch actuator"} <= labels
    assert len(labels) == len(report["modes"])      # the second mode DrTr leads (3.9 Hz): "drivetrain torsion (2)"
    out = io.StringIO()
    with redirect_stdout(out), redirect_stderr(io.StringIO()):                 # the closed loop too
        assert main(["linearize", str(fst), "--wind", "14", "--closed-loop", "--json"]) == 0
    loop = json.loads(out.getvalue().strip().splitlines()[-1])
    assert loop["success"] == [True] and loop["pitch_gain_margin_db"][0] > 0
    poles = [p["label"] for p in loop["closed_loop_poles"][0]]
    assert len(set(poles)) == len(poles)


@pytest.mark.slow
def test_linearize_wind_on_a_deck_with_flexible_blades(rosco_deck, tmp_path):
    """ROSCO's NREL 5 MW deck (16 DOFs: the trim runs on the MX graph). Its flexible blades make the model depend
    on the azimuth (gravity): by default it is averaged over 12 azimuths in multi-blade coordinates (the yaw mode
    carries ServoDyn's YawSpr); --keep-azimuth gives the model at the trim's azimuth in the blades' coordinates.
    References: the modes are the eigenvalues of A."""
    from contextlib import redirect_stderr

    from _op_data import runnable_rosco_deck
    from mbsym.cli import main

    fst = runnable_rosco_deck(rosco_deck, tmp_path / "deck")
    for extra, expected in (([], {"nacelle yaw", "drivetrain torsion", "1st flap collective", "pitch actuator",
                                  "1st tower fore-aft"}),
                            (["--keep-azimuth"], {"nacelle yaw", "drivetrain torsion", "blade 1 1st flap",
                                                  "pitch actuator", "1st tower fore-aft"})):
        out = io.StringIO()
        with redirect_stderr(io.StringIO()), redirect_stdout(out):
            assert main(["linearize", str(fst), "--wind", "14", "--json", *extra]) == 0
        report = json.loads(out.getvalue().strip().splitlines()[-1])
        assert ("GeAz" in report["states"]) == bool(extra)
        lam = np.linalg.eigvals(np.array(report["A"]))
        lam = lam[lam.imag >= 0]
        np.testing.assert_allclose(sorted(m["freq_hz"] for m in report["modes"]),
                                   sorted(np.abs(lam) / (2 * math.pi)), rtol=1e-9, atol=1e-12)
        assert expected <= {m["label"] for m in report["modes"]}
