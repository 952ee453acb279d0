"""Standard input data (SID) of a flexible beam body: shape integrals as Taylor terms.

The container :class:`ShapeIntegrals` holds the shape integrals of the paper's
Appendix A (Branlard & Geisler, WES 7, 2022), each expanded to first order in the
elastic coordinates ``q_e`` (Appendix D3), plus the unit geometric-stiffness
matrices of Appendix C and the end-node data needed to attach a child body.

Conventions (fixed; the symbolic engine relies on them)
-------------------------------------------------------
* Body frame: the undeflected beam lies along local ``z`` from ``z = 0`` (root,
  body origin) to ``z = L``. Shape ``j`` is the field ``Phi_j(z) = (Phi_jx, Phi_jy, 0)``.
* Skew matrix: ``skew(s) @ v == np.cross(s, v)``.
* A first-order term is the derivative with respect to ``q_e``:
  ``T(q_e) = order0 + sum_j order1[j] * q_e[j]``; ``order1[j] = dT/dq_e,j``.
* Geometric stiffness: ``k_sigma = K_g q_e`` sits on the LEFT side of the elastic
  equations together with ``K_e q_e`` (paper Eq. A16). Tension gives a positive
  ``K_g``. At each instant (paper Eq. C2, all vectors in the body frame)::

      K_g = sum_a (a_a - g_a) kg_t[a] + sum_a omegadot_a kg_r[a]
            + sum_ab omega_a omega_b kg_omega[a, b] + sum_a F_a kg_tip[a]

  with ``a`` the acceleration of the body origin, ``g`` the gravity vector,
  ``omega`` / ``omegadot`` the angular velocity / acceleration of the body frame,
  and ``F`` a force applied at the tip (e.g. the reaction of a child body).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Literal, Sequence

import numpy as np
from numpy.typing import ArrayLike

from mbsym.exceptions import BeamDataError, DimensionError

__all__ = ["Taylor", "ShapeIntegrals", "damping_matrix", "skew"]

_AXES = {"x": 0, "y": 1, "z": 2}


def skew(v: ArrayLike) -> np.ndarray:
    """Return the skew-symmetric matrix ``S`` of a 3-vector, with ``S @ w == v x w``.

    Parameters
    ----------
    v : array_like, shape (..., 3)
        Vector(s).

    Returns
    -------
    numpy.ndarray, shape (..., 3, 3)

    Examples
    --------
    >>> skew([1.0, 2.0, 3.0]) @ [0.0, 0.0, 1.0]
    array([ 2., -1.,  0.])
    """
    v = np.asarray(v, dtype=float)
    out = np.zeros(v.shape + (3,))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def _frozen(a: ArrayLike, name: str) -> np.ndarray:
    arr = np.array(a, dtype=float)  # copy
    if not np.all(np.isfinite(arr)):
        raise BeamDataError(f"`{name}` contains NaN or Inf; all entries must be finite numbers.")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True)
class Taylor:
    """First-order Taylor expansion of a shape integral (paper Eq. D2).

    ``T(q_e) = order0 + sum_j order1[j] * q_e[j]``.

    Parameters
    ----------
    order0 : array_like, shape S
        Value at ``q_e = 0`` (undeflected body).
    order1 : array_like, shape (n_e, *S), or None
        ``order1[j]`` is the derivative of ``T`` with respect to ``q_e[j]``.
        ``None`` means the term does not depend on ``q_e``.

    Examples
    --------
    >>> t = Taylor(np.eye(2), np.array([np.ones((2, 2))]))
    >>> t.evaluate([0.5])
    array([[1.5, 0.5],
           [0.5, 1.5]])
    """

    order0: np.ndarray
    order1: np.ndarray | None = None

    def __post_init__(self) -> None:
        o0 = _frozen(self.order0, "Taylor.order0")
        object.__setattr__(self, "order0", o0)
        if self.order1 is not None:
            o1 = _frozen(self.order1, "Taylor.order1")
            if o1.ndim != o0.ndim + 1 or o1.shape[1:] != o0.shape:
                raise DimensionError(
                    f"Taylor.order1 has shape {o1.shape}; expected (n_e, *{o0.shape}) "
                    "(one derivative array per elastic coordinate)."
                )
            object.__setattr__(self, "order1", o1)

    @property
    def n_e(self) -> int | None:
        """Number of elastic coordinates, or ``None`` for a constant term."""
        return None if self.order1 is None else self.order1.shape[0]

    def evaluate(self, qe: ArrayLike | None = None) -> np.ndarray:
        """Evaluate ``T(q_e)`` numerically.

        Parameters
        ----------
        qe : array_like, shape (n_e,), optional
            Elastic coordinates [m for tip-normalised shapes]; ``None`` means zero.

        Returns
        -------
        numpy.ndarray, shape S
        """
        if qe is None or self.order1 is None:
            return np.array(self.order0)
        q = np.asarray(qe, dtype=float).reshape(-1)
        if q.shape[0] != self.order1.shape[0]:
            raise DimensionError(
                f"q_e has {q.shape[0]} entries; expected {self.order1.shape[0]} (n_e)."
            )
        if not np.all(np.isfinite(q)):
            raise BeamDataError("q_e must be finite.")
        return self.order0 + np.tensordot(q, self.order1, axes=1)

    def select(self, idx: np.ndarray, n_dims: int) -> "Taylor":
        """Keep shapes ``idx``: slice the ``n_dims`` leading shape axes of ``order0``."""
        o0 = self.order0
        for ax in range(n_dims):
            o0 = np.take(o0, idx, axis=ax)
        o1 = None
        if self.order1 is not None:
            o1 = np.take(self.order1, idx, axis=0)
            for ax in range(n_dims):
                o1 = np.take(o1, idx, axis=ax + 1)
        return Taylor(o0, o1)


def damping_matrix(
    ke: ArrayLike,
    me: ArrayLike,
    ratios: ArrayLike,
    *,
    method: Literal["stiffness-proportional", "modal"] = "stiffness-proportional",
) -> np.ndarray:
    """Damping matrix of the elastic coordinates from one damping ratio per shape.

    Parameters
    ----------
    ke, me : array_like, shape (n_e, n_e)
        Generalized stiffness [N/m] and mass [kg].
    ratios : array_like, shape (n_e,)
        Damping ratio of each shape as a FRACTION of critical (0.01 = 1 %; ElastoDyn
        inputs are in percent: divide by 100).
    method : {"stiffness-proportional", "modal"}
        ``"stiffness-proportional"`` (ElastoDyn): column ``j`` of ``K_e`` scaled by
        ``zeta_j / (pi f_j)``, ``D[:, j] = zeta_j K[:, j] / (pi f_j)`` with
        ``f_j = sqrt(K_jj / M_jj) / (2 pi)`` the frequency of shape ``j`` alone.
        ``"modal"`` (paper App. B): diagonal ``D_jj = 2 zeta_j M_jj omega_j`` with
        ``omega_j = sqrt(K_jj / M_jj)``, exact when the shapes are orthogonal modes.
        For one shape both give ``2 zeta sqrt(K M)``.

    Returns
    -------
    numpy.ndarray, shape (n_e, n_e)
        ``D_e`` [N s/m].

    Raises
    ------
    BeamDataError
        Negative or non-finite ratios, non-positive diagonal of ``K_e`` or ``M_e``,
        unknown method.

    Examples
    --------
    >>> damping_matrix([[4.0]], [[1.0]], [0.5])
    array([[2.]])
    """
    k, m = np.asarray(ke, dtype=float), np.asarray(me, dtype=float)
    z = np.asarray(ratios, dtype=float).reshape(-1)
    n = k.shape[0]
    if z.shape[0] != n:
        raise BeamDataError(f"damping_ratios has {z.shape[0]} entries; expected {n} (one per shape).")
    if not np.all(np.isfinite(z)) or np.any(z < 0):
        raise BeamDataError(f"damping_ratios must be finite and >= 0; got {z.tolist()}.")
    kd, md = np.diag(k), np.diag(m)
    if np.any(kd <= 0) or np.any(md <= 0):
        raise BeamDataError(
            "damping needs positive diagonal generalized stiffness and mass; "
            f"got diag(K_e)={kd.tolist()}, diag(M_e)={md.tolist()}."
        )
    omega = np.sqrt(kd / md)
    if method == "stiffness-proportional":
        return k * (2.0 * z / omega)[None, :]
    if method == "modal":
        return np.diag(2.0 * z * md * omega)
    raise BeamDataError(
        f"unknown damping method {method!r}; expected 'stiffness-proportional' or 'modal'."
    )


# (field name, trailing shape as a function of n_e) used by validate()
def _expected_shapes(n: int) -> dict[str, tuple[int, ...]]:
    return {
        "ct": (n, 3), "me": (n, n), "ge": (n, n, 3), "ke": (n, n), "de": (n, n),
        "kg_t": (3, n, n), "kg_r": (3, n, n), "kg_omega": (3, 3, n, n), "kg_tip": (3, n, n),
        "end_position": (3,), "end_displacement": (3, n), "end_rotation": (3, n),
        "frequencies_hz": (n,),
    }


_TAYLOR_SHAPES = {"mxt": lambda n: (3, 3), "mtt": lambda n: (3, 3), "cr": lambda n: (n, 3),
                  "gr": lambda n: (n, 3, 3), "oe": lambda n: (n, 3, 3)}
# number of leading axes of order0 indexed by the shape number (for select())
_TAYLOR_SHAPE_AXES = {"mxt": 0, "mtt": 0, "cr": 1, "gr": 1, "oe": 1}


@dataclass(frozen=True)
class ShapeIntegrals:
    """Standard input data of a flexible beam body (paper App. A, C, D3).

    All quantities are in the body frame, about the body origin (beam root). The
    arrays are read-only copies. Build it with
    :func:`mbsym.beam.shape_integrals` or give every field directly.

    Parameters
    ----------
    mass : float
        Total mass [kg] (distributed mass plus any tip mass).
    n_e : int
        Number of shape functions / elastic coordinates.
    mxt : Taylor, 3x3
        ``M_xtheta = -int skew(s_P) dm`` (A3) [kg m]; ``order1[j] = -int skew(Phi_j) dm``.
    mtt : Taylor, 3x3
        ``M_thetatheta = -int skew(s_P) skew(s_P) dm`` (A4) [kg m^2], inertia tensor
        about the origin; ``order1[j] = -int (skew(s_P0) skew(Phi_j) + skew(Phi_j) skew(s_P0)) dm``.
        (The quadratic term in ``q_e`` is dropped, as in Wallrapp's SID.)
    ct : ndarray (n_e, 3)
        ``C_t``, ``M_xe = C_t^T = int Phi dm`` (A6) [kg].
    cr : Taylor (n_e, 3)
        ``C_r``, ``M_thetae = C_r^T = int skew(s_P) Phi dm`` (A5) [kg m];
        ``cr.order1[k, j] = int Phi_k x Phi_j dm`` [kg].
    me : ndarray (n_e, n_e)
        ``M_e = int Phi^T Phi dm`` (A7, B1) [kg].
    gr : Taylor (n_e, 3, 3)
        ``G_r,j = -2 int skew(s_P) skew(Phi_j) dm`` (A11) [kg m];
        ``order1[k, j] = -2 int skew(Phi_k) skew(Phi_j) dm``.
    ge : ndarray (n_e, n_e, 3)
        ``ge[j] = G_e,j = -2 int Phi^T skew(Phi_j) dm`` (A13) [kg].
    oe : Taylor (n_e, 3, 3)
        ``O_e,j = int skew(Phi_j) skew(s_P) dm = -1/2 G_r,j^T`` (A12) [kg m];
        ``order1[k, j] = int skew(Phi_j) skew(Phi_k) dm`` [kg]. Its first-order part
        contains the spin softening (``-m Omega^2 u`` for in-plane motion).
    ke : ndarray (n_e, n_e)
        Elastic stiffness (B2 with the twisted stiffness tensor) [N/m].
    de : ndarray (n_e, n_e)
        Damping [N s/m].
    kg_t : ndarray (3, n_e, n_e)
        Geometric stiffness per unit acceleration of the body frame along x, y, z
        [kg/m = N s^2/m^2]; enters as ``(a - g)_a kg_t[a]``.
        ``kg_t[z] = -int M_out(z) Phi_i' . Phi_j' dz`` with ``M_out(z)`` the mass
        outboard of ``z`` (incl. tip mass); ``kg_t[x] = kg_t[y] = 0``. (The minus sign,
        missing in the paper's Eq. C4, makes an upright tower under gravity negative.)
    kg_r : ndarray (3, n_e, n_e)
        Per unit angular acceleration (C7) [kg]; zero for a straight beam along z.
    kg_omega : ndarray (3, 3, n_e, n_e)
        Per unit ``omega_a omega_b`` (C6) [kg]:
        ``kg_omega[a, b] = int -e_z . (skew(e_a) skew(e_b) S(z)) Phi_i' . Phi_j' dz``
        with ``S(z) = int_z^L m s_P0 dz'`` (+ tip mass ``L e_z``). For the straight
        beam: ``kg_omega[x,x] = kg_omega[y,y] = int S_z(z) Phi_i' . Phi_j' dz > 0``
        (centrifugal stiffening), other entries zero. Spin softening is NOT here.
    kg_tip : ndarray (3, n_e, n_e)
        Per unit force at ``z = L`` along x, y, z (C5, ``z_k = L``) [1/m]:
        ``kg_tip[z] = int_0^L Phi_i' . Phi_j' dz``; x and y entries zero.
    end_position : ndarray (3,)
        Undeflected tip position ``(0, 0, L)`` [m].
    end_displacement : ndarray (3, n_e)
        ``Phi_j(L)`` [m per unit q_e].
    end_rotation : ndarray (3, n_e)
        Small rotation vector of the tip section per unit ``q_e,j`` [rad]:
        ``(-Phi_jy'(L), +Phi_jx'(L), 0)``, so that ``e_z`` turns into
        ``e_z + theta x e_z`` = the deflected tangent.
    frequencies_hz : ndarray (n_e,)
        ``sqrt(eig(K_e, M_e)) / (2 pi)`` ascending [Hz] (informational, no K_g).
    mtt2 : ndarray (n_e, n_e, 3, 3) or None
        Optional second-order term of ``M_thetatheta`` [kg]:
        ``mtt2[i, j] = -int skew(Phi_i) skew(Phi_j) dm``, so that
        ``M_thetatheta(q_e) = mtt(q_e) + sum_ij q_i q_j mtt2[i, j]`` exactly.
    nodes : mbsym.beam.nodes.LumpedNodes or None
        Optional point masses with their exact displacement field (lumped bodies, e.g.
        ElastoDyn's blades and tower): lets a :class:`~mbsym.FlexibleBody` use
        ``kinematics="exact"`` (Kane terms from the exact node positions, every order in ``q_e``).
    """

    mass: float
    n_e: int
    mxt: Taylor
    mtt: Taylor
    ct: np.ndarray
    cr: Taylor
    me: np.ndarray
    gr: Taylor
    ge: np.ndarray
    oe: Taylor
    ke: np.ndarray
    de: np.ndarray
    kg_t: np.ndarray
    kg_r: np.ndarray
    kg_omega: np.ndarray
    kg_tip: np.ndarray
    end_position: np.ndarray
    end_displacement: np.ndarray
    end_rotation: np.ndarray
    frequencies_hz: np.ndarray
    mtt2: np.ndarray | None = None
    nodes: object | None = None

    def __post_init__(self) -> None:
        for name in _expected_shapes(0):
            object.__setattr__(self, name, _frozen(getattr(self, name), name))
        if self.mtt2 is not None:
            object.__setattr__(self, "mtt2", _frozen(self.mtt2, "mtt2"))
        object.__setattr__(self, "mass", float(self.mass))
        object.__setattr__(self, "n_e", int(self.n_e))
        self.validate()

    def validate(self) -> None:
        """Check shapes, finiteness and symmetry of every field.

        Raises
        ------
        DimensionError
            A field has the wrong shape for ``n_e``.
        BeamDataError
            Non-positive mass, or ``M_e``, ``K_e``, ``M_thetatheta`` not symmetric,
            or ``M_e`` not positive definite.
        """
        n = self.n_e
        problems = []
        for name, shape in _expected_shapes(n).items():
            if getattr(self, name).shape != shape:
                problems.append(f"{name}: shape {getattr(self, name).shape}, expected {shape}")
        for name, fshape in _TAYLOR_SHAPES.items():
            t = getattr(self, name)
            if not isinstance(t, Taylor):
                problems.append(f"{name}: expected a Taylor, got {type(t).__name__}")
            elif t.order0.shape != fshape(n) or (t.order1 is not None and t.order1.shape[0] != n):
                o1 = None if t.order1 is None else t.order1.shape
                problems.append(f"{name}: order0 {t.order0.shape}, order1 {o1}; expected "
                                f"order0 {fshape(n)} and order1 ({n}, *{fshape(n)})")
        if self.mtt2 is not None and self.mtt2.shape != (n, n, 3, 3):
            problems.append(f"mtt2: shape {self.mtt2.shape}, expected {(n, n, 3, 3)}")
        if self.nodes is not None and getattr(self.nodes, "n_e", None) != n:
            problems.append(f"nodes: expected LumpedNodes with n_e={n}, got {self.nodes!r}")
        if problems:
            raise DimensionError(f"ShapeIntegrals with n_e={n} is inconsistent: " + "; ".join(problems))
        if not (np.isfinite(self.mass) and self.mass > 0):
            raise BeamDataError(f"mass must be positive and finite; got {self.mass}.")
        for name, mat in (("me", self.me), ("ke", self.ke), ("mtt.order0", self.mtt.order0)):
            scale = max(np.abs(mat).max(), 1e-300)
            if np.abs(mat - mat.T).max() > 1e-9 * scale:
                raise BeamDataError(f"{name} must be symmetric; max |A - A^T| / max|A| = "
                                    f"{np.abs(mat - mat.T).max() / scale:.2e}.")
        if n and np.linalg.eigvalsh(self.me).min() <= 0:
            raise BeamDataError("me (generalized mass) must be positive definite: a shape moves no mass "
                                "or two shapes are linearly dependent.")

    # ------------------------------------------------------------------ helpers
    @property
    def center_of_mass(self) -> np.ndarray:
        """Undeflected centre of mass ``s_CM`` [m], from ``M_xtheta = -M skew(s_CM)``."""
        a = self.mxt.order0
        return np.array([a[1, 2], a[2, 0], a[0, 1]]) / self.mass

    def mass_matrix(self, qe: ArrayLike | None = None, *, second_order: bool = False) -> np.ndarray:
        """Body mass matrix (paper Eq. A1) of size ``6 + n_e`` at ``q_e``, body frame.

        Order: translation of the origin (3), rotation (3), elastic (n_e).

        Parameters
        ----------
        qe : array_like, shape (n_e,), optional
            Elastic coordinates; ``None`` means zero.
        second_order : bool, keyword-only
            Add the quadratic term ``mtt2`` to ``M_thetatheta`` (needs ``mtt2``).

        Returns
        -------
        numpy.ndarray, shape (6 + n_e, 6 + n_e)
        """
        n = self.n_e
        mxt, mtt, cr = self.mxt.evaluate(qe), self.mtt.evaluate(qe), self.cr.evaluate(qe)
        if second_order and qe is not None:
            if self.mtt2 is None:
                raise BeamDataError("second_order=True needs the mtt2 term; build with shape_integrals().")
            q = np.asarray(qe, dtype=float).reshape(-1)
            mtt = mtt + np.einsum("i,j,ijab->ab", q, q, self.mtt2)
        out = np.zeros((6 + n, 6 + n))
        out[:3, :3] = self.mass * np.eye(3)
        out[:3, 3:6], out[3:6, :3] = mxt, mxt.T
        out[3:6, 3:6] = mtt
        out[:3, 6:], out[6:, :3] = self.ct.T, self.ct
        out[3:6, 6:], out[6:, 3:6] = cr.T, cr
        out[6:, 6:] = self.me
        return out

    def geometric_stiffness(
        self,
        *,
        acceleration: ArrayLike = (0.0, 0.0, 0.0),
        gravity: ArrayLike = (0.0, 0.0, 0.0),
        angular_velocity: ArrayLike = (0.0, 0.0, 0.0),
        angular_acceleration: ArrayLike = (0.0, 0.0, 0.0),
        tip_force: ArrayLike = (0.0, 0.0, 0.0),
    ) -> np.ndarray:
        """Numeric ``K_g`` (paper Eq. C2) for given loads, all in the body frame.

        Parameters
        ----------
        acceleration : array_like (3,)
            Acceleration of the body origin [m/s^2].
        gravity : array_like (3,)
            Gravity vector [m/s^2], e.g. ``(0, 0, -9.81)`` for an upright tower.
        angular_velocity, angular_acceleration : array_like (3,)
            Of the body frame [rad/s], [rad/s^2].
        tip_force : array_like (3,)
            Force applied at the tip [N] (tension positive along +z).

        Returns
        -------
        numpy.ndarray, shape (n_e, n_e)
            ``K_g`` [N/m], to be added to ``K_e`` on the left-hand side.

        Examples
        --------
        The self-weight of an upright tower softens it: ``geometric_stiffness(
        gravity=(0, 0, -9.81))`` is negative definite.
        """
        a = np.asarray(acceleration, float) - np.asarray(gravity, float)
        w = np.asarray(angular_velocity, float)
        return (np.tensordot(a, self.kg_t, 1) + np.tensordot(np.asarray(angular_acceleration, float), self.kg_r, 1)
                + np.einsum("a,b,abij->ij", w, w, self.kg_omega)
                + np.tensordot(np.asarray(tip_force, float), self.kg_tip, 1))

    def with_damping(
        self,
        ratios: ArrayLike | None = None,
        *,
        method: Literal["stiffness-proportional", "modal"] = "stiffness-proportional",
        matrix: ArrayLike | None = None,
    ) -> "ShapeIntegrals":
        """Return a copy with a new damping matrix.

        Parameters
        ----------
        ratios : array_like (n_e,), optional
            Damping ratios (fractions of critical), see :func:`damping_matrix`.
        method : {"stiffness-proportional", "modal"}
            See :func:`damping_matrix`.
        matrix : array_like (n_e, n_e), optional
            Explicit ``D_e`` [N s/m] instead of ratios.

        Returns
        -------
        ShapeIntegrals
        """
        if (ratios is None) == (matrix is None):
            raise BeamDataError("give exactly one of `ratios` or `matrix` to with_damping().")
        de = damping_matrix(self.ke, self.me, ratios, method=method) if matrix is None else matrix
        return dataclasses.replace(self, de=np.asarray(de, dtype=float))

    def select(self, indices: Sequence[int]) -> "ShapeIntegrals":
        """Return the SID restricted to the shapes ``indices`` (in that order).

        Parameters
        ----------
        indices : sequence of int
            Shape numbers to keep (0-based).

        Returns
        -------
        ShapeIntegrals
        """
        idx = np.asarray(indices, dtype=int).reshape(-1)
        if idx.size and (idx.min() < -self.n_e or idx.max() >= self.n_e):
            raise DimensionError(f"shape indices {idx.tolist()} out of range for n_e={self.n_e}.")

        def sq(a: np.ndarray, lead: int = 0) -> np.ndarray:
            return np.take(np.take(a, idx, axis=lead), idx, axis=lead + 1)

        me, ke = sq(self.me), sq(self.ke)
        freqs = _frequencies(ke, me) if idx.size else np.zeros(0)
        return ShapeIntegrals(
            mass=self.mass, n_e=idx.size,
            mxt=Taylor(self.mxt.order0, None if self.mxt.order1 is None else self.mxt.order1[idx]),
            mtt=Taylor(self.mtt.order0, None if self.mtt.order1 is None else self.mtt.order1[idx]),
            ct=self.ct[idx], cr=self.cr.select(idx, 1), me=me,
            gr=self.gr.select(idx, 1), ge=sq(self.ge), oe=self.oe.select(idx, 1),
            ke=ke, de=sq(self.de), kg_t=sq(self.kg_t, 1), kg_r=sq(self.kg_r, 1),
            kg_omega=sq(self.kg_omega, 2), kg_tip=sq(self.kg_tip, 1),
            end_position=self.end_position, end_displacement=self.end_displacement[:, idx],
            end_rotation=self.end_rotation[:, idx], frequencies_hz=freqs,
            mtt2=None if self.mtt2 is None else sq(self.mtt2),
            nodes=None if self.nodes is None else self.nodes.select(idx),
        )


def _frequencies(ke: np.ndarray, me: np.ndarray) -> np.ndarray:
    """``sqrt(eig(K, M)) / 2 pi`` ascending [Hz]; negative eigenvalues give NaN-free 0.

    Cholesky reduction ``L^-1 K L^-T`` with numpy (scipy.linalg is not imported on the model-building
    path: import time of mbsym).
    """
    L = np.linalg.cholesky(me)
    B = np.linalg.solve(L, np.linalg.solve(L, ke).T)       # L^-1 K L^-T (K symmetric)
    lam = np.linalg.eigvalsh(0.5 * (B + B.T))
    return np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * np.pi)


def axis_index(axis: str | int) -> int:
    """Map ``"x"|"y"|"z"`` or 0..2 to an axis index (raises BeamDataError)."""
    if isinstance(axis, str) and axis.lower() in _AXES:
        return _AXES[axis.lower()]
    if isinstance(axis, (int, np.integer)) and 0 <= int(axis) < 3:
        return int(axis)
    raise BeamDataError(f"axis must be 'x', 'y', 'z' or 0, 1, 2; got {axis!r}.")
