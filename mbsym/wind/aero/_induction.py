"""Induction solver of the steady BEM (private): polars, Prandtl factor, Ning's residual.

See :mod:`mbsym.wind.aero.bem` for the model.  The solver works on flat arrays of
blade elements (one entry per operating point × azimuth × node) and only
evaluates the residual where an element is still unconverged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from ..deck.airfoils import AirfoilPolar

_EPS = 1e-6  # distance of the brackets from the singular angles 0, pi/2, pi [rad]
_F_MIN = 1e-4  # lower bound of the Prandtl factor (AeroDyn)
_BRACKETS = ((_EPS, math.pi / 2 - _EPS), (-math.pi / 4, -_EPS), (math.pi / 2 + _EPS, math.pi - _EPS))


def _polar_tables(polars: tuple[AirfoilPolar, ...]) -> dict[str, np.ndarray]:
    """All polars resampled on the union of their AoA grids (exact for linear interpolation).

    ``table`` has shape (n_polars, n_grid, 3) holding (cl, cd, cm); ``which`` maps
    each node to its polar.
    """
    unique = {id(p): p for p in polars}
    grid = np.unique(np.concatenate([p.alpha for p in unique.values()]))
    table = np.stack([np.stack([np.interp(grid, p.alpha, getattr(p, key))
                                for key in ("cl", "cd", "cm")], axis=-1)
                      for p in unique.values()])
    index = {key: i for i, key in enumerate(unique)}
    return {"grid": grid, "table": table, "lift_drag": np.ascontiguousarray(table[..., :2]),
            "which": np.array([index[id(p)] for p in polars])}


def _lookup(tables: dict[str, np.ndarray], alpha: np.ndarray, rows: np.ndarray, *,
            key: str = "table") -> np.ndarray:
    """Linear interpolation of (cl, cd, cm) at ``alpha``; ``rows`` = polar of each entry.

    Returns an array of shape ``alpha.shape + (3,)`` (``key="lift_drag"``: (cl, cd)).
    """
    grid = tables["grid"]
    wrapped = np.mod(alpha + math.pi, 2.0 * math.pi) - math.pi
    i = np.clip(np.searchsorted(grid, wrapped, side="right") - 1, 0, grid.size - 2)
    w = ((wrapped - grid[i]) / (grid[i + 1] - grid[i]))[..., None]
    table = tables[key]
    return table[rows, i] * (1.0 - w) + table[rows, i + 1] * w


# ----------------------------------------------------------------------------- elements
@dataclass
class _Elements:
    """Flat arrays of blade-element data (one entry per element) and the options."""

    vx: np.ndarray
    vy: np.ndarray
    theta: np.ndarray
    sigma: np.ndarray  # local solidity B c / (2 pi r)
    tip_const: np.ndarray
    hub_const: np.ndarray
    rows: np.ndarray  # polar index
    tables: dict
    n_blades: int
    tip_loss: bool
    hub_loss: bool
    tangential_induction: bool
    axial_drag: bool
    tangential_drag: bool

    def take(self, index: np.ndarray) -> "_Elements":
        """The elements at ``index`` (a new object; options shared)."""
        values = {f.name: getattr(self, f.name) for f in fields(self)}
        for name in ("vx", "vy", "theta", "sigma", "tip_const", "hub_const", "rows"):
            values[name] = values[name][index]
        return _Elements(**values)


def _prandtl(sin_phi: np.ndarray, e: _Elements) -> np.ndarray:
    s = np.maximum(np.abs(sin_phi), 1e-12)
    f = np.ones_like(s)
    if e.tip_loss:
        f = f * (2.0 / math.pi) * np.arccos(np.minimum(1.0, np.exp(-e.tip_const / s)))
    if e.hub_loss:
        f = f * (2.0 / math.pi) * np.arccos(np.minimum(1.0, np.exp(-e.hub_const / s)))
    return np.maximum(f, _F_MIN)


def _induction(phi: np.ndarray, e: _Elements) -> dict[str, np.ndarray]:
    """Induction factors and Ning's residual at inflow angle ``phi`` (AeroDyn inductionFactors0)."""
    coef = _lookup(e.tables, phi - e.theta, e.rows, key="lift_drag")
    cl, cd = coef[..., 0], coef[..., 1]
    sin_phi, cos_phi = np.sin(phi), np.cos(phi)
    cx = cl * cos_phi + cd * sin_phi if e.axial_drag else cl * cos_phi
    cy = cl * sin_phi - cd * cos_phi if e.tangential_drag else cl * sin_phi
    f = _prandtl(sin_phi, e)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        k = e.sigma * cx / (4.0 * f * sin_phi**2)
        momentum = ((phi > 0) & (e.vx >= 0)) | ((phi < 0) & (e.vx < 0))
        a = k / (1.0 + k)  # momentum region, k <= 2/3
        high = momentum & (k > 2.0 / 3.0)
        if high.any():  # Buhl's empirical correction for high thrust
            two_fk, fh = 2.0 * f[high] * k[high], f[high]
            g1, g2 = two_fk - (10.0 / 9.0 - fh), two_fk - (4.0 / 3.0 - fh) * fh
            g3 = two_fk - (25.0 / 9.0 - 2.0 * fh)
            a[high] = np.where(np.abs(g3) < 1e-6, 1.0 - 0.5 / np.sqrt(np.abs(g2)),
                               (g1 - np.sqrt(np.abs(g2))) / g3)
        a = np.where(momentum, a, k / (k - 1.0))  # propeller brake region
        valid = np.where(momentum, k >= -1.0, k > 1.0)
        if e.tangential_induction:
            kp = e.sigma * cy / (4.0 * f * sin_phi * cos_phi)
            kp = np.where(e.vx < 0, -kp, kp)
            ap = kp / (1.0 - kp)
        else:
            kp = ap = np.zeros_like(phi)
        inv_lambda = e.vx / e.vy
        tangential = cos_phi * inv_lambda * (1.0 - kp)
        residual = np.where(momentum, sin_phi / (1.0 - a) - tangential,
                            sin_phi * (1.0 - k) - tangential)
        residual = np.where(momentum & (a == 1.0), -tangential, residual)
    return {"a": a, "ap": ap, "valid": valid, "residual": residual}


def _regula_falsi(e: _Elements, lo: np.ndarray, hi: np.ndarray, f_lo: np.ndarray, f_hi: np.ndarray,
              *, tol: float = 1e-11, max_iter: int = 100) -> np.ndarray:
    """Regula falsi (Anderson-Bjorck variant), evaluating only the unconverged elements.

    An element is converged when its bracket is narrower than ``tol`` [rad] or its
    residual (a difference of O(1) quantities) is below 1e-12.
    """
    a, b, fa, fb = lo.copy(), hi.copy(), f_lo.copy(), f_hi.copy()
    active = np.flatnonzero((np.abs(b - a) > tol) & (fb != 0))
    for _ in range(max_iter):
        if active.size == 0:
            break
        aa, bb, faa, fbb = a[active], b[active], fa[active], fb[active]
        with np.errstate(divide="ignore", invalid="ignore"):
            c = bb - fbb * (bb - aa) / (fbb - faa)
        bad = ~np.isfinite(c) | (c <= np.minimum(aa, bb)) | (c >= np.maximum(aa, bb))
        c = np.where(bad, 0.5 * (aa + bb), c)
        fc = _induction(c, e.take(active))["residual"]
        flip = fc * fbb < 0
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = 1.0 - fc / fbb  # Anderson-Bjorck scaling of the retained end
        scale = np.where((scale > 0) & np.isfinite(scale), scale, 0.5)
        a[active] = np.where(flip, bb, aa)
        fa[active] = np.where(flip, fbb, scale * faa)
        b[active], fb[active] = c, fc
        done = (np.abs(c - a[active]) <= tol) | (np.abs(fc) <= 1e-12) | ~np.isfinite(fc)
        active = active[~done]
    return b


def _solve_phi(e: _Elements) -> tuple[np.ndarray, np.ndarray]:
    """Inflow angle of every element: the first bracket with a sign change, else none.

    Returns (phi, found); phi is NaN where no bracket holds a root.
    """
    phi = np.full(e.vx.shape, np.nan)
    todo = np.arange(e.vx.size)
    for lo, hi in _BRACKETS:
        if todo.size == 0:
            break
        sub = e.take(todo)
        lo_a, hi_a = np.full(todo.size, lo), np.full(todo.size, hi)
        f_lo, f_hi = _induction(lo_a, sub)["residual"], _induction(hi_a, sub)["residual"]
        here = (f_lo * f_hi <= 0) & np.isfinite(f_lo) & np.isfinite(f_hi)
        if here.any():
            phi[todo[here]] = _regula_falsi(sub.take(here), lo_a[here], hi_a[here], f_lo[here],
                                        f_hi[here])
        todo = todo[~here]
    return phi, np.isfinite(phi)
