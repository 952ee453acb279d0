"""SubDyn substructures: the reader, the frame FE model, Guyan/Craig-Bampton reduction, the output equation.

Reference: OpenFAST v5.0.0 runs of the IEA 15 MW monopile deck and of a made-up tripod
(``tests/data/openfast_subdyn``, see its README): the summary file's matrices (7 significant digits)
and 2 s time series of the TP motion, CB states and SubDyn's interface loads.

Measured differences over the five cases (6×6 matrices: entry (i, j) scaled by sqrt(|A_ii A_jj|)): K_BB ≤ 3.1e-7,
M_BB ≤ 4.1e-7, rigid-body mass ≤ 3.0e-7; C_BB ≤ 6.3e-8 and M_Bm ≤ 7.6e-8 of their largest entry; frequencies
(full system, Guyan, CB) ≤ 3.4e-7 relative; nodal gravity loads ≤ 3.4e-7 of the largest; the time series: TP
forces ≤ 6.6e-8 and moments ≤ 2.6e-7 of the largest, CB accelerations ≤ 1.2e-7. The tests allow 2e-6.
"""

from __future__ import annotations

import dataclasses
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ModelWarning, OpenFASTFormatError, ParameterError, UnsupportedFeatureError
from mbsym.wind.deck.subdyn import read_subdyn
from mbsym.wind.offshore.frame_fem import rigid_transform, small_rotation_angles
from mbsym.wind.offshore.substructure import Substructure

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_subdyn"
CASES = ("monopile", "monopile_cb", "monopile_eb", "tripod", "tripod_eb")
TOL = 2e-6


@pytest.fixture(scope="module")
def built():
    """case -> (summary extract, Substructure, the deck's reduction)."""
    out = {}
    for case in CASES:
        ref = json.loads((DATA / f"{case}.json").read_text())
        sub = Substructure.from_subdyn(read_subdyn(DATA / f"{case}.dat"), ref["reference_point"], ref["gravity"])
        with pytest.warns(ModelWarning, match="degenerate") if case == "monopile_cb" else _nothing():
            red = sub.reduce()
        out[case] = (ref, sub, red)
    return out


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *args):
        return False


def _scaled(a, b) -> float:
    """max |a − b| with entry (i, j) scaled by sqrt(|b_ii b_jj|) (mixed units of a 6×6 matrix)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    scale = np.sqrt(np.abs(np.outer(np.diag(b), np.diag(b))))
    return float(np.max(np.abs(a - b) / np.where(scale > 0, scale, 1.0)))


def _aligned(sub, red, subdyn_mbm):
    """``red`` with its CB modes turned into SubDyn's basis: within a group of equal frequencies LAPACK's
    eigenvectors are an arbitrary basis (the monopile's bending pairs), so each SubDyn mode is written as a
    combination of ours of the same frequency (found from M_Bm)."""
    with warnings.catch_warnings():  # the extra modes may cut another pair: only the groups of red's modes matter
        warnings.simplefilter("ignore", ModelWarning)
        big = sub.craig_bampton(red.n_modes + 2, damping_ratios=0.0)
    turn = np.zeros((big.n_modes, red.n_modes))
    for j, omega in enumerate(red.frequencies):
        group = np.flatnonzero(np.abs(big.frequencies / omega - 1.0) < 1e-4)
        turn[group, j] = np.linalg.lstsq(big.mass_coupling[:, group], subdyn_mbm[:, j], rcond=None)[0]
    return dataclasses.replace(red, mass_coupling=big.mass_coupling @ turn, modal_shapes=big.modal_shapes @ turn,
                               modal_gravity_load=turn.T @ big.modal_gravity_load)


# ---------------------------------------------------------------------------------------------- vs SubDyn
@pytest.mark.parametrize("case", CASES)
def test_tp_matrices_and_frequencies_match_subdyn_summary(built, case):
    ref, sub, red = built[case]
    assert _scaled(red.stiffness, ref["KBBt"]) < TOL
    assert _scaled(red.mass, ref["MBBt"]) < TOL
    assert np.abs(red.damping - np.array(ref["CBBt"])).max() <= TOL * np.abs(ref["CBBt"]).max()
    np.testing.assert_allclose(red.guyan_frequencies(), np.ravel(ref["GY_frequencies"]), rtol=TOL)
    np.testing.assert_allclose(sub.full_frequencies(12), ref["Full_frequencies_first12"], rtol=TOL)
    np.testing.assert_allclose(red.frequencies / (2 * math.pi), np.ravel(ref["CB_frequencies"]), rtol=TOL)
    if red.n_modes:
        np.testing.assert_allclose(np.diag(red.modal_damping), np.ravel(ref["CMMdiag"]), rtol=TOL)
        np.testing.assert_allclose(np.diag(red.modal_stiffness), np.ravel(ref["KMMdiag"]), rtol=TOL)
        mbm = sub.interface_transform.T @ np.array(ref["MBM"])  # the summary's MBM is at the interface joints
        turned = _aligned(sub, red, mbm)
        assert np.abs(turned.mass_coupling - mbm).max() < TOL * np.abs(mbm).max()


@pytest.mark.parametrize("case", CASES)
def test_gravity_mass_and_interface_transform_match_subdyn(built, case):
    ref, sub, _ = built[case]
    fg = np.ravel(ref["FG"])
    assert np.abs(sub.frame.gravity_load - fg).max() < TOL * np.abs(fg).max()
    assert _scaled(sub.rigid_body_mass(), ref["M_P"]) < TOL
    assert sub.rigid_body_mass()[0, 0] == pytest.approx(ref["Mass"], rel=TOL)
    # SubDyn prints TI with 3 digits
    np.testing.assert_allclose(sub.interface_transform, ref["TI"], atol=5e-3 * np.abs(ref["TI"]).max())


@pytest.mark.parametrize("case", CASES)
def test_output_equation_reproduces_subdyn_time_series(built, case):
    """Y1 and q̈ from the recorded TP motion and CB states equal SubDyn's −Intf1F*ss and SSqmdd."""
    ref, sub, red = built[case]
    if red.n_modes:
        red = _aligned(sub, red, sub.interface_transform.T @ np.array(ref["MBM"]))
    rows = np.genfromtxt(DATA / f"{case}.csv", delimiter=",", names=True)
    deg = math.pi / 180.0
    loads, accelerations, wanted, wanted_q = [], [], [], []
    for row in rows:
        euler = [row[f"Intf1RD{c}ss"] for c in "XYZ"]
        u = np.r_[[row[f"Intf1TD{c}ss"] for c in "XYZ"], small_rotation_angles(_euler_zyx(euler))]
        udot = np.r_[[row[f"PtfmTV{c}i"] for c in "xyz"], [deg * row[f"PtfmRV{c}i"] for c in "xyz"]]
        uddot = np.r_[[row[f"Intf1TA{c}ss"] for c in "XYZ"], [row[f"Intf1RA{c}ss"] for c in "XYZ"]]
        modes = range(1, red.n_modes + 1)
        q, qdot = [row[f"SSqm{i:02d}"] for i in modes], [row[f"SSqmd{i:02d}"] for i in modes]
        y1, qddot = red.tp_loads(u, udot, uddot, q, qdot)
        loads.append(y1)
        accelerations.append(qddot)
        wanted.append([-row[f"Intf1{c}ss"] for c in ("FX", "FY", "FZ", "MX", "MY", "MZ")])
        wanted_q.append([row[f"SSqmdd{i:02d}"] for i in modes])
    loads, wanted = np.array(loads), np.array(wanted)
    for part in (slice(0, 3), slice(3, 6)):
        assert np.abs(loads[:, part] - wanted[:, part]).max() < TOL * np.abs(wanted[:, part]).max()
    if red.n_modes:
        accelerations, wanted_q = np.array(accelerations), np.array(wanted_q)
        assert np.abs(accelerations - wanted_q).max() < TOL * np.abs(wanted_q).max()


def _euler_zyx(angles) -> np.ndarray:
    """OpenFAST's EulerConstructZYX (global → body DCM) of roll, pitch, yaw [rad]."""
    cx, sx, cy, sy, cz, sz = (f(a) for a in angles for f in (math.cos, math.sin))
    rx = np.array([[1, 0, 0], [0, cx, sx], [0, -sx, cx]])
    ry = np.array([[cy, 0, -sy], [0, 1, 0], [sy, 0, cy]])
    rz = np.array([[cz, sz, 0], [-sz, cz, 0], [0, 0, 1]])
    return rx @ ry @ rz


# ---------------------------------------------------------------------------------------------- invariants
def test_mass_is_the_pipes_closed_form_plus_the_concentrated_mass(built):
    ref, sub, _ = built["monopile"]
    settings = sub.settings
    steel = 0.0
    for member in settings.members:
        a, b = settings.section(member.prop1), settings.section(member.prop2)
        d, t = 0.5 * (a.diameter + b.diameter), 0.5 * (a.thickness + b.thickness)  # uniform but at the 1-mm steps
        length = math.dist(settings.joint(member.joint1).position, settings.joint(member.joint2).position)
        steel += a.density * math.pi * (d * d - (d - 2 * t) ** 2) / 4 * length
    assert sub.frame.steel_mass() == pytest.approx(steel, rel=1e-12)
    assert sub.rigid_body_mass()[0, 0] == pytest.approx(steel + 1.0e5, rel=1e-12)
    assert steel + 1.0e5 == pytest.approx(ref["Mass"], rel=1e-6)


@pytest.mark.parametrize("case", CASES)
def test_symmetric_positive_definite(built, case):
    _, sub, red = built[case]
    for matrix in (red.stiffness, red.mass, sub.frame.mass):
        assert np.abs(matrix - matrix.T).max() <= 1e-12 * np.abs(matrix).max()
        assert np.linalg.eigvalsh(matrix).min() > 0
    phi = red.modal_shapes
    np.testing.assert_allclose(phi.T @ sub.frame.mass @ phi, np.eye(red.n_modes), atol=1e-9)
    scale = max(red.frequencies, default=1.0) ** 2
    np.testing.assert_allclose(phi.T @ sub.frame.stiffness @ phi, red.modal_stiffness, atol=1e-9 * scale)


@pytest.mark.parametrize("fem, n_div", [(1, 1), (1, 3), (3, 1), (3, 3)])
def test_cantilever_pipe_tip_flexibility_is_the_closed_form(tmp_path, fem, n_div):
    """An inclined pipe clamped at one end: the TP flexibility K_BB⁻¹ is the beam's, turned to global axes."""
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    length, d, t, e, g = 12.0, 2.0, 0.05, 2.1e11, 8.1e10
    path = _pipe_deck(tmp_path, [(0.0, 0.0, -20.0), tuple(np.array([0.0, 0.0, -20.0]) + length * axis)],
                      fem=fem, n_div=n_div, section=(e, g, 7850.0, d, t), spin=25.0)
    top = np.array([0.0, 0.0, -20.0]) + length * axis
    red = Substructure(read_subdyn(path), top, 9.81).guyan()
    area, inertia = math.pi * (d * d - (d - 2 * t) ** 2) / 4, math.pi * (d ** 4 - (d - 2 * t) ** 4) / 64
    nu, m = e / (2 * g) - 1, ((d - 2 * t) / d) ** 2
    kappa = 6 * (1 + nu) ** 2 * (1 + m) ** 2 / ((1 + m) ** 2 * (7 + 14 * nu + 8 * nu ** 2)
                                                + 4 * m * (5 + 10 * nu + 4 * nu ** 2))
    shear = length / (kappa * g * area) if fem == 3 else 0.0
    bend, tilt = length ** 3 / (3 * e * inertia) + shear, length ** 2 / (2 * e * inertia)
    local = np.zeros((6, 6))  # local axes: x, y across the pipe, z along it
    local[0, 0] = local[1, 1] = bend
    local[2, 2] = length / (e * area)
    local[3, 3] = local[4, 4] = length / (e * inertia)
    local[5, 5] = length / (g * 2 * inertia)
    local[0, 4] = local[4, 0] = tilt
    local[1, 3] = local[3, 1] = -tilt
    x = np.cross([0.0, 0.0, 1.0], axis)
    frame = np.column_stack([x / np.linalg.norm(x), np.cross(axis, x / np.linalg.norm(x)), axis])
    turn = np.kron(np.eye(2), frame)
    np.testing.assert_allclose(np.linalg.inv(red.stiffness), turn @ local @ turn.T, rtol=1e-9,
                               atol=1e-9 * np.abs(local).max())


def test_gravity_load_of_a_uniform_vertical_pipe_is_half_its_weight(tmp_path):
    path = _pipe_deck(tmp_path, [(0.0, 0.0, -30.0), (0.0, 0.0, 10.0)], n_div=4, cmass=5e4)
    sub = Substructure(read_subdyn(path), (0.0, 0.0, 10.0), 9.81)
    red = sub.guyan()
    weight = sub.frame.steel_mass() * 9.81
    np.testing.assert_allclose(red.gravity_load, [0, 0, -0.5 * weight - 5e4 * 9.81, 0, 0, 0], atol=1e-6 * weight)


def test_lever_arm_stiffness_is_the_derivative_of_the_output_equation(built):
    _, _, red = built["tripod"]
    tp, modal = red.lever_arm_stiffness()
    q0, zero = red.static_modal_coordinates(), np.zeros(6)
    start, start_q = red.tp_loads(zero, zero, zero)  # SubDyn's initial state q = 0: gravity drives the modes
    np.testing.assert_allclose(start_q, red.modal_gravity_load, rtol=1e-12)
    np.testing.assert_allclose(start, red.gravity_load - red.mass_coupling @ red.modal_gravity_load, rtol=1e-12)
    base, base_q = red.tp_loads(zero, zero, zero, q0)  # static equilibrium
    np.testing.assert_allclose(base, red.gravity_load, rtol=1e-9, atol=1e-9 * np.abs(base).max())
    assert np.abs(base_q).max() < 1e-9 * np.abs(red.modal_gravity_load).max()
    h = 1e-6
    for j in range(6):
        u = np.zeros(6)
        u[j] = h
        y, qdd = red.tp_loads(u, zero, zero, q0)
        expected = tp[:, j] - red.stiffness[:, j] - red.mass_coupling @ modal[:, j]
        np.testing.assert_allclose((y - base) / h, expected, rtol=0, atol=1e-6 * np.abs(tp).max())
        np.testing.assert_allclose((qdd - base_q) / h, modal[:, j], rtol=0, atol=1e-6 * np.abs(modal).max())


def test_node_motion_and_the_static_improvement(built):
    _, sub, red = built["tripod"]
    u = np.array([0.01, -0.02, 0.003, 1e-3, -2e-3, 5e-4])
    disp = red.node_displacements(u)
    for k in sub.frame.interface_nodes:
        np.testing.assert_allclose(disp[k], rigid_transform(sub.frame.positions[k] - red.reference_point) @ u)
    for k in sub.frame.reaction_nodes:
        assert not disp[k].any()
    # CB static coordinates + static improvement = the exact static interior displacement (TP held)
    q0 = red.static_modal_coordinates()
    exact = np.zeros(6 * sub.frame.n_nodes)
    inner = sub.interior_dofs
    exact[inner] = np.linalg.solve(sub.frame.stiffness[np.ix_(inner, inner)], sub.frame.gravity_load[inner])
    improved = red.node_displacements(np.zeros(6), q0, static_loads=sub.frame.gravity_load)
    np.testing.assert_allclose(improved.ravel(), exact, atol=1e-9 * np.abs(exact).max())


def test_craig_bampton_arguments(built):
    _, sub, _ = built["tripod"]
    with pytest.raises(OpenFASTFormatError, match=r"line \d+, key 'Nmodes'"):
        sub.craig_bampton(10_000)
    red = sub.craig_bampton(3, damping_ratios=[0.01, 0.02])
    np.testing.assert_allclose(red.damping_ratios, [0.01, 0.02, 0.02])
    _, monopile, _ = built["monopile"]
    with pytest.raises(ParameterError, match="damping_ratios"):
        monopile.craig_bampton(2)


def test_warns_when_short_euler_bernoulli_elements_ruin_the_conditioning(tmp_path):
    """The stock IEA monopile has 1-mm members at its thickness steps: with FEMMod 1, 12 E I / L³ makes K_LL's
    condition number ~1e14 (with NDiv 2, SubDyn v5's summary then gives a total mass 2.2 % above the model's)."""
    text = (DATA / "monopile.dat").read_text()
    path = tmp_path / "eb_SubDyn.dat"
    path.write_text(text.replace("3                      FEMMod", "1                      FEMMod", 1))
    with pytest.warns(ModelWarning, match=r"condition number of about 1e1[3-6].*0.001 m"):
        Substructure(read_subdyn(path), (0.0, 0.0, 15.0), 9.81)


# ---------------------------------------------------------------------------------------------- reader
def test_reader_keeps_every_value_of_the_tripod():
    sd = read_subdyn(DATA / "tripod_SubDyn.dat")
    assert (sd.fem_model, sd.n_divisions, sd.n_modes, sd.static_improvement) == (3, 2, 6, True)
    np.testing.assert_allclose(sd.mode_damping, [0.01, 0.015, 0.02, 0.02, 0.02, 0.02])
    assert sd.guyan_damping_model == 2 and sd.guyan_damping_matrix[0, 4] == 1e5
    assert sd.reactions == (11, 12, 13) and sd.interfaces == (31, 32, 33)
    assert sd.members[12].spin == pytest.approx(math.radians(30.0))
    assert sd.concentrated_masses[0].inertia == (5e4, 6e4, 7e4, 1e3, -2e3, 1.5e3)
    assert sd.concentrated_masses[1].offset == (0.0, 0.0, 0.0)  # the 5-column form
    assert sd.outputs[:2] == ("Intf1FXss", "Intf1FYss")


BAD_INPUTS = [
    ("SSI file", '    11           1           1           1           1           1           1         ""',
     '    11           1           1           1           1           1           1         "soil.dat"',
     UnsupportedFeatureError, r"line 45, key 'SSIfile'.*soil.dat"),
    ("free reaction DOF", "    12           1           1           1           1           1           1         \"\"",
     "    12           1           1           1           0           0           1         \"\"",
     UnsupportedFeatureError, r"line 46, key 'RctTDXss'.*free DOFs"),
    ("cable member", "    151          40          50           4           4          1c            0",
     "    151          40          50           4           4          2             0",
     UnsupportedFeatureError, r"line 74, key 'MType'.*cable"),
    ("second TP", "  33         1         1           1", "  33         2         1           1",
     UnsupportedFeatureError, r"line 52, key 'TPID'.*\[1, 2\]"),
    ("pin joint", "    40        0.0000      0.0000     10.0000          1",
     "    40        0.0000      0.0000     10.0000          3", UnsupportedFeatureError,
     r"line 39, key 'JointType'.*pin"),
    ("FEMMod 2", "3                      FEMMod", "2                      FEMMod", OpenFASTFormatError,
     r"line 9, key 'FEMMod': must be 1 .* or 3"),
    ("bad number", "7850.0           0.8", "7850.O           0.8", OpenFASTFormatError,
     r"line 81, key 'NPropSets': row 3 of 4: expected 6"),
    ("missing joint", "    142          32          40", "    142          32          41", OpenFASTFormatError,
     r"line 72, key 'MJointID1'.*joint 41"),
    ("too many JDampings", "1.0, 1.5, 2.0          JDampings", "1, 1, 1, 1, 1, 1, 1  JDampings", OpenFASTFormatError,
     r"line 12, key 'JDampings': 7 values for Nmodes = 6"),
    ("line out of order", "2                      NDiv", "2                      NDivisions", OpenFASTFormatError,
     r"line 10, key 'NDiv': expected 'NDiv'.*'NDivisions'"),
    ("Guyan matrix size", "6                      GuyanDampSize", "5                      GuyanDampSize",
     OpenFASTFormatError, None),
]


@pytest.mark.parametrize("name, old, new, error, message", BAD_INPUTS, ids=[b[0] for b in BAD_INPUTS])
def test_reader_names_file_line_and_key_of_bad_inputs(tmp_path, name, old, new, error, message):
    text = (DATA / "tripod_SubDyn.dat").read_text()
    assert text.count(old) == 1, name
    path = tmp_path / "bad_SubDyn.dat"
    path.write_text(text.replace(old, new))
    with pytest.raises(error, match=message) as info:
        read_subdyn(path)
    assert str(path) in str(info.value)


def test_reader_reads_the_stock_iea_monopile_deck():
    path = (Path.home() / ".cache/mbsym/rosco/2.10.6/deck/IEA-15-240-RWT/IEA-15-240-RWT-Monopile"
            / "IEA-15-240-RWT-Monopile_SubDyn.dat")
    if not path.is_file():
        pytest.skip(f"the ROSCO wheel's IEA 15 MW deck is not extracted at {path.parent}")
    sd = read_subdyn(path)
    assert (sd.fem_model, sd.n_modes, sd.mode_damping, sd.time_step) == (3, 0, (), "default")
    assert len(sd.joints) == 19 and len(sd.members) == 18 and sd.interfaces == (19,)
    assert sd.member_outputs == ((1, 1, 1), (3, 1, 1))
    assert sd.outputs == ("M2N1MKxe", "M2N1MKye", "M1N1MKxe", "M1N1MKye", "-ReactFXss", "-ReactFYss", "-ReactFZss",
                          "-ReactMXss", "-ReactMYss", "-ReactMZss")


def test_rigid_body_position_has_no_effect_and_is_said_so(tmp_path):
    text = (DATA / "tripod_SubDyn.dat").read_text()
    path = tmp_path / "rb_SubDyn.dat"
    path.write_text(text.replace("  0.0        0.0        0.0       0.0        0.0        0.0",
                                 "  1.0        0.0        0.0       0.0        0.0        5.0", 1))
    assert read_subdyn(path).rigid_body_position[5] == pytest.approx(math.radians(5.0))
    with pytest.warns(ModelWarning, match="only for floating structures"):
        Substructure(read_subdyn(path), (0.0, 0.0, 15.0), 9.81)


def test_reader_refuses_a_missing_file(tmp_path):
    with pytest.raises(OpenFASTFormatError, match="SubDyn input file not found"):
        read_subdyn(tmp_path / "none.dat")


# ---------------------------------------------------------------------------------------------- a deck writer
def _pipe_deck(tmp_path, points, fem=3, n_div=1, section=(2.1e11, 8.1e10, 7850.0, 2.0, 0.05), spin=0.0,
               cmass=None) -> Path:
    """A SubDyn file of one pipe from points[0] (clamped) to points[1] (the interface joint)."""
    head = ["----------- SubDyn v1.01.x MultiMember Support Structure Input File ------------", "test pipe",
            "-------------------------- SIMULATION CONTROL  ---------------------------------",
            "False Echo", '"DEFAULT" SDdeltaT', "3 IntMethod", "True SttcSolve",
            "-------------------- FEA and CRAIG-BAMPTON PARAMETERS---------------------------",
            f"{fem} FEMMod", f"{n_div} NDiv", "0 Nmodes", "1.0 JDampings", "0 GuyanDampMod", "0.0, 0.0 RayleighDamp",
            "6 GuyanDampSize", *["0 0 0 0 0 0"] * 6,
            "------- INITIAL RIGID-BODY POSITION -------", "RBSurge", "(m)", "0 0 0 0 0 0",
            "---- STRUCTURE JOINTS ----", "2 NJoints", "ID X Y Z Type DX DY DZ K", "(-)",
            *(f"{i + 1} {p[0]} {p[1]} {p[2]} 1 0 0 0 0" for i, p in enumerate(points)),
            "---- BASE REACTION JOINTS ----", "1 NReact", "ID", "(-)", '1 1 1 1 1 1 1 ""',
            "---- INTERFACE JOINTS ----", "1 NInterf", "ID", "(-)", "2 1 1 1 1 1 1 1",
            "---- MEMBERS ----", "1 NMembers", "ID", "(-)", f"1 1 2 1 1 1c {spin}",
            "---- CIRCULAR BEAM CROSS-SECTION PROPERTIES ----", "1 NPropSets", "ID", "(-)",
            "1 " + " ".join(map(str, section))]
    empty = [("RECTANGULAR BEAM CROSS-SECTION PROPERTIES", "NPropSets"), ("ARBITRARY BEAM", "NXPropSets"),
             ("CABLE PROPERTIES", "NCablePropSets"), ("RIGID LINK PROPERTIES", "NRigidPropSets"),
             ("SPRING ELEMENT PROPERTIES", "NSpringPropSets"), ("MEMBER COSINE MATRICES", "NCOSMs")]
    for rule, key in empty:
        head += [f"---- {rule} ----", f"0 {key}", "ID", "(-)"]
    masses = [f"2 {cmass} 0 0 0"] if cmass else []
    head += ["---- JOINT ADDITIONAL CONCENTRATED MASSES ----", f"{len(masses)} NCmass", "ID", "(-)", *masses,
             "---- OUTPUT: SUMMARY & OUTFILE ----", "False SumPrint", "0 OutCBModes", "0 OutFEMModes", "False OutCOSM",
             "False OutAll", "2 OutSwtch", "True TabDelim", "1 OutDec", '"ES11.4e2" OutFmt', '"A11" OutSFmt',
             "---- MEMBER OUTPUT LIST ----", "0 NMOutputs", "ID", "(-)", "---- SSOutList ----", "END"]
    path = tmp_path / f"pipe_{fem}_{n_div}.dat"
    path.write_text("\n".join(head) + "\n")
    return path
