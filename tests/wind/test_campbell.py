"""Multi-blade coordinates and Campbell diagrams (mbsym.wind.mbc, mbsym.wind.campbell, `mbsym campbell`).

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
from mbsym.wind.campbell import blade_groups, campbell, fixed_frame_modes
from mbsym.wind.mbc import coleman_matrices, mbc_second_order, mbc_transform, whirl_components
from mbsym.wind.turbine import TurbineModel

CASE = Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "cases" / "blade_campbell"
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
    groups, _ = blade_groups(eom.coordinates)
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
    groups, _ = blade_groups(eom.coordinates)
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
    groups, _ = blade_groups(eom.coordinates)
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


# ---------------------------------------------------------------- labels on a whole turbine
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
    assert _cli(["campbell", str(deck), "--rpm", "0, 12", "--azimuths", "3"]) == 0
    out = capsys.readouterr().out
    assert "1st flap collective" in out and "frequency [Hz]" in out and "12.00" in out
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
