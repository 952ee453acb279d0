"""Solving ``M x = b`` for a symmetric positive definite ``M`` as one unrolled SX Function (LDLᵀ).

The mass matrix of Kane's equations is symmetric positive definite, so its factorization needs no
pivoting: ``M = L D Lᵀ`` with ``L`` unit lower triangular, ``D`` diagonal positive, computed column by
column, then ``x = L⁻ᵀ D⁻¹ L⁻¹ b``. Written out in SX for the sparsity of ``M`` (structural zeros are
zeros in the expressions, so CasADi drops their products, and fill-in appears only where it must),
it becomes straight-line generated C: for the 15-DOF flexible NREL 5 MW (a dense 15 × 15) about 1 500
instructions, several times cheaper than CasADi's general sparse ``qr`` or ``ldl`` linear solvers in
generated code (benchmarks/README.md, "blade-loop-speed"), and differentiable like any SX expression.

Only the lower triangle and the diagonal are read: ``M`` must be symmetric (a matrix that is not, such as
WAMIT's slightly asymmetric A∞ added to it, needs a general solver). Positive definiteness is the caller's promise (``check_mass_matrix`` verifies it at the initial state);
a pivot that is not positive gives non-finite or wrong numbers, not an exception, as with any solver
without pivoting.
"""

from __future__ import annotations

import functools

import casadi as ca

__all__ = ["spd_solver", "spd_solve"]


@functools.lru_cache(maxsize=64)
def _solver(pattern: tuple, n: int, n_rhs: int) -> ca.Function:
    rows, cols = zip(*pattern) if pattern else ((), ())
    sp = ca.Sparsity.triplet(n, n, list(rows), list(cols))
    M = ca.SX.sym("M", sp)
    b = ca.SX.sym("b", n, n_rhs)
    L = [[None] * n for _ in range(n)]
    d = [None] * n
    for j in range(n):
        s = M[j, j]
        for k in range(j):
            if not _zero(L[j][k]):
                s = s - L[j][k] * L[j][k] * d[k]
        d[j] = s
        for i in range(j + 1, n):
            s = M[i, j]
            for k in range(j):
                if not (_zero(L[i][k]) or _zero(L[j][k])):
                    s = s - L[i][k] * L[j][k] * d[k]
            L[i][j] = s / d[j] if not _zero(s) else ca.SX(0)
    y = [None] * n
    for i in range(n):                                  # L y = b
        s = b[i, :]
        for k in range(i):
            if not _zero(L[i][k]):
                s = s - L[i][k] * y[k]
        y[i] = s
    x = [None] * n
    for i in reversed(range(n)):                        # D Lᵀ x = y
        s = y[i] / d[i]
        for k in range(i + 1, n):
            if not _zero(L[k][i]):
                s = s - L[k][i] * x[k]
        x[i] = s
    return ca.Function(f"spd_solve_{n}x{n_rhs}", [M, b], [ca.vertcat(*x)], ["M", "b"], ["x"], {"cse": True})


def _zero(e) -> bool:
    return isinstance(e, ca.SX) and e.is_zero()


def spd_solver(sparsity: ca.Sparsity, n_rhs: int = 1) -> ca.Function:
    """``(M, b) -> x`` solving ``M x = b`` for symmetric positive definite ``M`` of this sparsity (n × n).

    Parameters
    ----------
    sparsity : casadi.Sparsity
        Of ``M`` (square; made symmetric: the pattern and its transpose).
    n_rhs : int, optional
        Columns of ``b``.

    Returns
    -------
    casadi.Function
        SX, cached per pattern.
    """
    if sparsity.size1() != sparsity.size2():
        raise ValueError(f"spd_solver needs a square matrix; got {sparsity.size1()} x {sparsity.size2()}.")
    sym = sparsity + sparsity.T
    rows, cols = sym.get_triplet()
    pattern = tuple(sorted(zip(rows, cols)) + [(i, i) for i in range(sym.size1()) if not sym.has_nz(i, i)])
    return _solver(tuple(sorted(set(pattern))), sym.size1(), int(n_rhs))


def spd_solve(M, b):
    """``M⁻¹ b`` for symmetric positive definite ``M`` (MX or SX) through :func:`spd_solver`."""
    return spd_solver(M.sparsity(), b.size2())(M, b)
