"""ServoDyn's structural controllers (StC): reader, refusals, a closed form (mbsym.wind.operation.structural_control).

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


@pytest.mark.parametrize("key, value, match", [("StC_DOF_MODE", 5, "TLCD"), ("StC_DOF_MODE", 6, "prescribed"),
                                               ("StC_DOF_MODE", 7, "DLL"), ("StC_CMODE", 1, "StC_CMODE = 1"),
                                               ("Use_F_TBL", "True", "spring-force table")])
def test_unmodelled_settings_refused(tmp_path, key, value, match):
    from mbsym.wind.deck.stc import read_stc
    from mbsym.wind.operation.structural_control import _refusals

    problems = _refusals(read_stc(_stc_file(tmp_path, **{key: value})))
    assert any(match in p and f"key '{key}'" in p for p in problems), problems


def test_blade_and_tower_stcs_refused(tmp_path):
    from types import SimpleNamespace

    from mbsym.wind.operation.structural_control import structural_controls

    srvd = tmp_path / "srvd.dat"
    srvd.write_text("x\nx\n1 NumBStC\n\"a.dat\" BStCfiles\n0 NumNStC\n\"unused\" NStCfiles\n1 NumTStC\n"
                    "\"b.dat\" TStCfiles\n0 NumSStC\n\"unused\" SStCfiles\n")
    s = SimpleNamespace(path=str(srvd), lines={"NumBStC": 3, "NumTStC": 7}, n_blade_structural_controllers=1,
                        n_nacelle_structural_controllers=0, n_tower_structural_controllers=1,
                        n_substructure_structural_controllers=0)
    turbine = SimpleNamespace(simulation=SimpleNamespace(substructure_model=0))
    with pytest.raises(UnsupportedFeatureError, match=r"line 3, key 'NumBStC'.*\n.*line 7, key 'NumTStC'"):
        structural_controls(s, turbine)


def test_tmd_on_free_platform_matches_two_mass_closed_form(tmp_path):
    from mbsym.wind import nrel5mw
    from mbsym.wind.deck.stc import read_stc
    from mbsym.wind.operation.structural_control import StructuralControl, StructuralControls, stc_terms
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
