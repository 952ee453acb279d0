"""Airfoil polars of the blade nodes as CasADi SX expressions: smooth splines or AeroDyn's linear.

AeroDyn interpolates the steady polars linearly in the angle of attack α (``InterpOrd = 1``, the
NREL 5 MW files). Linear interpolation has kinks at every table point, which a Newton solve,
a linearization or an optimizer dislikes, so the default here is smooth:

* ``"spline"`` (default): for each airfoil, the table is interpolated linearly (AeroDyn) at a
  **uniform grid** of step ``step`` (0.25° by default) over [-180°, 180°], and a C² cubic
  interpolating spline (not-a-knot ends) is fitted through those values. Because the grid is
  uniform, the cell of α is ``floor((α + π) / step)`` -- no search -- and one O(1) table
  gather (an MX Function reading one column of a constant matrix, kept as one call node in the
  SX graph) returns the cell's cubic; Horner's rule evaluates it.
  The spline rounds the corners of AeroDyn's piecewise-linear polar over about one grid step;
  the measured differences (docs/blade_aero.md) are below 1e-3 in cl and cd in the attached-flow
  range, and 0.04 % on the rotor's Cp.
* ``"linear"``: AeroDyn's own linear interpolation through the table points (CasADi ``linear``
  interpolant, binary search), C⁰; for validation against AeroDyn and :func:`solve_bem`.

α is wrapped into [-π, π) first (the polars are periodic; the wrap has zero derivative).
Each node has its airfoil; all airfoils share one lookup table (airfoil ``i`` occupies cells
``i * n_cells ... (i + 1) * n_cells - 1``).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import casadi as ca
import numpy as np

from ....exceptions import ParameterError
from ...deck.airfoils import AirfoilPolar

__all__ = ["NodePolars", "POLAR_METHODS"]

#: The polar representations offered.
POLAR_METHODS = ("spline", "linear")
_COLUMNS = ("cl", "cd", "cm")


def _gather(name: str, rows: np.ndarray) -> ca.Function:
    """``i -> rows[i]`` for an integer-valued ``i``: an MX Function of one indexed read.

    Called from SX with ``never_inline`` it stays one call node, whose generated C is an array
    access (about 25 ns; a CasADi ``linear`` interpolant in ``exact`` mode costs about 85 ns).
    Its derivative with respect to ``i`` is zero (``i`` is a floor anyway).
    """
    i = ca.MX.sym("i")
    flat = ca.MX(ca.DM(np.ascontiguousarray(rows).ravel()))
    m = rows.shape[1]
    # one indexed read per coefficient: unlike a column slice with a symbolic index, this form
    # has a zero (not NaN) derivative with respect to the index in CasADi 3.6-3.8
    return ca.Function(name, [i], [ca.vertcat(*[flat[m * i + k] for k in range(m)])], ["cell"], ["coefficients"])


def _wrap(alpha: Any) -> Any:
    """α wrapped into [-π, π) (floor: zero derivative)."""
    return alpha - 2.0 * math.pi * ca.floor((alpha + math.pi) / (2.0 * math.pi))


def _cell_cubics(polar: AirfoilPolar, step: float) -> np.ndarray:
    """(n_cells, 3, 4) power-basis coefficients in the local coordinate t ∈ [0, 1] of each cell.

    The C² not-a-knot cubic spline through AeroDyn's linear interpolation of ``polar`` at the
    uniform grid ``-π + i step``.
    """
    from scipy.interpolate import CubicSpline

    n_cells = int(round(2.0 * math.pi / step))
    grid = -math.pi + step * np.arange(n_cells + 1)
    out = np.empty((n_cells, 3, 4))
    for k, name in enumerate(_COLUMNS):
        values = np.interp(grid, polar.alpha, getattr(polar, name))
        spline = CubicSpline(grid, values, bc_type="not-a-knot")
        c = spline.c  # (4, n_cells): c[0] (x - x_i)^3 + ... + c[3]
        for p in range(4):  # coefficient of t^p = c[3 - p] step^p
            out[:, k, p] = c[3 - p] * step**p
    return out


@dataclass(frozen=True, eq=False)
class NodePolars:
    """The polars of the blade nodes as SX expressions (one airfoil per node).

    Attributes
    ----------
    polars : tuple of AirfoilPolar
        One per node (length ``n_nodes``).
    method : {"spline", "linear"}
        See the module docstring.
    step : float
        Grid step of the spline [rad] (default 0.25°).
    """

    polars: tuple[AirfoilPolar, ...]
    method: str = "spline"
    step: float = math.radians(0.25)
    airfoil_index: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if self.method not in POLAR_METHODS:
            raise ParameterError(f"polar method must be one of {POLAR_METHODS}; got {self.method!r}.")
        if not (isinstance(self.step, float) and 0 < self.step <= math.radians(2.0)):
            raise ParameterError(f"the spline step must be in (0, 2] deg [rad]; got {self.step!r}.")
        unique = list({id(p): p for p in self.polars}.values())
        index = {id(p): i for i, p in enumerate(unique)}
        object.__setattr__(self, "airfoil_index", np.array([index[id(p)] for p in self.polars]))
        object.__setattr__(self, "_unique", tuple(unique))
        object.__setattr__(self, "_tables", self._build())

    # ------------------------------------------------------------------ tables
    def _key(self) -> str:
        digest = hashlib.sha1(f"{self.method}{self.step!r}".encode())
        for p in self._unique:  # type: ignore[attr-defined]
            for a in (p.alpha, p.cl, p.cd, p.cm):
                digest.update(np.ascontiguousarray(a).tobytes())
        return digest.hexdigest()[:12]

    def _build(self) -> dict[str, Any]:
        key = self._key()
        unique: tuple[AirfoilPolar, ...] = self._unique  # type: ignore[attr-defined]
        if self.method == "linear":
            out = {}
            for i, p in enumerate(unique):
                out[i] = ca.interpolant(f"polar_linear_{key}_{i}", "linear", [p.alpha],
                                        np.stack([p.cl, p.cd, p.cm], axis=-1).ravel())
            return out
        cells = np.concatenate([_cell_cubics(p, self.step) for p in unique])  # (n_af*n, 3, 4)
        return {
            "n_cells": int(round(2.0 * math.pi / self.step)),
            "lift": _gather(f"polar_cl_{key}", cells[:, 0, :]),
            "all": _gather(f"polar_all_{key}", cells.reshape(cells.shape[0], 12)),
            "cells": cells,
        }

    # ------------------------------------------------------------------ evaluation
    def __call__(self, alpha: Any, nodes: Sequence[int], *, lift_only: bool = False,
                 wrap: bool = True, slope: bool = False) -> dict[str, Any]:
        """Coefficients at angles of attack ``alpha`` [rad] (SX column, one entry per ``nodes``).

        Parameters
        ----------
        alpha : casadi.SX, shape (m, 1)
            Angle of attack of each entry.
        nodes : sequence of int
            The blade node (0-based, within a blade) of each entry: selects its airfoil.
        lift_only : bool, optional
            Return only ``cl`` (cheaper: what the induction needs without AIDrag/TIDrag).
        wrap : bool, optional
            Wrap α into [-π, π) first; False when the caller knows it is there.
        slope : bool, optional
            Also return ``dcl``, ``dcd`` (d/dα of the same cubics), for a Newton step that
            must not differentiate through the gather (its forward derivative clears a
            table-sized vector in CasADi's generated code).

        Returns
        -------
        dict of str to SX column
            ``cl`` (and ``cd``, ``cm`` unless ``lift_only``).
        """
        which = self.airfoil_index[np.asarray(nodes, dtype=int)]
        names = _COLUMNS[:1] if lift_only else _COLUMNS
        if self.method == "linear":
            symbol = ca.SX.sym("alpha", alpha.shape[0])
            wrapped = _wrap(symbol) if wrap else symbol
            rows = ca.horzcat(*[self._tables[int(w)](wrapped[i]) for i, w in enumerate(which)]).T  # (m, 3)
            values = {name: rows[:, k] for k, name in enumerate(names)}
            if slope:  # the interpolant's own derivative (its forward mode is cheap)
                values.update({"d" + name: ca.jtimes(values[name], symbol, ca.DM.ones(alpha.shape[0]))
                               for name in names})
            keys = list(values)
            return dict(zip(keys, ca.substitute([values[k] for k in keys], [symbol], [alpha])))
        wrapped = _wrap(alpha) if wrap else alpha
        n_cells = self._tables["n_cells"]
        scaled = (wrapped + math.pi) / self.step
        cell = ca.fmin(ca.fmax(ca.floor(scaled), 0), n_cells - 1)
        t = scaled - cell
        index = cell + which.reshape(-1, 1) * n_cells
        table = self._tables["lift" if lift_only else "all"]
        out: dict[str, list] = {}
        for i in range(index.shape[0]):
            coef = table.call([index[i]], False, True)[0]  # a call node: one gather in the C code
            for k, name in enumerate(names):
                c = coef[4 * k:4 * k + 4]
                out.setdefault(name, []).append(((c[3] * t[i] + c[2]) * t[i] + c[1]) * t[i] + c[0])
                if slope:
                    out.setdefault("d" + name, []).append(((3.0 * c[3] * t[i] + 2.0 * c[2]) * t[i] + c[1])
                                                          / self.step)
        return {name: ca.vertcat(*values) for name, values in out.items()}

    def by_airfoil(self, alpha: Any, airfoil: Any) -> dict[str, Any]:
        """cl, cd, cm at ``alpha`` [rad] of the airfoil numbered ``airfoil`` (an SX value: :attr:`airfoil_index`
        of a node), the ``"spline"`` tables only: one SX expression for any node, for a Function mapped over nodes.

        Raises
        ------
        ParameterError
            With ``method="linear"`` (one interpolant per airfoil: the airfoil must be known when building).
        """
        if self.method != "spline":
            raise ParameterError("NodePolars.by_airfoil needs the 'spline' tables (one table for every airfoil); "
                                 "this one is 'linear'.")
        n_cells = self._tables["n_cells"]
        scaled = (_wrap(alpha) + math.pi) / self.step
        cell = ca.fmin(ca.fmax(ca.floor(scaled), 0), n_cells - 1)
        t = scaled - cell
        coef = self._tables["all"].call([cell + airfoil * n_cells], False, True)[0]
        return {name: ((coef[4 * k + 3] * t + coef[4 * k + 2]) * t + coef[4 * k + 1]) * t + coef[4 * k]
                for k, name in enumerate(_COLUMNS)}

    def numeric(self, alpha: np.ndarray, node: int) -> dict[str, np.ndarray]:
        """cl, cd, cm of node ``node``'s airfoil at ``alpha`` [rad] (numpy, for checks and docs)."""
        alpha = np.asarray(alpha, dtype=float).ravel()
        a = ca.SX.sym("a", alpha.size)
        out = self(a, [node] * alpha.size)
        f = ca.Function("polar", [a], [out["cl"], out["cd"], out["cm"]])
        values = f(alpha)
        return {n: np.asarray(v).ravel() for n, v in zip(_COLUMNS, values)}
