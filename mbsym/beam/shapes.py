"""Shape functions of a beam along local z: value, slope and curvature on arrays of z.

A shape function ``j`` is the 3-vector field ``Phi_j(z) = (Phi_jx(z), Phi_jy(z), 0)``
[m per unit generalized coordinate] in the body frame, for ``0 <= z <= L``.

Three kinds are provided:

* :class:`PolynomialShape` -- ElastoDyn's ``sum_k c_k (z/L)^k`` for k = 2, 3, ...
* :class:`CallableShape` -- user functions, derivatives given or computed numerically;
* :class:`HermiteShape` -- piecewise cubic Hermite fields, e.g. finite-element modes
  from :mod:`mbsym.beam.fem`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from mbsym.exceptions import BeamDataError

__all__ = ["ShapeFunction", "PolynomialShape", "CallableShape", "HermiteShape", "ELASTODYN_SUM_TOLERANCE"]

#: ElastoDyn rejects mode-shape coefficients whose sum differs from 1 by more than this.
ELASTODYN_SUM_TOLERANCE = 0.0015


def _direction_vector(direction: str | ArrayLike) -> np.ndarray:
    if isinstance(direction, str):
        key = direction.lower()
        if key not in ("x", "y"):
            raise BeamDataError(f"shape direction must be 'x', 'y' or a vector (dx, dy[, 0]); got {direction!r}.")
        return np.array([1.0, 0.0, 0.0]) if key == "x" else np.array([0.0, 1.0, 0.0])
    d = np.asarray(direction, dtype=float).reshape(-1)
    if d.shape[0] == 2:
        d = np.array([d[0], d[1], 0.0])
    if d.shape[0] != 3 or not np.all(np.isfinite(d)) or d[2] != 0.0 or not np.any(d):
        raise BeamDataError(
            f"shape direction vector must be finite, non-zero, transverse (z-component 0); got {d.tolist()}."
        )
    return d


def _as_z(z: ArrayLike) -> np.ndarray:
    zz = np.atleast_1d(np.asarray(z, dtype=float))
    if zz.ndim != 1:
        raise BeamDataError(f"z must be a scalar or a 1-D array; got shape {zz.shape}.")
    return zz


class ShapeFunction(ABC):
    """A transverse displacement field of a beam of length ``length`` along z.

    Subclasses implement :meth:`evaluate`. Attributes: ``length`` [m], ``name``.
    """

    length: float
    name: str

    @abstractmethod
    def evaluate(self, z: ArrayLike, derivative: int = 0) -> np.ndarray:
        """Shape (``derivative=0``), slope (1) or curvature (2) at stations ``z``.

        Parameters
        ----------
        z : array_like, shape (n,)
            Stations along the beam [m], ``0 <= z <= length``.
        derivative : {0, 1, 2}
            Order of the derivative with respect to z.

        Returns
        -------
        numpy.ndarray, shape (3, n)
            Components (x, y, z) [m, -, 1/m per unit coordinate]; z-component 0.
        """

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r}, length={self.length})"


class _DirectionalShape(ShapeFunction):
    """A scalar profile times a fixed transverse direction."""

    def __init__(self, length: float, direction: str | ArrayLike, name: str) -> None:
        length = float(length)
        if not (np.isfinite(length) and length > 0):
            raise BeamDataError(f"shape length must be positive and finite; got {length} m.")
        self.length = length
        self.direction = _direction_vector(direction)
        self.name = name

    @abstractmethod
    def scalar(self, z: np.ndarray, derivative: int) -> np.ndarray:
        """Scalar profile or its derivative at ``z``."""

    def evaluate(self, z: ArrayLike, derivative: int = 0) -> np.ndarray:
        if derivative not in (0, 1, 2):
            raise BeamDataError(f"derivative must be 0, 1 or 2; got {derivative!r}.")
        return self.direction[:, None] * self.scalar(_as_z(z), derivative)[None, :]


class PolynomialShape(_DirectionalShape):
    """ElastoDyn polynomial ``phi(z) = sum_k c_k (z/L)^(k)``, k = 2, 3, ..., 1 + n_c.

    Parameters
    ----------
    coefficients : array_like, shape (n_c,)
        Coefficients of ``(z/L)^2, (z/L)^3, ...`` (ElastoDyn: 5 coefficients, x^2..x^6).
    length : float
        Beam length ``L`` [m].
    direction : {"x", "y"} or array_like
        Direction of the displacement in the body frame.
    normalize : bool, keyword-only
        Divide the coefficients by their sum (paper Eq. 47) so that ``phi(L) = 1``.
        Otherwise the sum must be 1 within ``tolerance`` (ElastoDyn's rule).
    tolerance : float, keyword-only
        Allowed ``|sum - 1|``; default 0.0015.
    name : str, keyword-only

    Raises
    ------
    BeamDataError
        Coefficients not finite, empty, or not summing to 1 (without ``normalize``).

    Examples
    --------
    >>> s = PolynomialShape([0.7004, 2.1963, -5.6202, 6.2275, -2.504], 87.6)
    >>> round(float(s.evaluate([87.6], 1)[0, 0]), 5)
    0.01852
    """

    def __init__(
        self,
        coefficients: ArrayLike,
        length: float,
        direction: str | ArrayLike = "x",
        *,
        normalize: bool = False,
        tolerance: float = ELASTODYN_SUM_TOLERANCE,
        name: str = "polynomial",
    ) -> None:
        super().__init__(length, direction, name)
        c = np.asarray(coefficients, dtype=float).reshape(-1)
        if c.size == 0 or not np.all(np.isfinite(c)):
            raise BeamDataError(f"shape {name!r}: coefficients must be a non-empty list of finite numbers; got {c.tolist()}.")
        total = float(c.sum())
        if normalize:
            if abs(total) < 1e-12:
                raise BeamDataError(f"shape {name!r}: cannot normalize coefficients that sum to {total:g}.")
            c = c / total
        elif abs(total - 1.0) > tolerance:
            raise BeamDataError(
                f"shape {name!r}: coefficients {c.tolist()} sum to {total:.6g}; expected 1 within "
                f"{tolerance:g} (ElastoDyn's rule, so that the tip deflection equals the coordinate). "
                "Fix the coefficients or pass normalize=True to divide them by their sum."
            )
        self.coefficients = c
        self.exponents = np.arange(2, 2 + c.size)

    def scalar(self, z: np.ndarray, derivative: int) -> np.ndarray:
        x = z / self.length
        k = self.exponents
        if derivative == 0:
            fac, p = np.ones_like(k, dtype=float), k
        elif derivative == 1:
            fac, p = k / self.length, k - 1
        else:
            fac, p = k * (k - 1) / self.length**2, k - 2
        return (x[:, None] ** p[None, :]) @ (self.coefficients * fac)


class CallableShape(ShapeFunction):
    """A shape given by Python callables.

    Parameters
    ----------
    function : callable
        ``function(z) -> phi``: with ``direction`` given, a scalar profile of shape (n,);
        with ``direction=None``, the transverse components, shape (2, n) or (3, n)
        (z-component must be 0).
    length : float
        Beam length [m].
    direction : {"x", "y"}, array_like or None
        Displacement direction for a scalar profile; ``None`` for a vector field.
    slope, curvature : callable, optional, keyword-only
        First and second derivatives (same output convention). When missing they are
        computed by 4th-order central differences with step ``step`` (so ``function``
        must accept ``z`` slightly outside [0, L]); the error is ~1e-9 relative for
        smooth functions.
    step : float, optional, keyword-only
        Finite-difference step [m]; default ``1e-3 L``.
    name : str, keyword-only

    Examples
    --------
    >>> s = CallableShape(lambda z: 1 - np.cos(np.pi * z / 20.0), 10.0)
    >>> round(float(s.evaluate([10.0])[0, 0]), 12)
    1.0
    """

    def __init__(
        self,
        function: Callable[[np.ndarray], ArrayLike],
        length: float,
        direction: str | ArrayLike | None = "x",
        *,
        slope: Callable[[np.ndarray], ArrayLike] | None = None,
        curvature: Callable[[np.ndarray], ArrayLike] | None = None,
        step: float | None = None,
        name: str = "callable",
    ) -> None:
        length = float(length)
        if not (np.isfinite(length) and length > 0):
            raise BeamDataError(f"shape length must be positive and finite; got {length} m.")
        for f, label in ((function, "function"), (slope, "slope"), (curvature, "curvature")):
            if f is not None and not callable(f):
                raise BeamDataError(f"shape {name!r}: `{label}` must be callable; got {type(f).__name__}.")
        self.length, self.name = length, name
        self.direction = None if direction is None else _direction_vector(direction)
        self._funcs = (function, slope, curvature)
        self.step = 1e-3 * length if step is None else float(step)
        if not (np.isfinite(self.step) and self.step > 0):
            raise BeamDataError(f"shape {name!r}: step must be positive; got {step}.")

    def _call(self, f: Callable, z: np.ndarray) -> np.ndarray:
        out = np.asarray(f(z), dtype=float)
        if self.direction is not None:
            out = np.broadcast_to(out, z.shape) if out.ndim == 0 else out
            if out.shape != z.shape:
                raise BeamDataError(f"shape {self.name!r}: callable returned shape {out.shape}; expected {z.shape}.")
            return self.direction[:, None] * out[None, :]
        if out.shape == (2, z.size):
            out = np.vstack([out, np.zeros((1, z.size))])
        if out.shape != (3, z.size):
            raise BeamDataError(
                f"shape {self.name!r}: vector callable returned shape {out.shape}; expected (2, {z.size}) or (3, {z.size})."
            )
        if np.any(out[2] != 0.0):
            raise BeamDataError(f"shape {self.name!r}: the z-component must be 0 (transverse shapes only).")
        return out

    def evaluate(self, z: ArrayLike, derivative: int = 0) -> np.ndarray:
        if derivative not in (0, 1, 2):
            raise BeamDataError(f"derivative must be 0, 1 or 2; got {derivative!r}.")
        zz = _as_z(z)
        f = self._funcs[derivative]
        if f is not None:
            return self._call(f, zz)
        g, h = self._funcs[0], self.step
        vals = [self._call(g, zz + k * h) for k in (-2, -1, 1, 2)]
        if derivative == 1:
            return (vals[0] - 8 * vals[1] + 8 * vals[2] - vals[3]) / (12 * h)
        mid = self._call(g, zz)
        return (-vals[0] + 16 * vals[1] - 30 * mid + 16 * vals[2] - vals[3]) / (12 * h * h)


def _hermite_basis(xi: np.ndarray, h: np.ndarray, derivative: int) -> np.ndarray:
    """Cubic Hermite basis (v0, s0, v1, s1) on an element of length h, xi in [0, 1]."""
    if derivative == 0:
        return np.stack([1 - 3 * xi**2 + 2 * xi**3, h * (xi - 2 * xi**2 + xi**3),
                         3 * xi**2 - 2 * xi**3, h * (-xi**2 + xi**3)])
    if derivative == 1:
        return np.stack([(-6 * xi + 6 * xi**2) / h, 1 - 4 * xi + 3 * xi**2,
                         (6 * xi - 6 * xi**2) / h, -2 * xi + 3 * xi**2])
    return np.stack([(-6 + 12 * xi) / h**2, (-4 + 6 * xi) / h,
                     (6 - 12 * xi) / h**2, (-2 + 6 * xi) / h])


class HermiteShape(_DirectionalShape):
    """Piecewise cubic Hermite field from nodal values and slopes (FEM mode shapes).

    The curvature is piecewise linear; at an interior node it is the mean of the
    two adjacent elements' values.

    Parameters
    ----------
    nodes : array_like, shape (n,)
        Strictly increasing node positions [m], ``nodes[0] = 0``; ``length = nodes[-1]``.
    values, slopes : array_like, shape (n,)
        Displacement [m] and slope [-] at the nodes (per unit coordinate).
    direction : {"x", "y"} or array_like
    name : str, keyword-only

    Examples
    --------
    >>> s = HermiteShape([0.0, 1.0], [0.0, 1.0], [0.0, 2.0])   # exactly z^2
    >>> float(s.evaluate([0.5])[0, 0])
    0.25
    """

    def __init__(
        self,
        nodes: ArrayLike,
        values: ArrayLike,
        slopes: ArrayLike,
        direction: str | ArrayLike = "x",
        *,
        name: str = "hermite",
    ) -> None:
        x = np.asarray(nodes, dtype=float).reshape(-1)
        v = np.asarray(values, dtype=float).reshape(-1)
        s = np.asarray(slopes, dtype=float).reshape(-1)
        if x.size < 2 or v.shape != x.shape or s.shape != x.shape:
            raise BeamDataError(
                f"HermiteShape needs >= 2 nodes and as many values and slopes; got {x.size}, {v.size}, {s.size}."
            )
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(v)) and np.all(np.isfinite(s))):
            raise BeamDataError("HermiteShape nodes, values and slopes must be finite.")
        if np.any(np.diff(x) <= 0) or x[0] != 0.0:
            raise BeamDataError("HermiteShape nodes must start at 0 and increase strictly.")
        super().__init__(x[-1], direction, name)
        self.nodes, self.values, self.slopes = x, v, s

    def scalar(self, z: np.ndarray, derivative: int) -> np.ndarray:
        x = self.nodes
        e = np.clip(np.searchsorted(x, z, side="right") - 1, 0, x.size - 2)
        h = x[e + 1] - x[e]
        dofs = np.stack([self.values[e], self.slopes[e], self.values[e + 1], self.slopes[e + 1]])
        out = np.sum(_hermite_basis((z - x[e]) / h, h, derivative) * dofs, axis=0)
        if derivative == 2:
            at_node = np.isin(z, x[1:-1])  # mean of left and right limits there
            if np.any(at_node):
                el = e[at_node] - 1  # element on the left of that node
                hl = x[el + 1] - x[el]
                dl = np.stack([self.values[el], self.slopes[el], self.values[el + 1], self.slopes[el + 1]])
                left = np.sum(_hermite_basis(np.ones(el.size), hl, 2) * dl, axis=0)
                out[at_node] = 0.5 * (out[at_node] + left)
        return out
