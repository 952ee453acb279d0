"""eom.latex(): readable LaTeX of M and F, checked against closed forms by parsing it back.

References: the planar double pendulum of point masses (relative angles; textbook Lagrange
equations, written out below), whose LaTeX is parsed back with sympy's LaTeX parser and
evaluated at random points (tolerance 1e-12: coefficients are written exactly with
digits=None); the paper's 2-DOF turbine (Sect. 4.4, examples/paper_4_4_two_dof.py), whose
LaTeX must reproduce eom.mass_matrix / eom.forcing (1e-10 relative).
"""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ExportError
from mbsym.export import latex_entries, latex_name

from . import _models

G = 9.81


def parse(tex: str, names: dict[str, str]):
    """sympy expression of one entry: speeds renamed to plain symbols, implicit products before \\left( made explicit."""
    latex = pytest.importorskip("sympy.parsing.latex")
    pytest.importorskip("antlr4")
    for old, new in names.items():
        tex = tex.replace(old, new)
    tex = tex.replace(" \\left(", " \\cdot \\left(")     # "m l \left(...\right)" is a product, not l(...)
    return latex.parse_latex(tex)


def evaluate(expr, values: dict[str, float]) -> float:
    import sympy

    f = sympy.lambdify(sorted(expr.free_symbols, key=str), expr, "math")
    return float(f(*[values[str(s)] for s in sorted(expr.free_symbols, key=str)]))


def closed_form(q1, q2, w1, w2, m1, m2, l1, l2):
    c2, s2 = np.cos(q2), np.sin(q2)
    M = [[(m1 + m2) * l1**2 + m2 * l2**2 + 2 * m2 * l1 * l2 * c2, m2 * l2**2 + m2 * l1 * l2 * c2],
         [m2 * l2**2 + m2 * l1 * l2 * c2, m2 * l2**2]]
    F = [m2 * l1 * l2 * s2 * (2 * w1 * w2 + w2**2) - (m1 + m2) * G * l1 * np.sin(q1) - m2 * G * l2 * np.sin(q1 + q2),
         -m2 * l1 * l2 * s2 * w1**2 - m2 * G * l2 * np.sin(q1 + q2)]
    return np.array(M), np.array(F)


def test_double_pendulum_reads_like_the_textbook():
    M, F = latex_entries(_models.double_pendulum(), digits=None)
    assert M[1][1] == "m_{2} l_{2}^{2}"
    assert M[0][1] == M[1][0] == "m_{2} l_{2} \\left(l_{1} \\cos\\left(q_{2}\\right) + l_{2}\\right)"
    assert "q_{1}" not in M[0][0] + M[0][1]                 # sin^2 + cos^2 = 1 removed the absolute angle
    assert "\\sin\\left(q_{1} + q_{2}\\right)" in F[0] and "\\dot{q}_{1}^{2}" in F[1]


def test_double_pendulum_parses_back_to_the_closed_form():
    M, F = latex_entries(_models.double_pendulum(), digits=None)
    names = {"\\dot{q}_{1}": "w_{1}", "\\dot{q}_{2}": "w_{2}"}
    exprs_M = [[parse(M[i][j], names) for j in range(2)] for i in range(2)]
    exprs_F = [parse(f, names) for f in F]
    rng = np.random.default_rng(3)
    for _ in range(4):
        v = dict(zip(["q_{1}", "q_{2}", "w_{1}", "w_{2}", "m_{1}", "m_{2}", "l_{1}", "l_{2}"],
                     np.r_[rng.normal(size=4), rng.uniform(0.5, 2.0, 4)]))
        M_ref, F_ref = closed_form(*v.values())
        got_M = np.array([[evaluate(e, v) for e in row] for row in exprs_M])
        got_F = np.array([evaluate(e, v) for e in exprs_F])
        np.testing.assert_allclose(got_M, M_ref, rtol=1e-12)
        np.testing.assert_allclose(got_F, F_ref, rtol=1e-12, atol=1e-12 * np.abs(F_ref).max())


def _paper_model():
    path = Path(__file__).resolve().parents[2] / "examples" / "paper_4_4_two_dof.py"
    spec = importlib.util.spec_from_file_location("paper_4_4_two_dof", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.build()[0].equations()


def test_paper_two_dof_turbine_matches_its_equations():
    eom = _paper_model()
    text = eom.latex(digits=None)
    assert text.startswith("\\begin{aligned}") and "\\dot{\\psi}" in text
    M, F = latex_entries(eom, digits=None)
    names = {"\\dot{q}": "v", "\\dot{\\psi}": "w"}
    exprs_M = [[parse(M[i][j], names) for j in range(2)] for i in range(2)]
    exprs_F = [parse(f, names) for f in F]
    rng = np.random.default_rng(0)
    for _ in range(3):
        q, psi, v, w = rng.normal(scale=[0.5, 1.0, 0.3, 1.0])
        vals = {"q": q, "psi": psi, "v": v, "w": w}
        got_M = np.array([[evaluate(e, vals) for e in row] for row in exprs_M])
        got_F = np.array([evaluate(e, vals) for e in exprs_F])
        M_ref = eom.mass_matrix([q, psi])          # its off-diagonal is rounding noise (~1e-12) of an exact 0
        np.testing.assert_allclose(got_M, M_ref, rtol=1e-10, atol=1e-10 * np.abs(M_ref).max())
        F_ref = eom.forcing([q, psi], [v, w])
        np.testing.assert_allclose(got_F, F_ref, rtol=1e-10, atol=1e-10 * np.abs(F_ref).max())


def test_symbol_names():
    assert latex_name("q1") == "q_{1}" and latex_name("m_2") == "m_{2}"
    assert latex_name("theta") == "\\theta" and latex_name("psi2") == "\\psi_{2}"
    assert latex_name("GeAz") == "\\mathrm{GeAz}" and latex_name("TFA1") == "\\mathrm{TFA}_{1}"
    text = _models.pendulum().latex(form="matrix")
    assert "\\theta" in text and "\\begin{bmatrix}" in text and "T" in text   # the input T appears in F


def test_large_models_and_bad_options_are_refused():
    with pytest.raises(ExportError, match="more than 50 terms"):
        _models.chain(9).latex(max_terms=50)
    eom = _models.pendulum()
    with pytest.raises(ExportError, match="form must be"):
        eom.latex(form="table")
    with pytest.raises(ExportError, match="digits"):
        eom.latex(digits=0)
    with pytest.raises(TypeError):
        eom.latex(simplify=False)
