"""Read WAMIT output (``.hst``, ``.1``, ``.3``) and redimensionalize it as HydroDyn does.

WAMIT writes nondimensional coefficients; HydroDyn (``WAMIT.f90``, ``WAMIT_Init``) scales
them with the water density ρ, gravity g and the length ``WAMITULEN`` = L, element by
element, by the kind of each row/column (translation 1-3, rotation 4-6):

============================  =====================  ======================
file                          translation-translation  each rotation index adds
============================  =====================  ======================
``.hst`` restoring C           ρ g L²                  × L
``.1`` added mass A            ρ L³                    × L
``.1`` damping B               ρ L³ ω                  × L
``.3`` excitation X (per m)    ρ g L² (forces)         × L (moments)
============================  =====================  ======================

Periods in ``.1``: a negative period (WAMIT writes −1) is the zero-frequency limit, a zero
period the infinite-frequency limit; those rows carry the added mass only (HydroDyn's
reading, ``WAMIT.f90``).  ``.3`` rows are ``period, heading [deg], i, |X|, phase [deg],
Re X, Im X``; the complex amplitude ``Re + i Im`` is kept.

Rows HydroDyn would stop at (a line that does not parse) are errors here, with file and
line.  No ρ, g, L are assumed: :meth:`WamitData.redimensionalize` takes them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError

__all__ = ["WamitData", "WamitHydrodynamics", "read_wamit", "read_wamit_hst", "read_wamit_1", "read_wamit_3",
           "scale_matrix", "RadiationFit", "read_wamit_ss", "ExcitationFit", "read_wamit_ssexctn"]


def scale_matrix(n: int, base: float, length: float, power: int) -> np.ndarray:
    """``base · L^(power + [i is a rotation] + [j is a rotation])`` for an ``n × n`` WAMIT matrix (6 DOF per body)."""
    rot = np.array([(k % 6) >= 3 for k in range(n)], dtype=int)
    return base * length ** (power + rot[:, None] + rot[None, :])


def _rows(path: Path, widths: tuple[int, ...], what: str) -> tuple[list[list[float]], list[int]]:
    """Numeric rows of a WAMIT file; each must have one of ``widths`` numbers."""
    if not path.is_file():
        raise OpenFASTFormatError(f"WAMIT {what} file not found: tried '{path.absolute()}'. Check PotFile in the "
                                  "HydroDyn file (the root name, without extension).")
    rows, lines = [], []
    for number, text in enumerate(path.read_text(encoding="latin-1").splitlines(), start=1):
        tokens = text.split()
        if not tokens:
            continue
        try:
            row = [float(t.replace("D", "E").replace("d", "e")) for t in tokens]
        except ValueError:
            row = None
        if row is None or len(row) not in widths or not all(map(math.isfinite, row)):
            raise OpenFASTFormatError(
                f"{path}, line {number}: expected {' or '.join(map(str, widths))} numbers in a WAMIT {what} row, got "
                f"{text.strip()[:70]!r}. Regenerate the file with WAMIT or fix that line.")
        rows.append(row)
        lines.append(number)
    if not rows:
        raise OpenFASTFormatError(f"{path}: the WAMIT {what} file has no data rows. Regenerate it with WAMIT.")
    return rows, lines


def _index(path: Path, line: int, i: float, j: float | None = None) -> tuple[int, ...]:
    ok = all(float(k).is_integer() and k >= 1 for k in ([i] if j is None else [i, j]))
    if not ok:
        raise OpenFASTFormatError(f"{path}, line {line}: mode indices must be integers >= 1; got "
                                  f"{i}{'' if j is None else f', {j}'}. Fix that line.")
    return (int(i) - 1,) if j is None else (int(i) - 1, int(j) - 1)


def read_wamit_hst(path) -> np.ndarray:
    """The nondimensional hydrostatic restoring matrix of a ``.hst`` file (``i j C`` rows), ``n × n``."""
    p = Path(path)
    rows, lines = _rows(p, (3,), "hydrostatic (.hst)")
    n = max(max(int(r[0]), int(r[1])) for r in rows)
    out = np.zeros((n, n))
    for row, line in zip(rows, lines):
        i, j = _index(p, line, row[0], row[1])
        out[i, j] = row[2]
    return out


def read_wamit_1(path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Periods [s] in file order (−1: zero frequency, 0: infinite), nondimensional added mass
    and damping (``n_periods × n × n``; damping 0 on the limit rows) of a ``.1`` file."""
    p = Path(path)
    rows, lines = _rows(p, (4, 5), "added-mass and damping (.1)")
    periods: list[float] = []
    for row in rows:
        if not periods or row[0] != periods[-1]:
            periods.append(row[0])
    if len(set(periods)) != len(periods):
        raise OpenFASTFormatError(f"{p}: the periods are not in contiguous blocks (a period appears twice). "
                                  "Regenerate the file with WAMIT.")
    n = max(max(int(r[1]), int(r[2])) for r in rows)
    where = {t: k for k, t in enumerate(periods)}
    added, damping = np.zeros((len(periods), n, n)), np.zeros((len(periods), n, n))
    for row, line in zip(rows, lines):
        i, j = _index(p, line, row[1], row[2])
        if row[0] > 0 and len(row) != 5:
            raise OpenFASTFormatError(f"{p}, line {line}: a finite period ({row[0]} s) needs 5 numbers "
                                      "(period, i, j, added mass, damping). Fix that line.")
        added[where[row[0]], i, j] = row[3]
        if len(row) == 5:
            damping[where[row[0]], i, j] = row[4]
    return np.array(periods), added, damping


def read_wamit_3(path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Periods [s], headings [rad] (both in file order) and the nondimensional complex
    excitation ``n_periods × n_headings × n`` (``Re + i Im`` per unit wave amplitude) of a ``.3`` file."""
    p = Path(path)
    rows, lines = _rows(p, (7,), "excitation (.3)")
    periods = list(dict.fromkeys(r[0] for r in rows))
    headings = list(dict.fromkeys(r[1] for r in rows))
    n = max(int(r[2]) for r in rows)
    wp, wh = {t: k for k, t in enumerate(periods)}, {h: k for k, h in enumerate(headings)}
    out = np.zeros((len(periods), len(headings), n), dtype=complex)
    seen = np.zeros(out.shape, dtype=bool)
    for row, line in zip(rows, lines):
        (i,) = _index(p, line, row[2])
        out[wp[row[0]], wh[row[1]], i] = complex(row[5], row[6])
        seen[wp[row[0]], wh[row[1]], i] = True
    if not seen.all():
        k = np.argwhere(~seen)[0]
        raise OpenFASTFormatError(f"{p}: no row for period {periods[k[0]]} s, heading {headings[k[1]]} deg, mode "
                                  f"{k[2] + 1}; every period needs every heading and mode. Regenerate the file.")
    return np.array(periods), np.radians(headings), out


@dataclass(frozen=True, eq=False)
class WamitHydrodynamics:
    """Dimensional WAMIT data (SI), frequencies sorted ascending as in HydroDyn.

    Attributes
    ----------
    restoring : (n, n) ndarray
        Hydrostatic restoring C [N/m, N/rad, N m/m, N m/rad].
    frequencies : (k,) ndarray
        Finite, positive frequencies ω [rad/s] of the ``.1`` file, ascending.
    added_mass, damping : (k, n, n) ndarray
        A(ω) [kg, kg m, kg m²] and B(ω) [N s/m, …] at ``frequencies``.
    added_mass_zero, added_mass_infinite : (n, n) ndarray or None
        A(0) and A(∞) (the ``.1`` file's period −1 and 0 rows), None when absent.
    excitation_frequencies, headings : ndarray
        ω [rad/s] ascending and wave headings [rad] of the ``.3`` file.
    excitation : (k3, n_headings, n) complex ndarray or None
        First-order wave excitation per unit wave amplitude [N/m, N m/m].
    """

    restoring: np.ndarray
    frequencies: np.ndarray
    added_mass: np.ndarray
    damping: np.ndarray
    added_mass_zero: np.ndarray | None
    added_mass_infinite: np.ndarray | None
    excitation_frequencies: np.ndarray | None
    headings: np.ndarray | None
    excitation: np.ndarray | None


@dataclass(frozen=True, eq=False)
class WamitData:
    """Nondimensional WAMIT output of one ``PotFile`` root (see :func:`read_wamit`)."""

    root: str
    hst: np.ndarray
    periods: np.ndarray
    added_mass: np.ndarray
    damping: np.ndarray
    excitation_periods: np.ndarray | None
    headings: np.ndarray | None
    excitation: np.ndarray | None

    def redimensionalize(self, water_density: float, gravity: float, length: float = 1.0) -> WamitHydrodynamics:
        """Scale by ρ [kg/m³], g [m/s²] and ``WAMITULEN`` L [m] as HydroDyn does (module docstring).

        Examples
        --------
        >>> data = read_wamit("HydroData/IEA-15-240-RWT-UMaineSemi")  # doctest: +SKIP
        >>> data.redimensionalize(1025.0, 9.80665).restoring[2, 2]  # doctest: +SKIP
        4453240.9...
        """
        for name, value in (("water_density", water_density), ("gravity", gravity), ("length", length)):
            if not (math.isfinite(value) and value > 0):
                raise OpenFASTFormatError(f"{name} must be a finite number > 0 to redimensionalize WAMIT data; got {value}.")
        rho_g = water_density * gravity
        n = self.hst.shape[0]
        restoring = self.hst * scale_matrix(n, rho_g, length, 2)
        m = self.added_mass.shape[1]
        mass_scale = scale_matrix(m, water_density, length, 3)
        finite = self.periods > 0
        omega = 2 * np.pi / self.periods[finite]
        order = np.argsort(omega)
        omega = omega[order]
        added = self.added_mass[finite][order] * mass_scale
        damping = self.damping[finite][order] * mass_scale * omega[:, None, None]
        zero = self.added_mass[self.periods < 0][0] * mass_scale if np.any(self.periods < 0) else None
        infinite = self.added_mass[self.periods == 0][0] * mass_scale if np.any(self.periods == 0) else None
        ex_omega = heads = excitation = None
        if self.excitation is not None:
            ex_omega = 2 * np.pi / self.excitation_periods
            ex_order = np.argsort(ex_omega)
            ex_omega = ex_omega[ex_order]
            rot = np.array([(k % 6) >= 3 for k in range(self.excitation.shape[2])], dtype=int)
            excitation = self.excitation[ex_order] * (rho_g * length ** (2 + rot))
            heads = self.headings
        return WamitHydrodynamics(restoring, omega, added, damping, zero, infinite, ex_omega, heads, excitation)


def read_wamit(root, *, excitation: bool = True) -> WamitData:
    """Read ``root.hst``, ``root.1`` and (with ``excitation``) ``root.3``.

    Parameters
    ----------
    root : str or Path
        The ``PotFile`` root name (e.g. :attr:`HydroDynInput.potential_files[0]`).
    excitation : bool, optional, keyword-only
        Also read the ``.3`` file (default True; it is the largest).

    Raises
    ------
    OpenFASTFormatError
        A missing file, a malformed row (file and line), inconsistent sizes.
    """
    base = str(root)
    hst = read_wamit_hst(base + ".hst")
    periods, added, damping = read_wamit_1(base + ".1")
    ex = (None, None, None) if not excitation else read_wamit_3(base + ".3")
    if added.shape[1] != hst.shape[0]:
        raise OpenFASTFormatError(f"{base}: the .hst file has {hst.shape[0]} modes but the .1 file "
                                  f"{added.shape[1]}. Use files of one WAMIT run.")
    return WamitData(base, hst, periods, added, damping, *ex)


@dataclass(frozen=True, eq=False)
class RadiationFit:
    """A state-space fit of the radiation memory (SS_Fitting's ``.ss``): ẋ = A x + B q̇, F = C x [SI].

    ``enabled`` and ``states_per_dof`` are the file's lines 2 and 4. The matrices are
    dimensional as written (SS_Fitting redimensionalizes with its own ρ; HydroDyn uses them as
    they are, ``SS_Radiation.f90``).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    enabled: tuple[int, ...]
    states_per_dof: tuple[int, ...]
    path: str


def _ss_rows(p: Path, what: str) -> list[tuple[int, list[float]]]:
    """(line number, numbers) of an SS_Fitting file after its title; text after ``%`` is a comment."""
    if not p.is_file():
        raise OpenFASTFormatError(f"{what} file not found: tried '{p.absolute()}'.")
    rows: list[tuple[int, list[float]]] = []
    for number, text in enumerate(p.read_text(encoding="latin-1").splitlines(), start=1):
        tokens = text.split("%")[0].split()
        if number == 1 or not tokens:
            continue
        try:
            rows.append((number, [float(t.replace("D", "E").replace("d", "e")) for t in tokens]))
        except ValueError:
            raise OpenFASTFormatError(f"{p}, line {number}: expected numbers, got {text.strip()[:60]!r}. "
                                      "Regenerate the file with SS_Fitting.") from None
    return rows


def _ss_matrices(p: Path, body: list[tuple[int, list[float]]], widths: list[int], after: int) -> list[list[float]]:
    """The rows of A, B, C (``widths`` numbers each) after line ``after``, checked."""
    n = widths[0]
    if len(body) != len(widths):
        raise OpenFASTFormatError(f"{p}: expected {len(widths)} matrix rows after line {after} (A: {n}, B: {n}, C: 6), "
                                  f"got {len(body)}.")
    for (number, row), width in zip(body, widths):
        if len(row) != width:
            raise OpenFASTFormatError(f"{p}, line {number}: expected {width} numbers, got {len(row)}.")
    return [row for _, row in body]


@dataclass(frozen=True, eq=False)
class ExcitationFit:
    """A state-space fit of the wave excitation (SS_Fitting's ``.ssexctn``): ẋ = A x + B η(t + Tc), F = C x [SI].

    ``heading`` [deg] the wave heading it was fitted for, ``delay`` Tc [s] (the elevation it is driven by is
    ``delay`` ahead), dimensional as written (HydroDyn uses them as they are, ``SS_Excitation.f90``).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    heading: float
    delay: float
    states_per_dof: tuple[int, ...]
    path: str


def read_wamit_ssexctn(path) -> ExcitationFit:
    """Read a wave-excitation state-space file (``root.ssexctn``) as HydroDyn does (``SS_Excitation.f90``): a
    title, the wave heading [deg], the time offset Tc [s], the number of states n, the states per DOF (6), then
    n rows of A (n values), n rows of B (1), 6 rows of C (n). Errors as :func:`read_wamit_ss`."""
    p = Path(path)
    rows = _ss_rows(p, "wave-excitation state-space (PotFile + '.ssexctn', ExctnMod = 2)")
    if len(rows) < 4 or len(rows[3][1]) != 6:
        raise OpenFASTFormatError(f"{p}: expected the heading, Tc, the number of states and the 6 states per DOF on "
                                  "lines 2-5.")
    n, per_dof = int(rows[2][1][0]), rows[3][1]
    if sum(per_dof) != n:
        raise OpenFASTFormatError(f"{p}, line {rows[2][0]}: {n} states, but the states per DOF {per_dof} add up to "
                                  f"{sum(per_dof):g}.")
    data = _ss_matrices(p, rows[4:], [n] * n + [1] * n + [n] * 6, rows[3][0])
    return ExcitationFit(np.array(data[:n]), np.array(data[n:2 * n]).ravel(), np.array(data[2 * n:]),
                         float(rows[0][1][0]), float(rows[1][1][0]), tuple(int(k) for k in per_dof), str(p))


def read_wamit_ss(path) -> RadiationFit:
    """Read a radiation state-space file (``root.ss``) as HydroDyn does (``SS_Radiation.f90``):
    a title, the enabled DOFs (6 flags), the number of states n, the states per DOF (6), then n
    rows of A (n values), n rows of B (6), 6 rows of C (n). Text after ``%`` is a comment.

    Raises
    ------
    OpenFASTFormatError
        Missing file, a short or malformed row, counts that do not add up (file and line).
    """
    p = Path(path)
    rows = _ss_rows(p, "radiation state-space (PotFile + '.ss', RdtnMod = 2)")
    if len(rows) < 3:
        raise OpenFASTFormatError(f"{p}: expected the enabled DOFs, the number of states and the states per DOF "
                                  "on lines 2-4.")
    enabled, (count_line, count), per_dof = rows[0][1], rows[1], rows[2][1]
    n = int(count[0])
    if len(enabled) != 6 or len(per_dof) != 6 or sum(per_dof) != n:
        raise OpenFASTFormatError(f"{p}, line {count_line}: {n} states, but the states per DOF {per_dof} add up to "
                                  f"{sum(per_dof):g} (6 flags and 6 counts expected).")
    data = _ss_matrices(p, rows[3:], [n] * n + [6] * n + [n] * 6, rows[2][0])
    return RadiationFit(np.array(data[:n]), np.array(data[n:2 * n]), np.array(data[2 * n:]),
                        tuple(int(e) for e in enabled), tuple(int(k) for k in per_dof), str(p))
