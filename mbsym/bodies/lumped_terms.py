"""Exact Kane terms of a flexible body made of point masses (ElastoDyn's blades and tower).

Node ``J`` (mass ``m_J``) sits at ``s_J(q) = (Phi_Jx q, Phi_Jy q, z_J - 1/2 q^T Ax_J q)`` in
the body frame, with partial velocities ``S_J = ds_J/dq`` and ``Sdot_J qd = -(qd^T Ax_J qd) e_z``.
With the body's generalized speeds ``V = [v; w; qd]`` (origin velocity and angular velocity in
body axes) a node moves with ``B_J V``, ``B_J = [I, -s~, S]``, and accelerates with
``B_J Vdot + w x (w x s) + 2 w x (S qd) + Sdot qd``. The body's Kane terms are therefore

``Mb = sum m B^T B``  and  ``k = sum m B^T [w x (w x s) + 2 w x (S qd) + Sdot qd]``,

exactly, with no truncation in ``q``: the first moment ``c = sum m s``, the second moments
``sum m s s^T``, ``C = sum m S``, ``G[a, b, j] = sum m s_a S_bj`` and ``M_e = sum m S^T S`` are
polynomials in ``q`` (degree <= 4) whose coefficients :class:`mbsym.beam.nodes.NodeMoments`
holds, evaluated here on the monomials of ``q`` (no symbolic loop over the nodes). Axial
shortening, centrifugal stiffening, spin softening and the ``sum m (Ax q)(Ax q)^T`` mass terms
all follow from these kinematics; no geometric-stiffness matrix is added.
"""

from __future__ import annotations

import itertools

import casadi as ca
import numpy as np

from ..kinematics import skew

__all__ = ["ExactLumpedTerms", "exact_lumped_terms"]


class _Monomials:
    """Monomial vectors of a few SX vectors, each built with one vectorized product per factor."""

    def __init__(self) -> None:
        self._cache: dict[tuple, tuple[ca.SX, np.ndarray]] = {}

    def get(self, groups: tuple[tuple[ca.SX, int], ...]) -> tuple[ca.SX, np.ndarray]:
        """Monomials of ``groups`` ((vector, degree), …) and the map (index tuples -> monomials).

        The monomials are products of one sorted index combination per group (kron order);
        ``map[t, k] = 1`` when the t-th index tuple of the contracted axes (C order) is a
        permutation of monomial k.
        """
        key = tuple((id(v), c) for v, c in groups)
        if key not in self._cache:
            mono, index = ca.SX.ones(1, 1), np.zeros(1, dtype=int)
            for vec, count in groups:
                n = vec.numel()
                combos = list(itertools.combinations_with_replacement(range(n), count))
                part = ca.SX.ones(len(combos), 1)
                for pos in range(count):
                    part = part * vec[[c[pos] for c in combos]]
                where = {c: k for k, c in enumerate(combos)}
                tuples = itertools.product(range(n), repeat=count)
                local = np.array([where[tuple(sorted(t))] for t in tuples], dtype=int)
                index = (index[:, None] * len(combos) + local[None, :]).reshape(-1)
                mono = ca.kron(mono, part)
            table = np.zeros((index.size, mono.numel()))
            table[np.arange(index.size), index] = 1.0
            self._cache[key] = (mono, table)
        return self._cache[key]


def _poly(mono: _Monomials, tensor: np.ndarray, groups: tuple[tuple[ca.SX, int], ...]) -> ca.SX:
    """Contract the trailing axes of ``tensor`` with the vectors of ``groups`` (vector, count).

    Returns a column of ``prod(tensor.shape[:-d])`` entries (C order): the sum over all index
    tuples of ``tensor[..., i1, …, id] * v_1[i1] * …``, written on unique monomials.
    """
    d = sum(c for _, c in groups)
    out_size = int(np.prod(tensor.shape[:tensor.ndim - d], dtype=int))
    vec, table = mono.get(groups)
    coeff = tensor.reshape(out_size, -1) @ table
    return ca.mtimes(ca.sparsify(ca.DM(coeff)), vec)


class ExactLumpedTerms:
    """The exact polynomial terms of one lumped body at symbolic ``q``, ``qd`` (body axes).

    Attributes
    ----------
    c : SX (3, 1)
        First moment ``sum m s`` [kg m].
    inertia : SX (3, 3)
        ``sum m (|s|^2 I - s s^T)`` about the origin [kg m^2].
    C : SX (3, n_e)
        ``sum m S`` [kg].
    G : list of SX (3, 3)
        ``G[j][a, b] = sum m s_a S_bj`` [kg m].
    coupling : SX (3, n_e)
        ``sum m s x S_j`` (column j) [kg m].
    me : SX (n_e, n_e)
        ``sum m S^T S`` [kg].
    """

    def __init__(self, moments, q: ca.SX, qd: ca.SX) -> None:
        self._m, self.q, self.qd, self.n_e = moments, q, qd, q.numel()
        self._mono = _Monomials()
        self._P = lambda t, groups: _poly(self._mono, np.asarray(t, dtype=float), groups)  # noqa: E731
        mo, P, q1, q2 = moments, self._P, ((q, 1),), ((q, 2),)
        self.c = ca.vertcat(P(mo.p, q1), mo.z1 - 0.5 * P(mo.k1, q2))
        self.inertia = self._inertia()
        self.C = ca.vertcat(ca.DM(mo.p), -P(mo.k1, q1).T)              # rows Phi_x, Phi_y, -(Ax q)^T
        self.G = self._g_tensor()
        self.coupling = ca.horzcat(*[_vee_antisym(Gj) for Gj in self.G])
        # M_e = sum m (Phi^T Phi + (Ax q)(Ax q)^T); [i, j] from kk[i, k, j, l] q_k q_l
        self.me = ca.DM(mo.pp[0, 0] + mo.pp[1, 1]) + _mat(P(np.transpose(mo.kk, (0, 2, 1, 3)), q2), self.n_e, self.n_e)

    def _inertia(self) -> ca.SX:
        """``tr(Q) I - Q`` with the second moments ``Q = sum m s s^T`` (degree 4 in q)."""
        mo, P, q = self._m, self._P, self.q
        sxy = _mat(P(mo.pp, ((q, 2),)), 2, 2)                                  # sum m s_a s_b, a, b in x, y
        sz = P(mo.pz, ((q, 1),)) - 0.5 * P(mo.kp, ((q, 3),))                   # sum m s_a s_z
        szz = mo.z2 - P(mo.kz, ((q, 2),)) + 0.25 * P(mo.kk, ((q, 4),))
        Q2 = ca.vertcat(ca.horzcat(sxy, sz), ca.horzcat(sz.T, szz))
        return ca.trace(Q2) * ca.SX.eye(3) - Q2

    def _g_tensor(self) -> list[ca.SX]:
        """``G[j][a, b] = sum m s_a S_bj`` (the outputs of ``_poly`` are C-ordered columns)."""
        mo, P, q, ne = self._m, self._P, self.q, self.n_e
        g_xy_xy = P(np.moveaxis(mo.pp, 2, 3), ((q, 1),))                       # [a, b, j]: pp[a, b, i, j] q_i
        g_z_xy = _mat(ca.DM(mo.pz.reshape(-1)) - 0.5 * P(np.moveaxis(mo.kp, 3, 1), ((q, 2),)), 2, ne)  # [b, j]
        g_xy_z = _mat(-P(mo.kp, ((q, 2),)), 2, ne)                             # [a, j]: kp[a, j, l, k] q_l q_k
        g_z_z = -P(mo.kz, ((q, 1),)) + 0.5 * P(np.moveaxis(mo.kk, 2, 0), ((q, 3),))  # [j]: kk[i, k, j, l] q_i q_k q_l
        out = []
        for j in range(ne):
            gxx = ca.vertcat(ca.horzcat(g_xy_xy[j], g_xy_xy[ne + j]),
                             ca.horzcat(g_xy_xy[2 * ne + j], g_xy_xy[3 * ne + j]))
            out.append(ca.vertcat(ca.horzcat(gxx, g_xy_z[:, j]), ca.horzcat(g_z_xy[:, j].T, g_z_z[j])))
        return out

    def mass_matrix(self) -> ca.SX:
        """``sum m B^T B`` ((6 + n_e)^2, order v, w, qd) [kg, kg m, kg m^2]."""
        m = self._m.mass
        cx = skew(self.c)
        return ca.blockcat([[m * ca.SX.eye(3), -cx, self.C],
                            [cx, self.inertia, self.coupling],
                            [self.C.T, self.coupling.T, self.me]])

    def velocity_terms(self, w: ca.SX) -> ca.SX:
        """``k = sum m B^T [w x (w x s) + 2 w x (S qd) + Sdot qd]`` (6 + n_e) for body-axes ``w``."""
        mo, ne, P, qd, q = self._m, self.n_e, self._P, self.qd, self.q
        W = skew(w)
        Cqd = self.C @ qd
        k_v = W @ (W @ self.c) + 2 * ca.cross(w, Cqd) - ca.vertcat(0, 0, P(mo.k1, ((qd, 2),)))
        H = sum((self.G[j] * qd[j] for j in range(ne)), ca.SX.zeros(3, 3))    # sum m s (S qd)^T
        kp_h = P(mo.kp, ((qd, 2), (q, 1)))                               # sum m (qd^T Ax qd) Phi_a q (2)
        k_w = ca.cross(w, self.inertia @ w) + 2 * (w * ca.trace(H) - H.T @ w) + ca.vertcat(-kp_h[1], kp_h[0], 0)
        # sum m S_j . (w x (w x s)) = w^T G_j w - |w|^2 tr G_j
        k_e = ca.vertcat(*[w.T @ self.G[j] @ w - ca.dot(w, w) * ca.trace(self.G[j]) for j in range(ne)])
        # 2 sum_k qd_k w . E[j, k], E[j, k] = sum m S_k x S_j
        k_e += 2 * self._coriolis(w)
        # sum m S_j . Sdot qd = sum m (Ax q)_j (qd^T Ax qd)
        k_e += P(mo.kk, ((q, 1), (qd, 2)))
        return ca.vertcat(k_v, k_w, k_e)

    def _coriolis(self, w: ca.SX) -> ca.SX:
        """``[sum_k qd_k w . (sum m S_k x S_j)]_j`` (n_e)."""
        mo, P, qd, q = self._m, self._P, self.qd, self.q
        # E_x[j,k] = -sum m Phi_y,k (Ax q)_j + sum m (Ax q)_k Phi_y,j ; kp[a, i, l, k] = sum m Ax_il Phi_a,k
        kpy, kpx = mo.kp[1], mo.kp[0]
        ex = P(-kpy + np.transpose(kpy, (2, 1, 0)), ((q, 1), (qd, 1)))    # (j) from [j, l, k] q_l qd_k
        ey = P(kpx - np.transpose(kpx, (2, 1, 0)), ((q, 1), (qd, 1)))
        pp = mo.pp
        ez_mat = np.asarray(pp[0, 1] - pp[1, 0]).T          # [j, k] = sum m (Phi_x,k Phi_y,j - Phi_y,k Phi_x,j)
        ez = ca.mtimes(ca.DM(ez_mat), qd)
        return w[0] * ex + w[1] * ey + w[2] * ez


def _mat(col: ca.SX, rows: int, cols: int) -> ca.SX:
    """A C-ordered (rows, cols) array stored as a column -> matrix (CasADi reshapes column-major)."""
    return ca.reshape(col, cols, rows).T


def _vee_antisym(G: ca.SX) -> ca.SX:
    """``sum m s x S_j`` from ``G_j[a, b] = sum m s_a S_bj``: ``(G_yz - G_zy, G_zx - G_xz, G_xy - G_yx)``."""
    return ca.vertcat(G[1, 2] - G[2, 1], G[2, 0] - G[0, 2], G[0, 1] - G[1, 0])


def exact_lumped_terms(moments, q: ca.SX, qd: ca.SX) -> ExactLumpedTerms:
    """:class:`ExactLumpedTerms` of a body with :class:`~mbsym.beam.nodes.NodeMoments` ``moments``."""
    return ExactLumpedTerms(moments, q, qd)
