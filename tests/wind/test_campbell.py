"""Multi-blade coordinates and Campbell diagrams (mbsym.wind.structure.mbc, mbsym.wind.analysis.campbell_diagram, `mbsym campbell`).

References
----------
- OpenFAST v5 blade_campbell linearizations (shared/openfast/cases/blade_campbell/blade_campbell.csv):
  1st flap, 1st edge, 2nd flap frequencies at 0-15 rpm with the hub held. With the hub held, the
  collective modes are the rotating-frame blade modes, so the issue's contract is 0.5 % on the
  collective frequencies; we also hold them to 1e-4 (ElastoDyn's finite-difference steps leave
  ~1e-5, docs/elastodyn_notes.md §8.1) and the damping ratios to 1 %.
- Floquet/Coleman theory (Bir 2008, NREL/CP-500-42553): for a rotating-frame system that is time
  invariant (blades on a hub turning at constant Ω, nothing coupling them to the fixed frame) the
  multi-blade eigenvalues are the rotating-frame ones (collective) and the same shifted by ±iΩ
  (forward / backward whirl), exactly; an isotropic rotor coupled to a fixed-frame structure has a
  time-invariant model in multi-blade coordinates (to round-off) although its rotating-frame
  model is periodic.
- The closed form of the Coleman matrix inverse: T1⁻¹ = ⅓ [[1, 1, 1], [2cos ψ_b], [2sin ψ_b]].
- OpenFAST v5 paper46_floating_lin0 linearization (shared/openfast/cases/paper46_floating/
  paper46_floating_lin.json, "undeflected"): platform pitch 0.099825 Hz (ζ 2.351e-5) and tower
  fore-aft 0.799826 Hz (ζ 0.0045543), the latter dominated by TFA1 in OpenFAST's own eigenvector.
  r-test tolerances are 1e-2 (frequency) and 0.1 % (damping); ElastoDyn's finite differences
  (method "elastodyn-fd") reproduce them to 2e-4, so we hold the frequencies to 1e-3. The exact
  Jacobian gives 0.10066 / 0.80007 Hz (docs/elastodyn_notes.md §8.3, 5 digits: rtol 1e-4).
- A per-azimuth loop of mbsym.linearize + mbc_transform (the pre-sweep implementation) as the
  independent reference for the batched azimuth sweep (1e-9 of the matrix norm).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

import mbsym as mb
from mbsym.cli.campbell import add_parser, parse_rpm_list, run
from mbsym.exceptions import DimensionError, ModelDefinitionError, ParameterError
from mbsym.wind import nrel5mw, read_openfast
from mbsym.wind.analysis.campbell_diagram import campbell, campbell_model, fixed_frame_modes, operating_point
from mbsym.wind.structure.mbc import (blade_dof, blade_indices, coleman_matrices, mbc_coordinate_names, mbc_second_order,
                            mbc_transform, whirl_components, whirl_coordinates)
from mbsym.wind.structure.turbine import TurbineModel

CASES = Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "cases"
CASE = CASES / "blade_campbell"
RPM = [0.0, 3.0, 6.0, 9.0, 12.0, 15.0]
COLLECTIVE = {"1st flap collective": 1, "1st edge collective": 2, "2nd flap collective": 3}


def _deck():
    if not (CASE / "blade_campbell_rpm00.fst").exists():
        pytest.skip("shared OpenFAST reference data not available")
    return CASE / "blade_campbell_rpm00.fst", np.loadtxt(CASE / "blade_campbell.csv", delimiter=",", skiprows=1)


def _u(eom, **values):
    return np.array([values.get(n, 0.0) for n in eom.inputs], dtype=float)


@pytest.fixture(scope="module")
def diagram():
    deck, _ = _deck()
    return campbell(read_openfast(deck), RPM)


# ---------------------------------------------------------------- validation against OpenFAST
def test_collective_frequencies_match_openfast(diagram):
    _, ref = _deck()
    np.testing.assert_array_equal(diagram.rpm, ref[:, 0])
    for label, col in COLLECTIVE.items():
        f = diagram.mode(label).freq_hz
        assert np.all(np.abs(f / ref[:, col] - 1) <= 5e-3), label          # the contract
        np.testing.assert_allclose(f, ref[:, col], rtol=1e-4, err_msg=label)
        np.testing.assert_allclose(diagram.mode(label).damping_ratio, ref[:, col + 3], rtol=1e-2, err_msg=label)


def test_whirl_modes_are_one_p_above_and_below(diagram):
    """Damped frequencies: forward = collective + Ω/2π, backward = collective - Ω/2π (1e-9 Hz)."""
    def damped(label):
        m = diagram.mode(label)
        return m.freq_hz * np.sqrt(1 - m.damping_ratio**2)

    for label in COLLECTIVE:
        kind = label.replace(" collective", "")
        np.testing.assert_allclose(damped(f"{kind} forward whirl") - damped(label), diagram.rpm / 60, atol=1e-9)
        np.testing.assert_allclose(damped(f"{kind} backward whirl") - damped(label), -diagram.rpm / 60, atol=1e-9)
    assert len(diagram.modes) == 9 and len(set(diagram.labels)) == 9


# ---------------------------------------------------------------- MBC transformation
def test_coleman_inverse_closed_form():
    psi = 0.7
    T = coleman_matrices(4, [(1, 2, 3)], psi)
    b = psi + 2 * np.pi * np.arange(3) / 3
    inv = np.vstack([np.ones(3), 2 * np.cos(b), 2 * np.sin(b)]) / 3
    np.testing.assert_allclose(np.linalg.inv(T.T1)[1:, 1:], inv, atol=1e-14)
    assert T.T1[0, 0] == 1.0 and not T.T2[0].any()
    h = 1e-6   # T2, T3 are the azimuth derivatives of T1 (central differences, 1e-8)
    dT = (coleman_matrices(4, [(1, 2, 3)], psi + h).T1 - coleman_matrices(4, [(1, 2, 3)], psi - h).T1) / (2 * h)
    np.testing.assert_allclose(dT, T.T2, atol=1e-8)
    d2 = (coleman_matrices(4, [(1, 2, 3)], psi + h).T2 - coleman_matrices(4, [(1, 2, 3)], psi - h).T2) / (2 * h)
    np.testing.assert_allclose(d2, T.T3, atol=1e-8)


@pytest.fixture(scope="module")
def hub_held():
    """NREL 5 MW blades (F1, E1, F2) on a hub turning through the prescribed azimuth, no gravity."""
    return TurbineModel(nrel5mw(), dofs=["FlapDOF1", "EdgeDOF", "FlapDOF2"], prescribed_azimuth=True).eom


def test_hub_held_mbc_eigenvalues_are_the_rotating_ones_shifted(hub_held):
    eom = hub_held
    om, psi = 1.3, 0.4
    lin = mb.linearize(eom, np.zeros(eom.n_q), np.zeros(eom.n_q), _u(eom, GeAz=psi - np.pi / 2, GeAz_d=om),
                       {"gravity": 0.0})
    groups = blade_indices(eom.coordinates)
    lam_r = np.linalg.eigvals(lin.A)               # three identical blades: every eigenvalue thrice
    expected = np.concatenate([lam_r, lam_r + 1j * om, lam_r - 1j * om])
    lam_b = np.linalg.eigvals(mbc_transform(lin.A, groups, psi, om))
    assert lam_b.size == 18
    for a, b in ((expected, lam_b), (lam_b, expected)):
        for lam in a:
            assert np.min(np.abs(b - lam)) <= 1e-7 * abs(lam), lam


def test_second_order_transform_matches_first_order(hub_held):
    eom = hub_held
    om, psi, al = 1.1, 2.0, 0.3
    rng = np.random.default_rng(5)
    q = rng.uniform(-0.5, 0.5, eom.n_q)
    lin = mb.linearize(eom, q, rng.uniform(-0.1, 0.1, eom.n_q), _u(eom, GeAz=psi, GeAz_d=om), {"gravity": 0.0})
    groups = blade_indices(eom.coordinates)
    M, C, K = mbc_second_order(lin.M, lin.C, lin.K, groups, psi, om, rotor_acceleration=al)
    n = eom.n_q
    A2 = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    A1 = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(lin.M, lin.K), -np.linalg.solve(lin.M, lin.C)]])
    np.testing.assert_allclose(mbc_transform(A1, groups, psi, om, rotor_acceleration=al), A2,
                               atol=1e-9 * np.abs(A2).max())
    A_B, B_B = mbc_transform(lin.A, groups, psi, om, B=lin.B)
    assert B_B.shape == lin.B.shape


def test_isotropic_rotor_on_rigid_tower_is_azimuth_independent():
    """Blades, drivetrain, generator and a sprung nacelle yaw (rigid tower, tilt and precone of the
    5 MW, no gravity) at 12 rpm: the rotating-frame A changes with azimuth (the cyclic flap couples
    with yaw), the multi-blade A does not (1e-9 of its norm) and neither do its frequencies."""
    model = TurbineModel(nrel5mw(), dofs=["YawDOF", "GenDOF", "DrTrDOF", "FlapDOF1", "EdgeDOF", "FlapDOF2"],
                         yaw_spring=9.02832e9, yaw_damping=1.916e7)
    eom = model.eom
    groups = blade_indices(eom.coordinates)
    om = 12 * np.pi / 30
    i = eom.coordinates.index("GeAz")
    rot, fixed, freqs = [], [], []
    for psi in (0.0, 0.5, 1.3, 2.9, 4.4):
        q, qd = np.zeros(eom.n_q), np.zeros(eom.n_q)
        q[i], qd[i] = psi - np.pi / 2, om
        lin = mb.linearize(eom, q, qd, None, {"gravity": 0.0})
        A = mbc_transform(lin.A, groups, psi, om)
        rot.append(lin.A)
        fixed.append(A)
        lam = np.linalg.eigvals(A)
        freqs.append(np.sort(np.abs(lam[lam.imag > 1e-6])))
    scale = np.abs(fixed[0]).max()
    assert max(np.abs(r - rot[0]).max() for r in rot) > 1e-3 * np.abs(rot[0]).max()
    for A, f in zip(fixed, freqs):
        np.testing.assert_allclose(A, fixed[0], atol=1e-9 * scale)
        np.testing.assert_allclose(f, freqs[0], rtol=1e-9)


def test_whirl_components_and_bad_input():
    assert whirl_components(1.0, -1j) == (2.0, 0.0)
    f, b = whirl_components(1.0, 1j)
    assert (f, b) == (0.0, 2.0)
    f, b = whirl_components(1.0, 0.0)      # a standing (pure cosine) pattern: half each way
    assert f == b == 0.5
    with pytest.raises(ModelDefinitionError, match="3 indices"):
        coleman_matrices(4, [(0, 1)], 0.0)
    with pytest.raises(ModelDefinitionError, match="distinct and in 0..3"):
        coleman_matrices(4, [(0, 1, 4)], 0.0)
    with pytest.raises(DimensionError, match="2 n_q rows"):
        mbc_transform(np.eye(3), [(0, 1, 2)], 0.0, 1.0)
    with pytest.raises(DimensionError, match="B must have 6 rows"):
        mbc_transform(np.eye(6), [(0, 1, 2)], 0.0, 1.0, B=np.ones((3, 1)))


def test_blade_coordinate_helpers():
    """One definition of the blade coordinate names (mbc.BLADE_COORDINATE) and the triplets."""
    coords = ["TFA1", "GeAz", "B1F1", "B2F1", "B3F1", "B1E1", "B2E1", "B3E1"]
    assert blade_indices(coords) == [(2, 3, 4), (5, 6, 7)]
    assert mbc_coordinate_names(coords)[2:5] == ("F1_coll", "F1_cos", "F1_sin")
    assert blade_dof("B3F2") == (3, "F2") and blade_dof("B3F3") is None and blade_dof("TFA1") is None
    with pytest.raises(ModelDefinitionError, match="blades 1..3 for each blade DOF; F1 has blades \\[1, 2\\]"):
        mbc_coordinate_names(["B1F1", "B2F1"])
    # the forward/backward split is unitary: it keeps inner products (energies) of the pair
    rng = np.random.default_rng(2)
    u, v = rng.normal(size=(2, 2)) + 1j * rng.normal(size=(2, 2))
    (fu, bu), (fv, bv) = whirl_coordinates(*u), whirl_coordinates(*v)
    assert np.conj(fu) * fv + np.conj(bu) * bv == pytest.approx(np.vdot(u, v), rel=1e-14)


# ---------------------------------------------------------------- azimuth sweep and conventions
def test_sweep_equals_a_per_azimuth_linearize_loop():
    """fixed_frame_modes (batched mbsym.linear.linearize_azimuths + AzimuthSweep.average) against
    a plain loop of mbsym.linearize and mbc_transform at the same points (exact Jacobians): A and M̄
    to 1e-9 of their norms. Built-in NREL 5 MW (tower, yaw, generator, drivetrain, 9 blade DOFs)."""
    model = TurbineModel(nrel5mw())
    eom, n, om, n_az = model.eom, model.eom.n_q, 9 * np.pi / 30, 4
    modes = fixed_frame_modes(model, om, n_azimuth=n_az, method="exact")
    groups, i = blade_indices(eom.coordinates), eom.coordinates.index("GeAz")
    op = operating_point(model, om)
    A, M = np.zeros((2 * n, 2 * n)), np.zeros((n, n))
    for j in range(n_az):
        psi = 2 * np.pi * j / n_az                     # blade-1 azimuth (AzimB1Up = 0)
        q = op.q.copy()
        q[i] = psi - np.pi / 2
        lin = mb.linearize(model, q, op.qd, op.u, op.p, method="exact")
        A += mbc_transform(lin.A, groups, psi, om) / n_az
        T1 = coleman_matrices(n, groups, psi).T1
        M += T1.T @ lin.M @ T1 / n_az
    np.testing.assert_allclose(modes.A, A, atol=1e-9 * np.abs(A).max())
    np.testing.assert_allclose(modes.M, M, atol=1e-9 * np.abs(M).max())


def test_azimuth_convention_and_blade1_offset():
    """Blade-1 azimuth = ElastoDyn's Azimuth output, q_GeAz + AzimB1Up + π/2 (notes §5, §6): the
    operating point at azimuth ψ has q_GeAz = ψ - AzimB1Up - π/2 and the Azimuth channel reads ψ
    (1e-9 deg). A constant AzimB1Up only rotates the cyclic (cos, sin) pair (Coleman), so every
    frequency, damping ratio and label is unchanged (1e-9). Exact derivatives: ElastoDyn's large
    finite steps (0.21 m on the flap DOFs) sample the exact lumped-blade kinematics' nonlinear terms
    at other physical azimuths and move the damping by ~2e-7 relative, an artefact of the steps."""
    t = nrel5mw()
    shifted = dataclasses.replace(t, azimuth_blade1_up=0.5)
    model = TurbineModel(shifted, dofs=["YawDOF", "GenDOF", "FlapDOF1"], yaw_spring=9.02832e9)
    op = operating_point(model, 1.0, azimuth=2.0)
    assert op.q[model.eom.coordinates.index("GeAz")] == pytest.approx(np.mod(2.0 - 0.5 - np.pi / 2, 2 * np.pi))
    ch = model.output_function()
    y = np.array(ch.function(np.concatenate([op.q, op.qd]), op.u, model.eom.parameter_vector({}))).ravel()
    assert y[ch.names.index("Azimuth")] == pytest.approx(np.rad2deg(2.0), abs=1e-9)
    kw = dict(n_azimuth=6, p={"gravity": 0.0}, method="exact")
    a = campbell(TurbineModel(t, dofs=["YawDOF", "GenDOF", "FlapDOF1"], yaw_spring=9.02832e9), [4.0, 12.0], **kw)
    b = campbell(model, [4.0, 12.0], **kw)
    assert a.labels == b.labels
    for ma, mb_ in zip(a.modes, b.modes):
        np.testing.assert_allclose(mb_.freq_hz, ma.freq_hz, rtol=1e-9)
        np.testing.assert_allclose(mb_.damping_ratio, ma.damping_ratio, rtol=1e-9, atol=1e-12)


def test_operating_point_zero_support_displacements_keeps_blade_deflections():
    """Tower/platform displacements zero (OpenFAST's lin0 decks), the blades at OoPDefl = 1 m with
    ElastoDyn's 2x2 tip solve (notes §5: q_F1 = 0.9876, q_E1 = 0.1268 at zero pitch, 1e-4)."""
    t = nrel5mw()
    ic = dataclasses.replace(t.initial_conditions, tower_top_fa_displacement=0.5, platform_pitch=0.05,
                             blade_oop_tip_deflection=1.0)
    deck = dataclasses.replace(_floating(t), initial_conditions=ic)
    dofs = ["PtfmSgDOF", "PtfmPDOF", "TwFADOF1", "GenDOF", "FlapDOF1", "EdgeDOF"]
    for model in (TurbineModel(deck, dofs=dofs), campbell_model(deck, dofs)):
        op = operating_point(model, 0.5)
        q = dict(zip(model.eom.coordinates, op.q))
        assert q["TFA1"] == q["P"] == q["Sg"] == 0.0
        assert q["B2F1"] == pytest.approx(0.9876, abs=1e-4) and q["B3E1"] == pytest.approx(0.1268, abs=1e-4)
        np.testing.assert_allclose(op.qdd, model.eom.accelerations(op.q, op.qd, op.u, op.p), rtol=1e-12)
    fixed = campbell_model(deck, ["GenDOF"])           # disabled DOFs: their constants are zero too
    assert fixed.turbine.initial_conditions.platform_pitch == 0.0
    assert fixed.turbine.initial_conditions.blade_oop_tip_deflection == 1.0


def _floating(t):
    return dataclasses.replace(t, platform_mass=7.5e6, platform_roll_inertia=4.2e9, platform_pitch_inertia=4.2e9,
                               platform_yaw_inertia=1.6e8, platform_cm=(0.0, 0.0, -90.0),
                               platform_reference=(0.0, 0.0, 20.0), tower_base_height=20.0)


# ---------------------------------------------------------------- labels on a whole turbine
def _paper46():
    fst = CASES / "paper46_floating" / "paper46_floating.fst"
    if not fst.exists():
        pytest.skip("shared OpenFAST reference data not available")
    ref = json.loads((fst.parent / "paper46_floating_lin.json").read_text())["undeflected"]
    return read_openfast(fst), ref["structural_modes"]


def test_paper46_coupled_modes_labelled_by_kinetic_energy():
    """The deck's free-decay ICs (TTDspFA = 1 m, PtfmPitch = 2°) are not used: 0 rpm gives OpenFAST's
    lin0 modes. The 0.80 Hz mode (kinetic energy TFA1 >> P, Sg; OpenFAST's dominant DOF TFA1) is
    the tower's, the 0.10 Hz one the platform pitch (surge is rigid: no label)."""
    turbine, ref = _paper46()
    cd = campbell(turbine, [0.0, 5.0])
    assert set(cd.labels) == {"platform pitch", "1st tower fore-aft"}
    for label, r in zip(("platform pitch", "1st tower fore-aft"), ref):
        m = cd.mode(label)
        np.testing.assert_allclose(m.freq_hz, r["freq_natural_Hz"], rtol=1e-3, err_msg=label)
        np.testing.assert_allclose(m.damping_ratio, r["damping_ratio"], atol=1e-3, err_msg=label)
    assert "TFA1" in ref[1]["dominant_dof"]
    modes = fixed_frame_modes(campbell_model(turbine), 0.0)
    assert np.all(np.diag(modes.participation) > 0.9)
    exact = campbell(turbine, [0.0], method="exact")
    np.testing.assert_allclose([exact.mode("platform pitch").freq_hz[0], exact.mode("1st tower fore-aft").freq_hz[0]],
                               [0.10066, 0.80007], rtol=1e-4)


def test_onshore_turbine_labels_are_unique_and_named_in_words():
    """The built-in NREL 5 MW (tower 4, yaw, generator, drivetrain, 9 blade DOFs): every mode has one
    label, tower and drivetrain modes are named in words, no mode is named after the free azimuth."""
    cd = campbell(nrel5mw(), [0.0, 6.0, 12.0], n_azimuth=6)
    labels = cd.labels
    assert len(labels) == len(set(labels))
    for name in ("1st tower fore-aft", "1st tower side-side", "2nd tower fore-aft", "drivetrain torsion",
                 "1st flap collective", "1st edge backward whirl", "2nd flap forward whirl"):
        assert name in labels, name
    assert "generator azimuth" not in labels
    fa = cd.mode("1st tower fore-aft").freq_hz
    assert np.all((fa > 0.3) & (fa < 0.35))
    d = cd.to_dict()
    assert d["rpm"] == [0.0, 6.0, 12.0] and len(d["modes"]) == len(labels)
    json.dumps(d)                       # NaN-free


def test_campbell_errors():
    with pytest.raises(ParameterError, match=">= 0"):
        campbell(nrel5mw(), [-1.0])
    with pytest.raises(ParameterError, match="non-empty"):
        campbell(nrel5mw(), [])
    locked = TurbineModel(dataclasses.replace(nrel5mw(), initial_conditions=dataclasses.replace(
        nrel5mw().initial_conditions, rotor_speed=0.0)), dofs=["FlapDOF1"])
    with pytest.raises(ModelDefinitionError, match="prescribed_azimuth=True"):
        campbell(locked, [3.0])
    with pytest.raises(TypeError, match="TurbineParameters or TurbineModel"):
        campbell("deck.fst", [3.0])
    with pytest.raises(ParameterError, match="n_azimuth"):
        fixed_frame_modes(locked, 0.0, n_azimuth=0)
    with pytest.raises(ParameterError, match="unknown linearization method 'fast'"):
        campbell(nrel5mw(), [3.0], method="fast")


# ---------------------------------------------------------------- command line
def _cli(argv):
    parser = argparse.ArgumentParser(prog="mbsym")
    add_parser(parser.add_subparsers(dest="command"))
    return run(parser.parse_args(argv))


def test_cli_json_contract(capsys, tmp_path):
    deck, ref = _deck()
    png = tmp_path / "campbell.png"
    assert _cli(["campbell", str(deck), "--rpm", "0,3,6,9,12,15", "--json", "--plot", str(png)]) == 0
    out = capsys.readouterr()
    data = json.loads(out.out)                       # stdout is exactly one JSON object
    assert data["rpm"] == RPM
    by_label = {m["label"]: m for m in data["modes"]}
    for label, col in COLLECTIVE.items():
        f = np.array(by_label[label]["freq_hz"])
        assert len(by_label[label]["damping_ratio"]) == len(RPM)
        assert np.all(np.abs(f / ref[:, col] - 1) <= 5e-3), label
    assert png.stat().st_size > 1000 and "wrote" in out.err


def test_cli_table_and_bad_rpm(capsys):
    deck, _ = _deck()
    assert _cli(["campbell", str(deck), "--rpm", "0, 12", "--azimuths", "3", "--method", "exact"]) == 0
    out = capsys.readouterr().out
    assert "1st flap collective" in out and "frequency [Hz]" in out and "12.00" in out and "method exact" in out
    assert parse_rpm_list(" 1,2.5 ") == [1.0, 2.5]
    with pytest.raises(ValueError, match="comma-separated numbers"):
        parse_rpm_list("0;3")
    with pytest.raises(ValueError, match=">= 0"):
        parse_rpm_list("3,-1")


def test_cli_registered_in_mbsym_main(capsys):
    """Through the `mbsym` command once the sub-command is registered in mbsym/cli/__init__.py."""
    from mbsym.cli import build_parser, main

    choices = build_parser()._subparsers._group_actions[0].choices
    if "campbell" not in choices:
        pytest.skip("`campbell` not registered in mbsym.cli yet")
    deck, _ = _deck()
    assert main(["campbell", str(deck), "--rpm", "6", "--json", "--azimuths", "3"]) == 0
    assert json.loads(capsys.readouterr().out)["rpm"] == [6.0]
    assert main(["campbell", str(deck), "--rpm", "x"]) == 2
