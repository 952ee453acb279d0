"""Inflow choices of the operating linear model: dynamic, frozen, quasi-steady wake (issue 22, item 6).

References (independent of the code under test):
- frozen: central finite differences of the nonlinear right-hand side (Dynamics.rhs_value) with the wake
  states held at their trim values, over every other state and input (steps 1e-6 of each variable's
  scale; agreement 1e-5 of each row's largest entry: truncation O(h²) and rounding O(ε/h) are far below);
- quasi-steady: central finite differences of the right-hand side with the wake states in equilibrium
  with the perturbed state and input (the model's own equilibrium function, Øye's filter at rest:
  ``w = (1 - k) v_qs``, ``v = v_qs``), same steps and tolerance;
- OpenFAST v5.0.0 linearizations of the same turbine (tests/data/openfast_linear_inflow, CalcSteady,
  12 azimuths, frozen wake DBEMT_Mod = -1), modes by our MBC3 of its .lin files: frequencies within 1 %,
  damping ratios within 0.5 points (the r-test's rtol 1e-2 on frequencies; 0.5 points is issue 22's
  like-for-like bound, looser than the r-test's 0.1 points).
"""

from __future__ import annotations

import io
import json
from contextlib import redirect_stderr
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ArgumentTypeError, OptionError, UnsupportedFeatureError
from mbsym.wind.analysis.inflow_choice import reduce_inflow, wake_states, with_inflow
from mbsym.wind.analysis.trim_linear import linearize_point

REFERENCE = Path(__file__).resolve().parents[2] / "data" / "openfast_linear_inflow" / "modes.json"


@pytest.fixture(scope="module")
def dynamic(trimmed_14):
    return linearize_point(trimmed_14.trimmer, trimmed_14[0], keep_azimuth=True)


def _fd_columns(g, v0, scale):
    """Central differences of g about v0, one column per entry (step 1e-6 of max(|v|, 1e-2))."""
    cols = []
    for j in range(v0.size):
        h = 1e-6 * max(abs(v0[j]), 1e-2) * scale
        e = np.zeros(v0.size)
        e[j] = h
        cols.append((g(v0 + e) - g(v0 - e)) / (2 * h))
    return np.array(cols).T


def _assert_rows_close(M, M_fd, tol=1e-5):
    row = np.maximum(np.max(np.abs(M_fd), axis=1, keepdims=True), 1e-12)
    assert np.max(np.abs(M - M_fd) / row) < tol


def _split(trimmed):
    dyn = trimmed.trimmer.dyn
    point = trimmed[0]
    z = [dyn.states.index(s) for s in wake_states(dyn.states)]
    keep = [i for i in range(dyn.n_x) if i not in z]
    return dyn, point, z, keep


def test_frozen_is_the_rhs_with_the_induction_held(trimmed_14, dynamic):
    dyn, point, z, keep = _split(trimmed_14)
    assert [dyn.states[i] for i in z] == ["DBEMT_w", "DBEMT_v"]
    x0, u0, p = point.state, point.inputs, dict(point.parameters)
    frozen = with_inflow(dynamic, "frozen")
    assert frozen.states == tuple(dyn.states[i] for i in keep)
    assert frozen.operating_point["removed_states"]["DBEMT_v"] == pytest.approx(x0[z[1]], rel=1e-12)

    def rhs_x(xs):
        x = x0.copy()
        x[keep] = xs
        return dyn.rhs_value(x, u0, p)[keep]

    _assert_rows_close(frozen.A, _fd_columns(rhs_x, x0[keep], 1.0))
    _assert_rows_close(frozen.B, _fd_columns(lambda u: dyn.rhs_value(x0, u, p)[keep], u0, 1.0))


def test_quasi_steady_is_the_rhs_with_the_induction_in_equilibrium(operating, trimmed_14, dynamic):
    dyn, point, z, keep = _split(trimmed_14)
    x0, u0, p = point.state, point.inputs, dict(point.parameters)
    pv = dyn.parameter_vector(p)
    equilibrium = operating._part("inflow_steady")
    assert np.allclose(np.asarray(equilibrium(x0, u0, pv), dtype=float).ravel(), x0[z], rtol=1e-6)   # the trim

    def rhs(xs, u):
        x = x0.copy()
        x[keep] = xs
        x[z] = np.asarray(equilibrium(x, u, pv), dtype=float).ravel()
        return dyn.rhs_value(x, u, p)[keep]

    qs = with_inflow(dynamic, "quasi-steady")
    assert "DBEMT_v" not in qs.states and qs.operating_point["inflow"] == "quasi-steady"
    _assert_rows_close(qs.A, _fd_columns(lambda xs: rhs(xs, u0), x0[keep], 1.0))
    _assert_rows_close(qs.B, _fd_columns(lambda u: rhs(x0[keep], u), u0, 1.0))


def test_dynamic_is_unchanged_and_the_json_says_which(trimmed_14, dynamic):
    from mbsym.cli.linearize_operating import operating_report

    same = with_inflow(dynamic, "dynamic")
    np.testing.assert_array_equal(same.A, dynamic.A)
    assert same.states == dynamic.states
    report = operating_report(with_inflow(dynamic, "frozen"), trimmed_14[0])
    assert report["inflow"] == "frozen" and "DBEMT_w" in report["removed_states"]
    assert "DBEMT_w" not in report["states"] and np.shape(report["A"]) == (len(report["states"]),) * 2


def test_bad_inflow_choices_are_refused(trimmed_14, dynamic):
    with pytest.raises(OptionError, match="expected one of"):
        with_inflow(dynamic, "frozen-wake")
    with pytest.raises(ArgumentTypeError, match="must be a string"):
        linearize_point(trimmed_14.trimmer, trimmed_14[0], inflow=None)
    A, B, C, D = np.eye(2), np.ones((2, 1)), np.ones((1, 2)), np.zeros((1, 1))
    with pytest.raises(UnsupportedFeatureError, match="no induction states"):
        reduce_inflow(A, B, C, D, ["TFA1", "TFA1_d"], "frozen")
    with pytest.raises(UnsupportedFeatureError, match="lag the thrust"):
        reduce_inflow(A, B, C, D, ["RotThrustLag", "RotTorqLag"], "frozen")


def test_cli_inflow_needs_the_operating_model():
    from mbsym.cli import main

    err = io.StringIO()
    with redirect_stderr(err):
        assert main(["linearize", "--inflow", "frozen"]) == 2
        assert main(["linearize", "--wind", "14", "--inflow", "frozen-wake"]) == 2
    assert "--inflow frozen applies" in err.getvalue() and "expected one of" in err.getvalue()



@pytest.mark.slow
def test_cli_frozen_json_keeps_the_layout():
    """``mbsym linearize --wind 14 --inflow frozen --json``: item 3's layout, without the wake states, whose
    values are reported under removed_states; A is the dynamic model's with the wake rows and columns deleted
    (the dynamic CLI run of the same point, to round-off)."""
    from contextlib import redirect_stdout

    from mbsym.cli import main

    reports = {}
    for inflow in ("frozen", "dynamic"):
        out = io.StringIO()
        with redirect_stdout(out):
            assert main(["linearize", "--wind", "14", "--inflow", inflow, "--json"]) == 0
        reports[inflow] = json.loads(out.getvalue().strip().splitlines()[-1])
    frozen, dyn = reports["frozen"], reports["dynamic"]
    assert frozen["inflow"] == "frozen" and {"DBEMT_w", "DBEMT_v"} <= set(frozen["removed_states"])
    assert {"BlPitchCom", "GenTqCom", "Wind1VelX"} <= set(frozen["inputs"])
    assert {"RotSpeed", "GenPwr", "TTDspFA"} <= set(frozen["outputs"])
    keep = [dyn["states"].index(s) for s in frozen["states"]]
    assert frozen["states"] == [s for s in dyn["states"] if not s.startswith("DBEMT")]
    np.testing.assert_allclose(frozen["A"], np.array(dyn["A"])[np.ix_(keep, keep)], rtol=1e-12, atol=1e-12)
    for mode in frozen["modes"]:
        assert {"freq_hz", "damping_ratio", "dominant_dof", "label"} <= set(mode)

# ---------------------------------------------------------------------- against OpenFAST's own linearization
def _openfast(inflow: str, wind_speed: float) -> dict:
    table = json.loads(REFERENCE.read_text())
    case = next(c for c in table["cases"] if c["inflow"] == inflow and c["wind_speed"] == wind_speed)
    return case["modes"]


def _tower_modes(lin) -> dict:
    from mbsym.wind.analysis.trim_linear import mode_label

    return {mode_label(m): (m.freq_hz, m.damping_ratio) for m in lin.modes()
            if mode_label(m) in ("1st tower fore-aft", "1st tower side-side")}


@pytest.mark.parametrize("inflow", ["frozen", "quasi-steady"])
def test_rotor_rung_tower_frequencies_and_side_side_damping_match_openfast(dynamic, inflow):
    """Like for like at 14 m/s (OpenFAST DBEMT_Mod -1 / 0): both tower frequencies within 1 %; side-side damping
    within 0.5 points although the rotor-effective rung has no rotor side force (the structure's 0.35 % against
    OpenFAST's ~0.5 %: the aerodynamic side-side damping is small)."""
    ours, ref = _tower_modes(with_inflow(dynamic, inflow)), _openfast(inflow, 14.0)
    for label in ("1st tower fore-aft", "1st tower side-side"):
        assert ours[label][0] == pytest.approx(ref[label]["freq_hz"], rel=0.01), label
    assert abs(ours["1st tower side-side"][1] - ref["1st tower side-side"]["damping_ratio"]) <= 0.005


@pytest.fixture(scope="module")
def linearize_model():
    """The rotor-effective model ``mbsym linearize`` linearizes (the disk's moment on: turbine_and_control)."""
    from mbsym.wind.analysis.operating_points import operating_points, turbine_and_control

    model, control, _ = turbine_and_control()
    assert model.structure.hub_moments
    ops = operating_points(model, [14.0], control)
    return linearize_point(ops.trimmer, ops[0], keep_azimuth=True)


@pytest.mark.parametrize("inflow", ["frozen", "quasi-steady"])
def test_rotor_rung_fore_aft_damping_matches_openfast(dynamic, linearize_model, inflow):
    """The linear model ``mbsym linearize`` makes (the disk's moment against tilt and yaw rates: the element loads'
    slope times ω⊥ r cos ψ, docs/operation.md) at 14 m/s: the tower modes' damping within 0.5 points of OpenFAST's
    like for like (measured 7.24 % against 7.46 % frozen, 6.62 % against 6.21 % quasi-steady; side-side 0.44 %
    against 0.55 / 0.50 %). Without the disk's moment the fore-aft damping is 1.3-1.9 points low (5.57 / 4.95 %):
    the gap an earlier xfail here blamed on the surfaces' thrust slope."""
    ours, ref = _tower_modes(with_inflow(linearize_model, inflow)), _openfast(inflow, 14.0)
    for label in ("1st tower fore-aft", "1st tower side-side"):
        assert ours[label][0] == pytest.approx(ref[label]["freq_hz"], rel=0.01), label
        assert abs(ours[label][1] - ref[label]["damping_ratio"]) <= 0.005, label
    without = _tower_modes(with_inflow(dynamic, inflow))
    assert ref["1st tower fore-aft"]["damping_ratio"] - without["1st tower fore-aft"][1] > 0.01


@pytest.mark.slow
@pytest.mark.parametrize("inflow", ["frozen", "quasi-steady"])
def test_blade_rung_tower_modes_match_openfast(blade_point_14, inflow):
    """The blade-element rung (BEM and DBEMT per node, rotor side forces) at 14 m/s, like for like: both tower
    frequencies within 1 % and damping ratios within 0.5 points of OpenFAST's."""
    from mbsym.wind.analysis.blade_linear import blade_linear_model, labelled_modes

    model, point = blade_point_14
    lin = blade_linear_model(model, point, outputs=(), keep_azimuth=True, inflow=inflow)
    assert not wake_states(lin.states) and lin.operating_point["inflow"] == inflow
    ours = {lab: (f, z) for lab, f, z in zip(*labelled_modes(lin))}
    ref = _openfast(inflow, 14.0)
    for label in ("1st tower fore-aft", "1st tower side-side"):
        assert ours[label][0] == pytest.approx(ref[label]["freq_hz"], rel=0.01), label
        assert abs(ours[label][1] - ref[label]["damping_ratio"]) <= 0.005, label


@pytest.fixture(scope="module")
def blade_point_14():
    """The blade-element NREL 5 MW (GenDOF, TwFADOF1, TwSSDOF1) at its periodic point at 14 m/s, pitch and torque
    held at the rotor-effective trim of the same deck (several minutes)."""
    from _op_data import INPUTS, need

    import mbsym as mb
    from mbsym.wind.analysis.blade_periodic import periodic_point
    from mbsym.wind.operation import trim

    fst = need(INPUTS / "steady_14" / "steady_14.fst")
    dofs = ["GenDOF", "TwFADOF1", "TwSSDOF1"]
    start = trim(mb.wind.OperatingTurbine.from_openfast(fst, aero="rotor", dofs=dofs), 14.0)
    model = mb.wind.OperatingTurbine.from_openfast(fst, aero="blade", dofs=dofs)
    return model, periodic_point(model, 14.0, start=start)
