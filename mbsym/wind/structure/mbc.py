"""Multi-blade coordinate (Coleman) transformation of rotor models (Bir 2008, NREL/CP-500-42553).

A three-bladed rotor's blade coordinates ``q_b`` (one DOF type, blades ``b = 1, 2, 3`` at
azimuths ``psi_b = psi + 2 pi (b - 1) / 3``, ``psi`` the azimuth of blade 1 increasing with the
rotation) are written in the fixed frame as

``q_b = q_0 + q_c cos(psi_b) + q_s sin(psi_b)``,

a collective coordinate ``q_0`` and the cosine and sine cyclic coordinates ``q_c``, ``q_s``
(for out-of-plane DOFs, tilt and yaw of the tip-path plane). Per DOF type ``q = T1 z`` with
``T1[b] = [1, cos psi_b, sin psi_b]``; ``T2 = dT1/dpsi`` and ``T3 = d^2T1/dpsi^2``. With the
rotor speed ``Omega = dpsi/dt`` and ``dOmega/dt``:

* second order: ``q' = T1 z' + Omega T2 z``, ``q'' = T1 z'' + 2 Omega T2 z' + (Omega^2 T3 +
  dOmega/dt T2) z``, so ``M q'' + C q' + K q`` becomes ``M_B z'' + C_B z' + K_B z`` with
  ``M_B = M T1``, ``C_B = 2 Omega M T2 + C T1``, ``K_B = Omega^2 M T3 + dOmega/dt M T2 +
  Omega C T2 + K T1`` (Bir's Eq. 10), premultiplied here by ``T1^-1``;
* first order, ``x = [q; q']``: ``x = T x_B`` with ``T = [[T1, 0], [Omega T2, T1]]``, so
  ``A_B = T^-1 (A T - dT/dt)`` and ``B_B = T^-1 B``.

Coordinates that are not blade coordinates (tower, drivetrain, platform …) are left
unchanged. The transformed coordinates keep the positions of the blade triplets: the
entries of blades 1, 2, 3 become collective, cosine and sine. Blade coordinates are
recognised by their names ``B<k><type>`` (:data:`BLADE_COORDINATE`, the one place that
defines them): :func:`blade_indices` finds the triplets, :func:`mbc_coordinate_names` names
the transformed coordinates.

Azimuth convention: ``psi`` is ElastoDyn's ``Azimuth`` output (notes §6), ``q_GeAz + q_DrTr +
AzimB1Up + π/2`` (:func:`blade1_azimuth`). A constant offset (AzimB1Up) only rotates the
(cosine, sine) pair, which leaves eigenvalues and whirl directions unchanged.

**General first-order systems** (:func:`mbc_system`): any state, input or output may come in
per-blade triplets (blade DOFs and their speeds, pitch actuators, the dynamic-wake states of
the same node on each blade, per-blade pitch commands, root moments …). Each triplet ``b``
is ``x_b = T1 z_b``; a triplet that is the time derivative of another (``B1F1_d`` of
``B1F1``) is ``x_d = T1 z_d + Omega T2 z``, as in the first-order form above, so that its
fixed-frame coordinates are the derivatives of the other's. With the full ``T`` and ``dT/dt``
(:func:`mbc_state_matrices`): ``A_B = T^-1 (A T - dT/dt)``, ``B_B = T^-1 B T_u``,
``C_B = T_y^-1 C T``, ``D_B = T_y^-1 D T_u`` (``T_u``, ``T_y`` of the input and output
triplets, ``T1`` only). :func:`rotating_triplets` finds the triplets by name and
:func:`mbc_names` names the results (``B1N5_vind_x`` -> ``N5_vind_x_coll``, ``BlPitch1_d``
-> ``BlPitch_coll_d``, ``RootMyc1`` -> ``RootMyc_coll``, ``_cos``, ``_sin``). For an
out-of-plane quantity of blade-1 azimuth ``psi`` measured from the upward vertical (ElastoDyn's
``Azimuth``), the cosine component is the tilt (vertical asymmetry of the rotor disk) and the
sine component the yaw (horizontal asymmetry) combination.

In the fixed frame, a rotating-frame blade mode of frequency ``w`` on an isolated rotor
appears as a collective mode at ``w`` and two whirling modes: forward (the cyclic pattern
travels with the rotor) at ``w + Omega`` and backward at ``w - Omega``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Sequence

import numpy as np

from ...exceptions import DimensionError, ModelDefinitionError
from .dofs import (BLADE_COORDINATE, N_BLADES, blade1_azimuth, blade_dof, blade_indices,  # noqa: F401
                              mbc_coordinate_names)

__all__ = ["BladeFrame", "ColemanMatrices", "coleman_matrices", "mbc_transform", "mbc_second_order", "whirl_components",
           "whirl_coordinates", "rotating_triplets", "mbc_names", "derivative_pairs", "mbc_state_matrices", "mbc_system", "BLADE_COORDINATE", "blade_dof", "blade_indices", "mbc_coordinate_names",
           "blade1_azimuth", "N_BLADES"]

@dataclass(frozen=True)
class ColemanMatrices:
    """Full-size transformation matrices for one azimuth (``q = T1 z``).

    Attributes
    ----------
    T1, T2, T3 : ndarray (n_q, n_q)
        ``T1`` and its first and second derivatives with respect to the azimuth; identity
        (``T1``) and zero (``T2``, ``T3``) outside the blade triplets.
    """

    T1: np.ndarray
    T2: np.ndarray
    T3: np.ndarray


def _groups(blade_indices: Sequence[Sequence[int]], n_q: int) -> list[tuple[int, ...]]:
    groups = [tuple(int(i) for i in g) for g in blade_indices]
    flat = [i for g in groups for i in g]
    bad = [g for g in groups if len(g) != N_BLADES]
    if bad:
        raise ModelDefinitionError(f"the multi-blade transformation needs {N_BLADES} blades: each group of blade "
                                   f"coordinates must list {N_BLADES} indices (blades 1, 2, 3); got {bad}.")
    out = [i for i in flat if not 0 <= i < n_q]
    if out or len(set(flat)) != len(flat):
        raise ModelDefinitionError(f"blade coordinate indices must be distinct and in 0..{n_q - 1}; got {groups}.")
    return groups


def coleman_matrices(n_q: int, blade_indices: Sequence[Sequence[int]], azimuth: float) -> ColemanMatrices:
    """``T1``, ``T2``, ``T3`` of the multi-blade transformation at one azimuth.

    Parameters
    ----------
    n_q : int
        Number of coordinates.
    blade_indices : sequence of triplets
        For each blade DOF type, the indices of blades 1, 2, 3 in ``q``.
    azimuth : float
        Azimuth of blade 1 [rad] (blades 2, 3 at +120°, +240° in the direction of rotation).

    Returns
    -------
    ColemanMatrices

    Examples
    --------
    >>> T = coleman_matrices(3, [(0, 1, 2)], 0.0)
    >>> T.T1.round(3).tolist()
    [[1.0, 1.0, 0.0], [1.0, -0.5, 0.866], [1.0, -0.5, -0.866]]
    """
    groups = _groups(blade_indices, n_q)
    T1, T2, T3 = np.eye(n_q), np.zeros((n_q, n_q)), np.zeros((n_q, n_q))
    psi = float(azimuth) + 2 * np.pi * np.arange(N_BLADES) / N_BLADES
    c, s = np.cos(psi), np.sin(psi)
    for g in groups:
        rows = np.array(g)
        T1[np.ix_(rows, rows)] = np.column_stack([np.ones(N_BLADES), c, s])
        T2[np.ix_(rows, rows)] = np.column_stack([np.zeros(N_BLADES), -s, c])
        T3[np.ix_(rows, rows)] = np.column_stack([np.zeros(N_BLADES), -c, -s])
    return ColemanMatrices(T1, T2, T3)


def mbc_transform(A, blade_indices: Sequence[Sequence[int]], azimuth: float, rotor_speed: float, *,
                  B=None, rotor_acceleration: float = 0.0):
    """First-order model ``x' = A x (+ B u)``, ``x = [q; q']``, in multi-blade coordinates.

    Parameters
    ----------
    A : array (2 n_q, 2 n_q)
        State matrix in the rotating frame (e.g. ``mbsym.linearize(...).A``).
    blade_indices : sequence of triplets
        For each blade DOF type, the indices of blades 1, 2, 3 in ``q``.
    azimuth : float
        Azimuth of blade 1 at the operating point [rad].
    rotor_speed : float
        ``dpsi/dt`` [rad/s].
    B : array (2 n_q, n_u), optional, keyword-only
        Input matrix, transformed as ``T^-1 B`` (inputs themselves are not transformed).
    rotor_acceleration : float, optional, keyword-only
        ``d^2psi/dt^2`` [rad/s^2] (default 0).

    Returns
    -------
    ndarray or (ndarray, ndarray)
        ``A_B`` (and ``B_B`` when ``B`` is given), states ``[z; z']`` with the blade triplets
        replaced by (collective, cosine, sine).

    Raises
    ------
    DimensionError
        ``A`` is not square of even size, or ``B`` has the wrong number of rows.
    ModelDefinitionError
        Bad blade index groups.

    Examples
    --------
    Three uncoupled blades (rotating-frame frequency 1 rad/s) spinning at 0.3 rad/s: the
    fixed-frame frequencies are 1 (collective) and 1 ± 0.3 (whirl).

    >>> import numpy as np
    >>> A = np.block([[np.zeros((3, 3)), np.eye(3)], [-np.eye(3), np.zeros((3, 3))]])
    >>> lam = np.linalg.eigvals(mbc_transform(A, [(0, 1, 2)], 0.4, 0.3))
    >>> np.sort(lam.imag[lam.imag > 0]).round(6).tolist()
    [0.7, 1.0, 1.3]
    """
    A = np.asarray(A, dtype=float)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] % 2:
        raise DimensionError(f"A must be square with 2 n_q rows (x = [q; qd]); got shape {A.shape}.")
    n = A.shape[0] // 2
    T = coleman_matrices(n, blade_indices, azimuth)
    om, al = float(rotor_speed), float(rotor_acceleration)
    Z = np.zeros((n, n))
    Tx = np.block([[T.T1, Z], [om * T.T2, T.T1]])
    Tdot = np.block([[om * T.T2, Z], [om**2 * T.T3 + al * T.T2, om * T.T2]])
    A_B = np.linalg.solve(Tx, A @ Tx - Tdot)
    if B is None:
        return A_B
    B = np.asarray(B, dtype=float)
    if B.ndim != 2 or B.shape[0] != 2 * n:
        raise DimensionError(f"B must have {2 * n} rows (x = [q; qd]); got shape {B.shape}.")
    return A_B, np.linalg.solve(Tx, B)


def mbc_second_order(M, C, K, blade_indices: Sequence[Sequence[int]], azimuth: float, rotor_speed: float, *,
                     rotor_acceleration: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``M``, ``C``, ``K`` (rotating frame) in multi-blade coordinates, premultiplied by ``T1^-1``.

    Returns ``(M_B, C_B, K_B)`` with ``M_B = T1^-1 M T1``, ``C_B = T1^-1 (2 Omega M T2 + C T1)``
    and ``K_B = T1^-1 (Omega^2 M T3 + dOmega/dt M T2 + Omega C T2 + K T1)``; the state
    matrix built from them equals :func:`mbc_transform` of the rotating-frame state matrix.

    Examples
    --------
    >>> import numpy as np
    >>> M, C, K = np.eye(3), np.zeros((3, 3)), np.eye(3)
    >>> _, C_B, K_B = mbc_second_order(M, C, K, [(0, 1, 2)], 0.0, 0.5)
    >>> (C_B.round(6) + 0.0).tolist()[1], (K_B.round(6) + 0.0).tolist()[1]
    ([0.0, 0.0, 1.0], [0.0, 0.75, 0.0])
    """
    M, C, K = (np.asarray(a, dtype=float) for a in (M, C, K))
    n = M.shape[0]
    for name, a in (("M", M), ("C", C), ("K", K)):
        if a.shape != (n, n):
            raise DimensionError(f"{name} has shape {a.shape}; expected ({n}, {n}) like M.")
    T = coleman_matrices(n, blade_indices, azimuth)
    om, al = float(rotor_speed), float(rotor_acceleration)
    M_B = np.linalg.solve(T.T1, M @ T.T1)
    C_B = np.linalg.solve(T.T1, 2 * om * M @ T.T2 + C @ T.T1)
    K_B = np.linalg.solve(T.T1, om**2 * M @ T.T3 + al * M @ T.T2 + om * C @ T.T2 + K @ T.T1)
    return M_B, C_B, K_B


def whirl_coordinates(cosine, sine):
    """Forward and backward whirl components ``((v_c + i v_s)/√2, (v_c - i v_s)/√2)`` of a cyclic pair.

    A unitary change of basis of the (cosine, sine) pair for an eigenvector of ``exp(i w t)``
    (``w > 0``): forward whirl (the pattern travels with the rotation) is ``v_s = -i v_c``,
    backward ``v_s = +i v_c``. Inner products are kept:
    ``conj(f_u) f_v + conj(b_u) b_v = conj(u_c) v_c + conj(u_s) v_s``, so energies split too.

    Examples
    --------
    >>> f, b = whirl_coordinates(1.0, -1j)
    >>> print(round(abs(f) ** 2, 12), round(abs(b) ** 2, 12))
    2.0 0.0
    """
    r = np.sqrt(0.5)
    return r * (cosine + 1j * sine), r * (cosine - 1j * sine)


def whirl_components(cosine: complex, sine: complex) -> tuple[float, float]:
    """Forward and backward whirl amplitudes² of a cyclic pair of an eigenvector.

    For an eigenvector of ``exp(i w t)`` (``w > 0``) with cosine and sine components
    ``v_c``, ``v_s``: forward whirl (the cyclic pattern travels in the direction of
    rotation) is ``v_s = -i v_c``, backward ``v_s = +i v_c``. Returns
    ``(|v_c + i v_s|^2 / 2, |v_c - i v_s|^2 / 2)``; they add up to ``|v_c|^2 + |v_s|^2``.

    Examples
    --------
    >>> whirl_components(1.0, -1j)
    (2.0, 0.0)
    """
    f = abs(cosine + 1j * sine) ** 2 / 2
    b = abs(cosine - 1j * sine) ** 2 / 2
    return float(f), float(b)


class BladeFrame:
    """The rotating frame of a rotor's blade DOFs, for :func:`mbsym.linear.linearize_azimuths`.

    Writes each azimuth's linear model in multi-blade coordinates (:func:`mbc_transform`
    for A, B; :func:`mbc_second_order` for M, C, K; outputs by ``Cy T``), so that the
    average over azimuths is the fixed-frame model OpenFAST's MBC3 gives.

    Parameters
    ----------
    coordinates : sequence of str
        The model's coordinates; blade DOFs are found by name (:func:`blade_indices`).
    spinning : str, optional
        The spinning coordinate (``"GeAz"``): the blade-1 azimuth is its value plus
        ``offset`` plus the drivetrain torsion ``DrTr`` when that is a coordinate.
    offset : float, optional
        Blade-1 azimuth minus the spinning coordinate [rad]: ElastoDyn's
        ``AzimB1Up + π/2`` for a turbine's GeAz, 0 otherwise.
    """

    def __init__(self, coordinates: Sequence[str], *, spinning: str = "GeAz", offset: float = 0.0) -> None:
        self.coordinates = tuple(coordinates)
        self.groups = blade_indices(self.coordinates)
        self.offset = float(offset)
        self._torsion = (self.coordinates.index("DrTr") if spinning == "GeAz" and "DrTr" in self.coordinates
                         else None)

    def azimuths(self, psi: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Blade-1 azimuth [rad] at each sample: spinning coordinate ``psi`` + offset (+ DrTr)."""
        torsion = X[:, self._torsion] if self._torsion is not None else 0.0
        return np.asarray(psi, dtype=float) + torsion + self.offset

    def to_fixed_frame(self, lin, azimuth: float, rotor_speed: float):
        """One :class:`~mbsym.linear.LinearModel` in multi-blade coordinates at blade-1 ``azimuth`` [rad]."""
        from ...linear import LinearModel

        om, n = rotor_speed, len(lin.coordinates)
        A, B = mbc_transform(lin.A, self.groups, azimuth, om, B=lin.B)
        M, C, K = mbc_second_order(lin.M, lin.C, lin.K, self.groups, azimuth, om)
        T = coleman_matrices(n, self.groups, azimuth)
        Tx = np.block([[T.T1, np.zeros((n, n))], [om * T.T2, T.T1]])
        Q = np.linalg.solve(T.T1, lin.Q)
        return LinearModel(M, C, K, Q, A, B, lin.coordinates, lin.states, lin.inputs, lin.operating_point,
                           lin.outputs, lin.Cy @ Tx, lin.Dy, lin.output_units, lin.method, units=dict(lin.units),
                           input_units=lin.input_units)


#: Per-blade names: a leading ``B<k>`` followed by a letter (``B1F1``, ``B2N7_vind_x``), or a trailing blade
#: number, optionally before ``_d`` (``BlPitch3``, ``BlPitch3_d``, ``RootMyc2``, ``BlPitchCom1``).
_LEADING = re.compile(r"B([1-9])(?=[A-Za-z])(.*)")
_TRAILING = re.compile(r"(.*\D)([1-9])(_d)?")


def _blade_key(name: str) -> tuple[tuple[str, str, str], int] | None:
    m = _LEADING.fullmatch(name)
    if m:
        return ("lead", m.group(2), ""), int(m.group(1))
    m = _TRAILING.fullmatch(name)
    if m:
        return ("trail", m.group(1), m.group(3) or ""), int(m.group(2))
    return None


def rotating_triplets(names: Sequence[str]) -> list[tuple[int, int, int]]:
    """Index triplets (blades 1, 2, 3) of the per-blade names in ``names`` (module docstring).

    A name belongs to a triplet when the names with the other blade numbers are there too;
    triplets are listed in the order of their blade-1 name.

    Examples
    --------
    >>> rotating_triplets(["TFA1", "B1F1", "B2F1", "B3F1", "BlPitch1", "BlPitch2", "BlPitch3", "TFA2"])
    [(1, 2, 3), (4, 5, 6)]
    """
    groups: dict[tuple[str, str, str], dict[int, int]] = {}
    for i, name in enumerate(names):
        key = _blade_key(str(name))
        if key is not None:
            groups.setdefault(key[0], {})[key[1]] = i
    out = [tuple(g[b] for b in range(1, N_BLADES + 1)) for g in groups.values()
           if set(g) == set(range(1, N_BLADES + 1))]
    return sorted(out)


def mbc_names(names: Sequence[str], triplets: Sequence[Sequence[int]]) -> tuple[str, ...]:
    """``names`` with each triplet renamed collective, cosine, sine (module docstring).

    Examples
    --------
    >>> mbc_names(["B1F1_d", "B2F1_d", "B3F1_d", "RootMyc1", "RootMyc2", "RootMyc3"], [(0, 1, 2), (3, 4, 5)])
    ('F1_coll_d', 'F1_cos_d', 'F1_sin_d', 'RootMyc_coll', 'RootMyc_cos', 'RootMyc_sin')
    """
    out = list(names)
    for g in triplets:
        key = _blade_key(str(names[g[0]]))
        if key is None:
            raise ModelDefinitionError(f"{names[g[0]]!r} is not a per-blade name (B<k>..., or ...<k>, ...<k>_d).")
        (kind, stem, tail), _ = key
        if kind == "lead" and stem.endswith("_d"):
            stem, tail = stem[:-2], "_d"
        for i, part in zip(g, ("coll", "cos", "sin")):
            out[i] = f"{stem}_{part}{tail}"
    return tuple(out)


def derivative_pairs(names: Sequence[str], triplets: Sequence[Sequence[int]]) -> list[tuple[int, int]]:
    """Pairs ``(a, b)`` of triplet numbers where triplet ``b`` is named as the derivative of ``a`` (``X``, ``X_d``).

    Examples
    --------
    >>> derivative_pairs(["B1F1", "B2F1", "B3F1", "B1F1_d", "B2F1_d", "B3F1_d"], [(0, 1, 2), (3, 4, 5)])
    [(0, 1)]
    """
    first = {str(names[g[0]]): k for k, g in enumerate(triplets)}
    pairs = []
    for k, g in enumerate(triplets):
        name = str(names[g[0]])
        if name.endswith("_d") and name[:-2] in first:
            pairs.append((first[name[:-2]], k))
    return pairs


def mbc_state_matrices(n: int, triplets: Sequence[Sequence[int]], azimuth: float, rotor_speed: float = 0.0, *,
                       derivatives: Sequence[tuple[int, int]] = (), rotor_acceleration: float = 0.0
                       ) -> tuple[np.ndarray, np.ndarray]:
    """``T`` and ``dT/dt`` of ``x = T z`` for a vector with per-blade triplets (module docstring).

    Parameters
    ----------
    n : int
        Size of the vector.
    triplets : sequence of triplets
        Indices of blades 1, 2, 3 for each per-blade quantity.
    azimuth : float
        Blade-1 azimuth [rad].
    rotor_speed : float, optional
        [rad/s] (enters ``dT/dt`` and the derivative blocks).
    derivatives : sequence of (int, int), optional, keyword-only
        ``(a, b)``: triplet ``b`` is the time derivative of triplet ``a`` (numbers in ``triplets``).
    rotor_acceleration : float, optional, keyword-only
        [rad/s²].

    Returns
    -------
    (ndarray, ndarray)
        ``T`` and ``dT/dt``, (n, n).

    Examples
    --------
    The first-order form of :func:`mbc_transform`:

    >>> T, Td = mbc_state_matrices(6, [(0, 1, 2), (3, 4, 5)], 0.3, 0.5, derivatives=[(0, 1)])
    >>> C = coleman_matrices(3, [(0, 1, 2)], 0.3)
    >>> bool(np.allclose(T[3:, :3], 0.5 * C.T2) and np.allclose(Td[:3, :3], 0.5 * C.T2))
    True
    """
    groups = _groups(triplets, n)
    blocks = coleman_matrices(N_BLADES, [tuple(range(N_BLADES))], azimuth)
    T1, T2, T3 = blocks.T1, blocks.T2, blocks.T3
    om, al = float(rotor_speed), float(rotor_acceleration)
    T, Td = np.eye(n), np.zeros((n, n))
    for g in groups:
        T[np.ix_(g, g)] = T1
        Td[np.ix_(g, g)] = om * T2
    for a, b in derivatives:
        if not (0 <= a < len(groups) and 0 <= b < len(groups)) or a == b:
            raise ModelDefinitionError(f"derivative pair {(a, b)} must name two different triplets of "
                                       f"0..{len(groups) - 1}.")
        T[np.ix_(groups[b], groups[a])] = om * T2
        Td[np.ix_(groups[b], groups[a])] = om**2 * T3 + al * T2
    return T, Td


def mbc_system(A, B, C, D, azimuth: float, rotor_speed: float, *, states: Sequence[Sequence[int]] = (),
               derivatives: Sequence[tuple[int, int]] = (), inputs: Sequence[Sequence[int]] = (),
               outputs: Sequence[Sequence[int]] = (), rotor_acceleration: float = 0.0):
    """A linear model ``(A, B, C, D)`` at one azimuth in multi-blade coordinates (module docstring).

    Parameters
    ----------
    A, B, C, D : array
        (n_x, n_x), (n_x, n_u), (n_y, n_x), (n_y, n_u).
    azimuth, rotor_speed : float
        Blade-1 azimuth [rad] and ``dpsi/dt`` [rad/s].
    states, inputs, outputs : sequence of triplets, keyword-only
        Per-blade triplets of each vector (:func:`rotating_triplets`).
    derivatives : sequence of (int, int), keyword-only
        State triplets that are derivatives of others (:func:`derivative_pairs`).
    rotor_acceleration : float, keyword-only
        [rad/s²].

    Returns
    -------
    tuple of ndarray
        ``(A_B, B_B, C_B, D_B)``.

    Raises
    ------
    DimensionError
        Inconsistent shapes.

    Examples
    --------
    Per-blade first-order lags ``x_b' = -x_b + u_b`` with outputs ``y_b = x_b``: an isotropic
    rotor, so the fixed-frame model is constant: the collective stays a lag, the cyclic pair
    couples through the rotation (``-Omega`` and ``+Omega`` off the diagonal).

    >>> A, I = -np.eye(3), np.eye(3)
    >>> Ab, Bb, Cb, Db = mbc_system(A, I, I, np.zeros((3, 3)), 0.7, 0.5, states=[(0, 1, 2)], inputs=[(0, 1, 2)],
    ...                             outputs=[(0, 1, 2)])
    >>> (Ab.round(12) + 0.0).tolist(), bool(np.allclose(Bb, I) and np.allclose(Cb, I))
    ([[-1.0, 0.0, 0.0], [0.0, -1.0, -0.5], [0.0, 0.5, -1.0]], True)
    """
    A, B, C, D = (np.asarray(M, dtype=float) for M in (A, B, C, D))
    nx, nu, ny = A.shape[0], B.shape[1], C.shape[0]
    if A.shape != (nx, nx) or B.shape != (nx, nu) or C.shape != (ny, nx) or D.shape != (ny, nu):
        raise DimensionError(f"inconsistent shapes A {A.shape}, B {B.shape}, C {C.shape}, D {D.shape}; expected "
                             "(n_x, n_x), (n_x, n_u), (n_y, n_x), (n_y, n_u).")
    T, Td = mbc_state_matrices(nx, states, azimuth, rotor_speed, derivatives=derivatives,
                               rotor_acceleration=rotor_acceleration)
    Tu = mbc_state_matrices(nu, inputs, azimuth)[0]
    Ty = mbc_state_matrices(ny, outputs, azimuth)[0]
    return (np.linalg.solve(T, A @ T - Td), np.linalg.solve(T, B @ Tu), np.linalg.solve(Ty, C @ T),
            np.linalg.solve(Ty, D @ Tu))
