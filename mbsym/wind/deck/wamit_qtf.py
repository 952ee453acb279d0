"""Read WAMIT second-order force files (quadratic transfer functions: ``.10d`` … ``.12d``, ``.10s`` … ``.12s``; the
mean-drift files ``.7`` … ``.9``).

A row is ``PER1 PER2 BETA1 BETA2 I MOD PHS RE IM``: two wave periods [s] and headings [deg], the force or moment
component ``I`` (1-6 for one body) and the nondimensional QTF as modulus and phase and as ``RE + i IM``; HydroDyn
(v5.0.0, ``WAMIT2.f90``, ``Read_DataFile4D``) keeps ``RE + i IM``, turns the periods into frequencies
``ω = 2π / PER`` (a negative period is ω = 0; a zero period, ω = ∞, is dropped here as HydroDyn zeroes the top of
its grid) and redimensionalizes with ``ρ g L`` (forces) and ``ρ g L²`` (moments) (:meth:`QtfData.redimensionalize`,
the wave amplitudes still to multiply). A file may give one triangle of the frequency pairs: HydroDyn fills the
other with the complex conjugate (difference-frequency files) or the same value (sum-frequency files), and with
equal frequencies the swapped heading pair with the same value. Every (ω1, ω2, β1, β2, I) the grid spans must then
be given, else HydroDyn's interpolation stops ("too sparse"), and so does this reader.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError
from .wamit import _rows

__all__ = ["QtfData", "read_wamit_qtf"]


@dataclass(frozen=True, eq=False)
class QtfData:
    """A WAMIT second-order force file (module docstring).

    Attributes
    ----------
    frequencies : (n,) ndarray
        The frequency grid ω [rad/s] of both wave components, ascending.
    headings : (m,) ndarray
        The heading grid β [deg] of both wave components, ascending.
    values : (n, n, m, m, 6) complex ndarray
        ``Q[ω1, ω2, β1, β2, I]``: nondimensional until :meth:`redimensionalize`, then [N/m², N m/m²].
    kind : str
        ``"difference"`` or ``"sum"``.
    source : str
        The file read.
    diagonal : bool
        A 3-D file (``.7`` … ``.9``: equal frequencies only, rows ``PER BETA1 BETA2 I MOD PHS RE IM``): only
        ``values[i, i]`` hold data (the mean drift and Newman's approximation use nothing else).
    components : tuple of 6 bool
        Which force and moment components the file gives (a 3-D file may leave some out, WAMIT's ``.8`` all but
        surge, sway and yaw; a 4-D file must give all six).
    """

    frequencies: np.ndarray
    headings: np.ndarray
    values: np.ndarray
    kind: str
    source: str
    diagonal: bool = False
    components: tuple[bool, ...] = (True,) * 6

    def redimensionalize(self, water_density: float, gravity: float, length: float) -> "QtfData":
        """``ρ g L`` on the forces, ``ρ g L²`` on the moments (HydroDyn's ``RhoXg WAMITULEN^K``)."""
        scale = water_density * gravity * np.array([length] * 3 + [length ** 2] * 3)
        return replace(self, values=self.values * scale)


def read_wamit_qtf(path) -> QtfData:
    """Read a WAMIT second-order file (module docstring); ``.NNd`` is a difference-, ``.NNs`` a sum-frequency QTF,
    ``.7`` … ``.9`` a mean-drift file (:attr:`QtfData.diagonal`).

    Raises
    ------
    OpenFASTFormatError
        A missing file, a row that is not 9 numbers (8 in a mean-drift file), a component outside 1-6 (one body), two rows for the
        same entry that disagree, or an entry of the grid that no row gives (naming the first).
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"WAMIT second-order file not found: tried '{p.absolute()}'. Check PotFile in the "
                                  "HydroDyn file (the root name) and the MnDrift / NewmanApp / DiffQTF / SumQTF number (the extension).")
    kind = "sum" if p.suffix.lower().endswith("s") else "difference"
    diagonal = p.suffix.lstrip(".") in ("7", "8", "9")
    if diagonal:                       # 3-D: PER BETA1 BETA2 I MOD PHS RE IM, the period twice for the 4-D layout
        raw = np.array(_rows(p, (8,), "mean-drift (PER BETA1 BETA2 I MOD PHS RE IM)")[0])
        rows = np.column_stack([raw[:, :1], raw])
    else:
        rows = np.array(_rows(p, (9,), "second-order (PER1 PER2 BETA1 BETA2 I MOD PHS RE IM)")[0])
    rows = rows[(rows[:, 0] != 0) & (rows[:, 1] != 0)]             # ω = ∞: HydroDyn's grid is zero there
    omega = np.where(rows[:, :2] < 0, 0.0, 2.0 * math.pi / np.abs(rows[:, :2]))
    freqs = np.unique(np.round(omega, 12))
    heads = np.unique(np.round(rows[:, 2:4], 9))
    n, m = len(freqs), len(heads)
    values = np.zeros((n, n, m, m, 6), dtype=complex)
    seen = np.zeros(values.shape, dtype=bool)
    fi = np.searchsorted(freqs, np.round(omega, 12))
    hi = np.searchsorted(heads, np.round(rows[:, 2:4], 9))
    for r, row in enumerate(rows):
        k = int(row[4]) - 1
        if not (row[4] == k + 1 and 0 <= k < 6):
            raise OpenFASTFormatError(f"{p}: component {row[4]:g} in row {r + 1} is outside 1-6 (one body). "
                                      "mbsym reads one WAMIT body; regenerate the file for it.")
        key = (fi[r, 0], fi[r, 1], hi[r, 0], hi[r, 1], k)
        value = complex(row[7], row[8])
        if seen[key] and not np.isclose(values[key], value, rtol=1e-5, atol=1e-12):
            raise OpenFASTFormatError(f"{p}: row {r + 1} gives another value for an entry given before "
                                      f"(periods {row[0]:g}, {row[1]:g} s, headings {row[2]:g}, {row[3]:g} deg, "
                                      f"component {k + 1}). Keep one.")
        values[key], seen[key] = value, True
    if diagonal:
        seen[~np.eye(n, dtype=bool)] = True                   # off the diagonal: no data (zero), none needed
        absent = ~seen.any(axis=(0, 1, 2, 3))                 # a .8 file holds surge, sway and yaw only
        seen[..., absent] = True
    else:
        _fill(values, seen, kind)
    if not seen.all():
        i = np.argwhere(~seen)[0]
        raise OpenFASTFormatError(
            f"{p}: no value for ω1 = {freqs[i[0]]:.6g}, ω2 = {freqs[i[1]]:.6g} rad/s, headings {heads[i[2]]:g}, "
            f"{heads[i[3]]:g} deg, component {i[4] + 1}, nor for its mirror: HydroDyn's interpolation needs every "
            "entry of the grid (the file is too sparse). Regenerate it with WAMIT over the full grid.")
    components = tuple(bool(np.any(values[..., m] != 0) or not diagonal) for m in range(6))
    return QtfData(freqs, heads, values, kind, str(p), diagonal, components)


def _fill(values: np.ndarray, seen: np.ndarray, kind: str) -> None:
    """HydroDyn's mirror fills: (ω2, ω1) from (ω1, ω2) (conjugate for a difference QTF), then at ω1 = ω2 the
    swapped headings."""
    mirror = np.swapaxes(values, 0, 1)
    mirror = mirror.conj() if kind == "difference" else mirror
    known = np.swapaxes(seen, 0, 1)
    take = known & ~seen
    values[take], seen[take] = mirror[take], True
    n = values.shape[0]
    for i in range(n):
        swapped, known = np.swapaxes(values[i, i], 0, 1), np.swapaxes(seen[i, i], 0, 1)
        take = known & ~seen[i, i]
        values[i, i][take], seen[i, i][take] = swapped[take], True
