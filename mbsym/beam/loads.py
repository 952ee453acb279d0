"""Distributed loads on a beam as shape integrals (paper Eqs. A17-A19).

A distributed force per unit length ``p(z, t) = w(z) P(t) d`` — a fixed profile
``w`` [-], a time-varying magnitude ``P`` [N/m] and a fixed direction ``d`` in the
body frame — contributes, per unit ``P``,

- the resultant ``f_x = ∫ w d dz`` [m],
- its moment about the body origin ``f_θ = ∫ s_P × w d dz``, a Taylor term in q_e
  (``∫ s_P0 × w d dz + Σ_j q_e,j ∫ Φ_j × w d dz``) [m^2],
- the generalized forces ``f_e,j = ∫ Φ_j · w d dz`` [m].

All integrals are computed once here; the engine multiplies them by ``P``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from mbsym.beam.integrals import _as_shapes, _common_length, check_stations, quadrature_weights
from mbsym.beam.shapes import ShapeFunction
from mbsym.beam.sid import Taylor
from mbsym.exceptions import BeamDataError

__all__ = ["DistributedLoadIntegrals", "distributed_load_integrals"]


@dataclass(frozen=True)
class DistributedLoadIntegrals:
    """Shape integrals of a distributed load profile, per unit magnitude.

    Attributes
    ----------
    force : ndarray (3,)
        Resultant ``∫ w d dz`` in body axes [m].
    moment : Taylor
        Moment about the body origin, order0 (3,) [m^2] and order1 (n_e, 3) [m].
    generalized : ndarray (n_e,)
        ``∫ Φ_j · w d dz`` [m] (shapes normalized to unit tip deflection).
    """

    force: np.ndarray
    moment: Taylor
    generalized: np.ndarray

    @property
    def n_e(self) -> int:
        """Number of shape functions."""
        return int(self.generalized.shape[0])


def distributed_load_integrals(z: ArrayLike, shapes: ShapeFunction | Sequence[ShapeFunction],
                               profile: ArrayLike | Callable[[np.ndarray], ArrayLike] = 1.0, *,
                               direction: str | ArrayLike = "x",
                               quadrature: str = "simpson") -> DistributedLoadIntegrals:
    """Integrals of a distributed load ``w(z) P(t) d`` over a beam along body z.

    Parameters
    ----------
    z : array_like (n,)
        Strictly increasing stations [m] spanning the loaded part of the beam.
    shapes : ShapeFunction or sequence of them
        The body's shape functions, in the order of its elastic coordinates.
    profile : float, array_like (n,) or callable, optional
        Dimensionless profile ``w(z)`` (default 1: uniform).
    direction : {'x', 'y', 'z'} or array_like (3,), keyword-only
        Load direction in body axes (normalized here).
    quadrature : {'simpson', 'trapezoid'}, keyword-only
        Rule on the stations.

    Returns
    -------
    DistributedLoadIntegrals

    Raises
    ------
    BeamDataError
        Bad stations, profile of the wrong length or not finite, zero direction.

    Examples
    --------
    >>> from mbsym.beam import PolynomialShape
    >>> s = PolynomialShape([1.0], 10.0)          # (z/L)^2 along x
    >>> li = distributed_load_integrals(np.linspace(0, 10, 101), [s])
    >>> round(float(li.generalized[0]), 6)          # ∫ (z/L)^2 dz = L/3
    3.333333
    """
    shapes = _as_shapes(shapes)
    length = _common_length(shapes)
    zz = check_stations(z)
    if zz[0] < -1e-9 * length or zz[-1] > length * (1 + 1e-9):
        raise BeamDataError(f"load stations span [{zz[0]:g}, {zz[-1]:g}] m, outside the beam [0, {length:g}] m; "
                            "give stations on the beam.")
    wq = quadrature_weights(zz, quadrature)
    w = np.asarray(profile(zz) if callable(profile) else profile, dtype=float)
    if w.ndim == 0:
        w = np.full(zz.shape, float(w))
    if w.shape != zz.shape or not np.all(np.isfinite(w)):
        raise BeamDataError(f"load profile must give {zz.size} finite values (one per station); got shape {w.shape}.")
    d = _direction(direction)
    phi = np.stack([s.evaluate(zz, 0) for s in shapes])        # (n_e, 3, n)
    pos = np.stack([np.zeros_like(zz), np.zeros_like(zz), zz])  # (3, n)
    load = d[:, None] * (w * wq)[None, :]                        # (3, n): p dz per unit P
    force = load.sum(axis=1)
    m0 = np.cross(pos.T, load.T).sum(axis=0)
    m1 = np.stack([np.cross(phi[j].T, load.T).sum(axis=0) for j in range(len(shapes))])
    gen = np.einsum("jan,an->j", phi, load)
    return DistributedLoadIntegrals(force, Taylor(m0, m1), gen)


def _direction(direction) -> np.ndarray:
    if isinstance(direction, str):
        axes = {"x": [1.0, 0, 0], "y": [0, 1.0, 0], "z": [0, 0, 1.0]}
        direction = direction.lower()
        if direction not in axes:
            raise BeamDataError(f"direction must be 'x', 'y', 'z' or 3 numbers; got {direction!r}.")
        return np.array(axes[direction])
    d = np.asarray(direction, dtype=float).reshape(-1)
    n = float(np.linalg.norm(d)) if d.size == 3 else 0.0
    if d.size != 3 or not np.isfinite(n) or n == 0.0:
        raise BeamDataError(f"direction must be a nonzero, finite 3-vector; got {direction!r}.")
    return d / n
