"""ServoDyn's structural controllers (StC): reader, refusals, a closed form (mbsym.wind.structure.structural_control).

Closed form: an SStC on a platform free in surge (PtfmSgDOF alone, no water, no mooring) is a two-mass system. With
the X mass ``m`` on a spring ``k`` and damper ``c`` and the rigid Y mass ``m_y`` moving with the platform (its
transverse inertia is StrucCtrl's ``F_Y_P(1)``), the relative coordinate obeys ``μ ẍ + c ẋ + k x = 0`` with
``μ = m M' / (m + M')``, ``M' = M + m_y`` (M: the structure's surge mass), and the surge DOF has a zero eigenvalue
(free translation). The linearized eigenvalues must equal those of the closed form to 1e-9 relative (rounding).
"""

from __future__ import annotations

import math
import subprocess
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError, UnsupportedFeatureError

DOC = "docs/source/user/servodyn-stc/ExampleFiles/NRELOffshrBsline5MW_StC.dat"
_TEMPLATE = Path(__file__).parent.parent.parent / "data" / "openfast_stc" / "NStC.dat"


def _stc_file(tmp_path: Path, **values) -> Path:
    """The reference data's StC file with some values replaced (key -> value)."""
    lines = []
    for line in _TEMPLATE.read_text().splitlines():
        tokens = line.split()
        if len(tokens) >= 2 and tokens[1] in values:
            line = f"{values[tokens[1]]}   {tokens[1]}   - replaced"
        lines.append(line)
    path = tmp_path / "StC.dat"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_read_stc_values_and_lines(tmp_path):
    from mbsym.wind.deck.stc import read_stc

    s = read_stc(_stc_file(tmp_path))
    assert s.dof_mode == 1 and s.dof == (True, True, False)
    assert s.values["StC_X_M"] == 7000.0 and s.values["StC_X_K"] == 28000.0 and s.values["StC_P_Z"] == 2.0
    assert s.lines["StC_X_K"] == 31 and not s.use_table and s.table.shape == (17, 6)


def test_read_stc_bad_mode_names_line(tmp_path):
    from mbsym.wind.deck.stc import read_stc

    with pytest.raises(OpenFASTFormatError, match=r"line 6, key 'StC_DOF_MODE'.*OpenFAST v5"):
        read_stc(_stc_file(tmp_path, StC_DOF_MODE=4))      # TLCD's number before OpenFAST v5


@pytest.mark.parametrize("key, value, match", [("StC_DOF_MODE", 5, "TLCD"),
                                               ("StC_DOF_MODE", 7, "DLL"), ("StC_CMODE", 1, "StC_CMODE = 1"),
                                               ("Use_F_TBL", "True", "spring-force table")])
def test_unmodelled_settings_refused(tmp_path, key, value, match):
    from mbsym.wind.deck.stc import read_stc
    from mbsym.wind.structure.structural_control import _refusals

    problems = _refusals(read_stc(_stc_file(tmp_path, **{key: value})))
    assert any(match in p and f"key '{key}'" in p for p in problems), problems


def test_blade_stcs_refused(tmp_path):
    from types import SimpleNamespace

    from mbsym.wind.structure.structural_control import structural_controls

    srvd = tmp_path / "srvd.dat"
    srvd.write_text("x\nx\n1 NumBStC\n\"a.dat\" BStCfiles\n0 NumNStC\n\"unused\" NStCfiles\n0 NumTStC\n"
                    "\"unused\" TStCfiles\n0 NumSStC\n\"unused\" SStCfiles\n")
    s = SimpleNamespace(path=str(srvd), lines={"NumBStC": 3}, n_blade_structural_controllers=1,
                        n_nacelle_structural_controllers=0, n_tower_structural_controllers=0,
                        n_substructure_structural_controllers=0)
    turbine = SimpleNamespace(simulation=SimpleNamespace(substructure_model=0), tower_height=87.6,
                              tower_base_height=0.0)
    with pytest.raises(UnsupportedFeatureError, match=r"line 3, key 'NumBStC': blade"):
        structural_controls(s, turbine)


def _servodyn_with(tmp_path: Path, kind: str, stc: Path):
    from types import SimpleNamespace

    srvd = tmp_path / "srvd.dat"
    names = {k: (f'"{stc.name}"' if k == kind else '"unused"') for k in "BNTS"}
    srvd.write_text("x\nx\n" + "".join(f"{int(k == kind)} Num{k}StC\n{names[k]} {k}StCfiles\n" for k in "BNTS"))
    n = {k: int(k == kind) for k in "BNTS"}
    return SimpleNamespace(path=str(srvd), lines={}, n_blade_structural_controllers=n["B"],
                           n_nacelle_structural_controllers=n["N"], n_tower_structural_controllers=n["T"],
                           n_substructure_structural_controllers=n["S"])


@pytest.mark.parametrize("values, match", [({"StC_P_Z": 90.0}, r"key 'StC_P_Z': a tower StC must lie on the tower"),
                                           ({"StC_DOF_MODE": 6, "PrescribedForcesFile": '"unused"'},
                                            r"key 'PrescribedForcesFile': StC_DOF_MODE = 6 needs")])
def test_tower_stc_refusals(tmp_path, values, match):
    from types import SimpleNamespace

    from mbsym.wind.structure.structural_control import structural_controls

    s = _servodyn_with(tmp_path, "T", _stc_file(tmp_path, **values))
    turbine = SimpleNamespace(simulation=SimpleNamespace(substructure_model=0), tower_height=87.6,
                              tower_base_height=0.0)
    with pytest.raises(UnsupportedFeatureError, match=match):
        structural_controls(s, turbine)


def test_prescribed_tables_hold_the_ends_as_interpstp(tmp_path):
    """ServoDyn interpolates the prescribed loads linearly in time and holds the end rows (NWTC ``InterpStp``)."""
    from types import SimpleNamespace

    from mbsym.wind.structure.structural_control import structural_controls

    (tmp_path / "f.dat").write_text("# t Fx Fy Fz Mx My Mz\n2 1 0 0 0 0 -4\n! a comment\n4 3 0 0 0 0 8\n")
    stc = _stc_file(tmp_path, StC_DOF_MODE=6, PrescribedForcesFile='"f.dat"')
    turbine = SimpleNamespace(simulation=SimpleNamespace(substructure_model=0), tower_height=87.6,
                              tower_base_height=0.0)
    controls = structural_controls(_servodyn_with(tmp_path, "N", stc), turbine)
    assert controls.state_names == () and controls.input_names[0] == "NStC1_Fx"
    tables = controls.tables(10.0)
    t = np.array([0.0, 2.0, 3.0, 4.0, 10.0])
    assert np.allclose(np.interp(t, *tables["NStC1_Fx"]), [1, 1, 2, 3, 3])
    assert np.allclose(np.interp(t, *tables["NStC1_Mz"]), [-4, -4, 2, 8, 8])
    assert tables["NStC1_Fx"][0][0] < 0.0 and tables["NStC1_Fx"][0][-1] > 10.0      # covers [0, t_end]


def test_tower_point_at_the_top_moves_with_the_yaw_bearing():
    """A tower point at the top of the flexible length (with an offset) moves as the same point of the nacelle
    (no yaw DOF): position, orientation, velocity, angular velocity and both accelerations, at random states."""
    from mbsym.wind import nrel5mw
    from mbsym.wind.structure.structural_control_terms import tower_point_motion
    from mbsym.wind.structure.turbine import TurbineModel

    t = nrel5mw()
    model = TurbineModel(t, dofs=["TwFADOF1", "TwFADOF2", "TwSSDOF1", "TwSSDOF2", "PtfmSgDOF", "PtfmPDOF",
                                  "PtfmRDOF", "PtfmYDOF"])
    eom = model.eom
    n = eom.n_q
    q, qd, qdd = ca.SX.sym("q", n), ca.SX.sym("qd", n), ca.SX.sym("qdd", n)
    u, p = ca.DM.zeros(eom.n_u), ca.DM(eom.parameter_vector())
    offset = (1.5, -0.7, 0.0)
    top = tower_point_motion(model, (offset[0], offset[1], t.tower_height - t.tower_base_height), q, qd, qdd, u, p)
    _, R, v, w, a, wd = eom.point_kinematics("nacelle", offset)(q, qd, qdd, u, p)
    f = ca.Function("f", [q, qd, qdd], [ca.vertcat(ca.vec(top[0] - R), top[1] - v, top[2] - w, top[3] - a,
                                                   top[4] - wd)])
    rng = np.random.default_rng(3)
    for _ in range(3):
        x = [rng.normal(scale=s, size=n) for s in (0.05, 0.3, 1.0)]
        assert np.max(np.abs(np.array(f(*x)))) < 1e-9


def test_prescribed_load_power_on_the_tower(tmp_path):
    """A prescribed load on a tower point does the work of F·v_P + M·ω_P: ``Qᵀ q̇`` equals it at random states
    (global and local axes), and it adds nothing to the mass matrix."""
    from mbsym.wind import nrel5mw
    from mbsym.wind.deck.stc import read_stc
    from mbsym.wind.structure.structural_control import StructuralControl, StructuralControls, stc_terms
    from mbsym.wind.structure.structural_control_terms import tower_point_motion
    from mbsym.wind.structure.turbine import TurbineModel

    model = TurbineModel(nrel5mw(), dofs=["TwFADOF1", "TwSSDOF1", "TwSSDOF2", "PtfmSgDOF", "PtfmRDOF", "PtfmYDOF"])
    eom = model.eom
    n = eom.n_q
    q, qd, load = ca.SX.sym("q", n), ca.SX.sym("qd", n), ca.SX.sym("f", 6)
    u, p = ca.DM.zeros(eom.n_u), ca.DM(eom.parameter_vector())
    rng = np.random.default_rng(5)
    for coords in (1, 2):
        s = read_stc(_stc_file(tmp_path, StC_DOF_MODE=6, StC_P_Z=40.0, StC_P_Y=0.8, PrescribedForcesCoordSys=coords))
        controls = StructuralControls((StructuralControl("T", 1, s, np.zeros((1, 7))),))
        terms = stc_terms(controls, eom, q, qd, u, p, ca.SX(0, 1), 9.81, u_stc=load, structure=model)
        R, v, w, _, _ = tower_point_motion(model, s.position, q, qd, ca.SX.zeros(n), u, p)
        F, M = (load[:3], load[3:]) if coords == 1 else (R @ load[:3], R @ load[3:])
        f = ca.Function("f", [q, qd, load], [ca.dot(terms["force"], qd) - ca.dot(F, v) - ca.dot(M, w),
                                             ca.norm_inf(terms["mass"])])
        for _ in range(3):
            power, mass = f(rng.normal(scale=0.05, size=n), rng.normal(size=n), rng.normal(scale=1e5, size=6))
            assert abs(float(power)) < 1e-6 and float(mass) == 0.0


def test_tmd_on_free_platform_matches_two_mass_closed_form(tmp_path):
    from mbsym.wind import nrel5mw
    from mbsym.wind.deck.stc import read_stc
    from mbsym.wind.structure.structural_control import StructuralControl, StructuralControls, stc_terms
    from mbsym.wind.structure.turbine import TurbineModel

    m, k, c, m_y = 5.0e4, 2.0e5, 3.0e4, 2.0e4
    s = read_stc(_stc_file(tmp_path, StC_Y_DOF="False", StC_X_M=m, StC_Y_M=m_y, StC_X_K=k, StC_X_C=c,
                           StC_X_PSP=100, StC_X_NSP=-100))
    controls = StructuralControls((StructuralControl("S", 1, s),))
    eom = TurbineModel(nrel5mw(), dofs=["PtfmSgDOF"]).eom
    n = eom.n_q
    x = ca.SX.sym("x", 2 * n + 6)
    q, qd, xs = x[:n], x[n:2 * n], x[2 * n:]
    u, p = ca.DM.zeros(eom.n_u), ca.DM(eom.parameter_vector())
    g = float(p[eom.parameters.index("gravity")])
    terms = stc_terms(controls, eom, q, qd, u, p, xs, g)
    f = eom.functions
    mass = f.mass_matrix(q, p) if f.mass_matrix.n_in() == 2 else f.mass_matrix(q, u, p)
    qdd = ca.solve(mass + terms["mass"], f.forcing(q, qd, u, p) + terms["force"])
    rhs = ca.Function("rhs", [x], [ca.vertcat(qd, qdd, terms["rates"](qdd))])
    J = np.array(ca.Function("J", [x], [ca.jacobian(rhs(x), x)])(np.zeros(2 * n + 6)))
    big = float(ca.Function("M", [x], [mass])(np.zeros(2 * n + 6))[0, 0])
    mu = m * (big + m_y) / (m + big + m_y)
    zeta, wn = c / (2 * math.sqrt(k * mu)), math.sqrt(k / mu)
    expected = wn * complex(-zeta, math.sqrt(1 - zeta ** 2))
    eig = np.linalg.eigvals(J)
    top = eig[np.argmax(eig.imag)]
    assert abs(top - expected) < 1e-9 * abs(expected)
