"""Smooth CasADi interpolants of rotor performance surfaces (TSR × pitch).

:class:`SurfaceSpline` fits, for each surface (cp, ct, ...), the interpolating
tensor-product spline of degree 3 (C², default) or 5 (C⁴) through the table
nodes (``scipy.interpolate.RectBivariateSpline`` with ``s = 0``, "not-a-knot"
ends), converts it to one polynomial per grid cell in local coordinates
``t, u ∈ [0, 1]`` and evaluates it as **SX expressions**:

* the cell index comes from ``floor`` of the scaled coordinate (uniform grids;
  a non-uniform axis is mapped to its fractional index by a piecewise-linear
  lookup first), so it has zero derivative;
* the cell's polynomial coefficients of all surfaces come from **one** call of a
  CasADi ``linear`` lookup table evaluated exactly at the cell number (a gather:
  no interpolation happens, and no derivative flows through it);
* the polynomial is evaluated by Horner's rule in ``t`` and ``u``.

So the value, gradient and Hessian are exact derivatives of the spline, and the
Hessian costs a few tens of SX instructions on top of the lookup -- unlike a
CasADi ``bspline`` interpolant, whose derivatives are further Function calls
(measured in ``benchmarks/aero.py``).  Outside the table the edge cells continue
linearly (value and slope of the boundary, C¹), which keeps simulations that
leave the table range (start-up, extreme gusts) finite; the table range is where
the surfaces are accurate.  ``method="bspline"`` builds CasADi's ``bspline``
interpolant instead, for comparison.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, field
from typing import Any, Sequence

import casadi as ca
import numpy as np
from scipy.interpolate import RectBivariateSpline

from ...exceptions import ParameterError
from ..deck.performance import PerformanceTable

__all__ = ["SurfaceSpline"]


def _is_uniform(axis: np.ndarray) -> bool:
    steps = np.diff(axis)
    return bool(np.allclose(steps, steps[0], rtol=1e-9, atol=1e-12))


def _cell_coefficients(axis_x: np.ndarray, axis_y: np.ndarray, values: np.ndarray,
                       degree: int) -> np.ndarray:
    """Power-basis coefficients (nx-1, ny-1, (d+1)²) of the interpolating spline per cell.

    Coefficient ``a * (d+1) + b`` multiplies ``t**a * u**b`` (local coordinates).
    """
    spline = RectBivariateSpline(axis_x, axis_y, values, kx=degree, ky=degree, s=0)
    n = degree + 1
    samples = 0.5 * (1.0 - np.cos(np.pi * np.arange(n) / degree))  # Chebyshev-Lobatto points
    vandermonde = np.array([[t**a * u**b for a in range(n) for b in range(n)]
                            for t in samples for u in samples])
    inverse = np.linalg.inv(vandermonde)
    hx, hy = np.diff(axis_x), np.diff(axis_y)
    xs = (axis_x[:-1, None] + samples[None, :] * hx[:, None]).ravel()  # (nx-1)*n
    ys = (axis_y[:-1, None] + samples[None, :] * hy[:, None]).ravel()
    grid = spline.ev(*np.meshgrid(xs, ys, indexing="ij"))  # (nx-1)*n x (ny-1)*n
    blocks = grid.reshape(len(hx), n, len(hy), n).transpose(0, 2, 1, 3)  # cell, cell, t, u
    return blocks.reshape(len(hx), len(hy), n * n) @ inverse.T


def _extend(cells: np.ndarray, n: int) -> np.ndarray:
    """Add ghost cells on both ends of axis 0 holding the linear continuation in ``t``.

    ``cells`` has shape (m, ..., n*n) with coefficient ``a*n + b`` of ``t**a u**b``.
    The left ghost uses ``t = scaled + 1`` (boundary at t = 1), the right one
    ``t = scaled - m`` (boundary at t = 0); value and slope match the edge cells.
    """
    c = cells.reshape(cells.shape[:-1] + (n, n))  # [..., a, b]
    left = np.zeros_like(c[:1])
    left[..., 0, :] = c[:1, ..., 0, :] - c[:1, ..., 1, :]
    left[..., 1, :] = c[:1, ..., 1, :]
    right = np.zeros_like(c[-1:])
    powers = np.arange(n)[:, None]
    right[..., 0, :] = c[-1:].sum(axis=-2)
    right[..., 1, :] = (powers * c[-1:]).sum(axis=-2)
    return np.concatenate([left, c, right]).reshape(
        (cells.shape[0] + 2,) + cells.shape[1:])


def _transpose_ab(cells: np.ndarray, n: int) -> np.ndarray:
    """Swap the roles of t and u in the coefficient layout (and the first two axes)."""
    c = cells.reshape(cells.shape[:-1] + (n, n)).swapaxes(-1, -2)
    return c.reshape(cells.shape).swapaxes(0, 1)


@dataclass(frozen=True, eq=False)
class SurfaceSpline:
    """C² (or C⁴) spline interpolant of performance surfaces, as CasADi SX expressions.

    Build it with :meth:`from_table`; call it with symbols (or numbers) for TSR and
    pitch [rad] to get a dict ``{"cp": ..., "ct": ..., ...}``.

    Attributes
    ----------
    tsr, pitch : ndarray
        The table axes (pitch in rad).
    names : tuple of str
        The surfaces, in output order.
    degree : int
        3 (cubic, C²) or 5 (quintic, C⁴).
    method : str
        ``"sx"`` (cell polynomials, default) or ``"bspline"`` (CasADi interpolant).
    coefficients : ndarray, shape (n_tsr+1, n_pitch+1, len(names), (degree+1)²)
        Cell polynomials in local coordinates (method ``"sx"``): the table's cells
        plus one ghost cell on every side holding the linear continuation.
    source : str or None
        The table's source.
    """

    tsr: np.ndarray
    pitch: np.ndarray
    names: tuple[str, ...]
    degree: int
    method: str
    coefficients: np.ndarray
    values: dict[str, np.ndarray] = field(repr=False)
    source: str | None = None

    @classmethod
    def from_table(cls, table: PerformanceTable, *, names: Sequence[str] = ("cp", "ct"),
                   degree: int = 3, method: str = "sx") -> "SurfaceSpline":
        """Interpolate the surfaces ``names`` of ``table``.

        Parameters
        ----------
        table : PerformanceTable
            The surfaces (nodes are reproduced exactly).
        names : sequence of str, optional
            Which of "cp", "ct", "cq" to interpolate (default cp and ct).
        degree : {3, 5}, optional
            Spline degree: 3 (C², default) or 5 (C⁴).
        method : {"sx", "bspline"}, optional
            ``"sx"``: cell polynomials (cheap exact Hessian, default);
            ``"bspline"``: CasADi's ``bspline`` interpolant (for comparison).

        Raises
        ------
        ParameterError
            Unknown surface name, degree or method, or too few grid points
            (``degree + 1`` per axis are needed).
        """
        if not isinstance(table, PerformanceTable):
            raise TypeError(f"SurfaceSpline.from_table needs a PerformanceTable; got "
                            f"{type(table).__name__}.")
        names = tuple(names)
        bad = [n for n in names if n not in ("cp", "ct", "cq")]
        if bad or not names:
            raise ParameterError(f"names must be some of 'cp', 'ct', 'cq'; got {names!r}.")
        if degree not in (3, 5):
            raise ParameterError(f"degree must be 3 or 5; got {degree!r}.")
        if method not in ("sx", "bspline"):
            raise ParameterError(f"method must be 'sx' or 'bspline'; got {method!r}.")
        if min(table.tsr.size, table.pitch.size) < degree + 1:
            raise ParameterError(f"a degree-{degree} spline needs at least {degree + 1} values "
                                 f"per axis; the table has {table.tsr.size} x {table.pitch.size}.")
        return cls.from_values(table.tsr, table.pitch, {n: getattr(table, n) for n in names}, degree=degree,
                               method=method, source=table.source)

    @classmethod
    def from_values(cls, tsr: Any, pitch: Any, values: dict[str, Any], *, degree: int = 3, method: str = "sx",
                    source: str | None = None) -> "SurfaceSpline":
        """Interpolate any surfaces ``values`` (name -> array (n_tsr, n_pitch)) over the axes ``tsr`` and
        ``pitch`` [rad] (strictly increasing; :meth:`from_table` for a PerformanceTable's).

        Raises
        ------
        ParameterError
            Shapes that do not match the axes, degree or method unknown, too few grid points.
        """
        tsr, pitch = np.asarray(tsr, dtype=float), np.asarray(pitch, dtype=float)
        values = {str(n): np.asarray(v, dtype=float) for n, v in values.items()}
        if not values or any(v.shape != (tsr.size, pitch.size) for v in values.values()):
            raise ParameterError(f"every surface must have shape (n_tsr, n_pitch) = ({tsr.size}, {pitch.size}); got "
                                 f"{ {n: v.shape for n, v in values.items()} }.")
        if degree not in (3, 5):
            raise ParameterError(f"degree must be 3 or 5; got {degree!r}.")
        if method not in ("sx", "bspline"):
            raise ParameterError(f"method must be 'sx' or 'bspline'; got {method!r}.")
        if min(tsr.size, pitch.size) < degree + 1:
            raise ParameterError(f"a degree-{degree} spline needs at least {degree + 1} values "
                                 f"per axis; the table has {tsr.size} x {pitch.size}.")
        names = tuple(values)
        coefficients = np.zeros(0)
        if method == "sx":
            n = degree + 1
            cells = np.stack([_cell_coefficients(tsr, pitch, values[k], degree)
                              for k in names], axis=2)  # (mx, my, surfaces, n*n)
            cells = _transpose_ab(_extend(_transpose_ab(_extend(cells, n), n), n), n)
            coefficients = cells
        return cls(tsr=tsr, pitch=pitch, names=names, degree=degree, method=method,
                   coefficients=coefficients, values=values, source=source)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_lookup", self._make_lookup())

    # ------------------------------------------------------------------ lookup tables
    def _key(self) -> str:
        digest = hashlib.sha1()
        for array in (self.tsr, self.pitch, self.coefficients,
                      *(self.values[n] for n in self.names)):
            digest.update(np.ascontiguousarray(array).tobytes())
        digest.update(f"{self.names}{self.degree}{self.method}".encode())
        return digest.hexdigest()[:12]

    def _make_lookup(self) -> dict[str, Any]:
        key = self._key()
        if self.method == "bspline":
            return {"bspline": ca.interpolant(f"surface_bspline_{key}", "bspline",
                                              [self.tsr, self.pitch],
                                              np.stack([self.values[n] for n in self.names],
                                                       axis=-1).transpose(1, 0, 2).ravel(),
                                              {"degree": [self.degree, self.degree]})}
        nx, ny = self.coefficients.shape[:2]  # cells including the ghosts
        table = ca.interpolant(f"surface_cells_{key}", "linear", [np.arange(nx * ny, dtype=float)],
                               self.coefficients.reshape(nx * ny, -1).ravel(),
                               {"lookup_mode": ["exact"]})  # O(1) index: integer grid
        maps = {}
        for axis_name, axis in (("tsr", self.tsr), ("pitch", self.pitch)):
            if not _is_uniform(axis):
                maps[axis_name] = ca.interpolant(f"surface_{axis_name}_index_{key}", "linear",
                                                 [axis], np.arange(axis.size, dtype=float))
        return {"cells": table, "maps": maps}

    # ------------------------------------------------------------------ evaluation
    def _index(self, value: Any, axis: np.ndarray, name: str) -> tuple[Any, Any]:
        """(cell number counting the left ghost as 0, local coordinate) along one axis."""
        maps = self._lookup["maps"]  # type: ignore[attr-defined]
        if name in maps:
            inside = ca.fmin(ca.fmax(value, axis[0]), axis[-1])
            h_lo, h_hi = axis[1] - axis[0], axis[-1] - axis[-2]
            scaled = maps[name](inside) + ca.fmin(value - axis[0], 0) / h_lo \
                + ca.fmax(value - axis[-1], 0) / h_hi
        else:
            scaled = (value - axis[0]) / (axis[1] - axis[0])
        cell = ca.fmin(ca.fmax(ca.floor(scaled), -1), axis.size - 1)
        return cell + 1, scaled - cell

    def __call__(self, tsr: Any, pitch: Any) -> dict[str, Any]:
        """Surfaces at ``tsr`` [-] and ``pitch`` [rad] (SX/MX symbols or numbers).

        Returns
        -------
        dict of str to casadi.SX (or MX / DM)
            One scalar expression per name.
        """
        tsr, pitch = _as_symbol(tsr), _as_symbol(pitch, like=tsr)
        if self.method == "bspline":
            values = self._lookup["bspline"](ca.vertcat(tsr, pitch))  # type: ignore[attr-defined]
            return {n: values[k] for k, n in enumerate(self.names)}
        i, t = self._index(tsr, self.tsr, "tsr")
        j, u = self._index(pitch, self.pitch, "pitch")
        cells = self._lookup["cells"](i * self.coefficients.shape[1] + j)  # type: ignore
        n = self.degree + 1
        return {name: _horner(cells[k * n * n:(k + 1) * n * n], n, t, u)
                for k, name in enumerate(self.names)}

    def function(self, name: str = "surface") -> ca.Function:
        """A CasADi Function ``(tsr, pitch) -> (one output per surface)``."""
        tsr, pitch = ca.SX.sym("tsr"), ca.SX.sym("pitch")
        out = self(tsr, pitch)
        return ca.Function(name, [tsr, pitch], [out[n] for n in self.names], ["tsr", "pitch"],
                           list(self.names))

    def evaluate(self, tsr: Any, pitch: Any) -> dict[str, np.ndarray]:
        """Numeric values at arrays ``tsr``, ``pitch`` [rad] (broadcast)."""
        t, p = np.broadcast_arrays(np.asarray(tsr, dtype=float), np.asarray(pitch, dtype=float))
        f = self.function().map(t.size)
        out = f(t.ravel()[None, :], p.ravel()[None, :])
        out = out if isinstance(out, (tuple, list)) else (out,)
        return {n: np.asarray(v).reshape(t.shape) for n, v in zip(self.names, out)}


def _horner(c: Any, n: int, t: Any, u: Any) -> Any:
    """P(t, u) = sum_ab c[a n + b] t^a u^b by Horner's rule in u, then t."""
    value = 0
    for a in reversed(range(n)):
        row = 0
        for b in reversed(range(n)):
            row = row * u + c[a * n + b]
        value = value * t + row
    return value


def _as_symbol(value: Any, like: Any = None) -> Any:
    """SX/MX stay as they are; numbers become SX constants (so Horner works)."""
    if isinstance(value, (ca.SX, ca.MX)):
        return value
    if isinstance(like, ca.MX):
        return ca.MX(value)
    return ca.SX(value)
