"""Natural periods of a rigid floating platform from its mass and stiffness matrices.

The undamped free vibrations ``M q̈ + K q = 0`` have ``K φ = ω² M φ`` (the generalized
eigenproblem). With the infinite-frequency added mass A∞ in M, the periods are those of the
platform's response to sudden motion; a lightly damped free decay oscillates near the
frequency ω where ``K φ = ω² (M_s + A(ω)) φ`` holds with the *frequency-dependent* added mass
(the radiation memory's in-phase part): :func:`periods_with_frequency_dependent_added_mass`
solves that fixed point per mode. Numbers only (numpy).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...exceptions import DimensionError, SolverError

__all__ = ["PlatformModes", "natural_periods", "periods_with_frequency_dependent_added_mass", "PLATFORM_DOFS"]

#: The platform DOFs in order (ElastoDyn's names).
PLATFORM_DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")


@dataclass(frozen=True)
class PlatformModes:
    """Modes sorted by their dominant DOF: ``periods`` [s] (inf for a zero stiffness),
    ``frequencies`` [rad/s], ``shapes`` (columns, unit max-norm), ``dominant`` DOF names."""

    periods: np.ndarray
    frequencies: np.ndarray
    shapes: np.ndarray
    dominant: tuple[str, ...]

    def period(self, dof: str) -> float:
        """The period [s] of the mode dominated by ``dof`` (``"surge"``, …, ``"yaw"``)."""
        if dof not in self.dominant:
            raise KeyError(f"no mode dominated by {dof!r}; modes: {self.dominant}")
        return float(self.periods[self.dominant.index(dof)])


def _check(mass, stiffness) -> tuple[np.ndarray, np.ndarray]:
    M, K = np.asarray(mass, dtype=float), np.asarray(stiffness, dtype=float)
    if M.shape != K.shape or M.ndim != 2 or M.shape[0] != M.shape[1]:
        raise DimensionError(f"mass {M.shape} and stiffness {K.shape} must be square matrices of one size.")
    if not (np.all(np.isfinite(M)) and np.all(np.isfinite(K))):
        raise DimensionError("mass and stiffness must be finite.")
    return M, K


def natural_periods(mass, stiffness, names: tuple[str, ...] = PLATFORM_DOFS) -> PlatformModes:
    """Undamped natural periods of ``M q̈ + K q = 0``.

    Parameters
    ----------
    mass, stiffness : (n, n) array_like
        M [kg, kg m, kg m²] (structure + added mass) and K [N/m, N/rad, …].
    names : tuple of str
        DOF names (default the six platform DOFs).

    Returns
    -------
    PlatformModes
        One mode per DOF, ordered by dominant DOF when each DOF dominates one mode; otherwise
        ordered by frequency, and ``dominant`` may name a DOF twice (``period`` gives the first).

    Examples
    --------
    >>> modes = natural_periods(np.diag([4.0, 1.0]), np.diag([1.0, 4.0]), ("a", "b"))
    >>> modes.period("a") / np.pi, modes.period("b") / np.pi
    (4.0, 1.0)
    """
    M, K = _check(mass, stiffness)
    values, vectors = np.linalg.eig(np.linalg.solve(M, K))
    omega = np.sqrt(np.clip(values.real, 0.0, None))
    shapes = vectors.real / np.abs(vectors.real).max(axis=0)
    scale = np.sqrt(np.abs(np.diag(M)))          # compare DOFs by their share of kinetic energy
    dominant = [int(np.argmax(np.abs(shapes[:, k]) * scale)) for k in range(len(omega))]
    order = np.argsort(dominant, kind="stable") if len(set(dominant)) == len(dominant) else np.argsort(omega)
    omega, shapes = omega[order], shapes[:, order]
    with np.errstate(divide="ignore"):
        periods = np.where(omega > 0, 2 * np.pi / np.where(omega > 0, omega, 1.0), np.inf)
    return PlatformModes(periods, omega, shapes, tuple(names[dominant[k]] for k in order))


def _added_mass_at(omega: float, frequencies, added, zero, infinite) -> np.ndarray:
    """A(ω) interpolated linearly between the tabulated frequencies, A(0) and A∞ at the ends."""
    w = np.concatenate(([0.0], frequencies)) if zero is not None else np.asarray(frequencies)
    table = np.concatenate((zero[None], added)) if zero is not None else np.asarray(added)
    if omega >= w[-1]:
        return table[-1] if infinite is None else infinite
    k = int(np.clip(np.searchsorted(w, omega) - 1, 0, len(w) - 2))
    t = (omega - w[k]) / (w[k + 1] - w[k])
    return (1 - t) * table[k] + t * table[k + 1]


def periods_with_frequency_dependent_added_mass(structure_mass, stiffness, wamit, *, platform=(0, 1, 2, 3, 4, 5),
                                                names: tuple[str, ...] = PLATFORM_DOFS, tol: float = 1e-10,
                                                max_iter: int = 200) -> PlatformModes:
    """Natural periods with A(ω) at each mode's own frequency: ``K φ = ω² (M_s + A(ω)) φ``.

    Parameters
    ----------
    structure_mass, stiffness : (n, n) array_like
        The structure's (ElastoDyn's) mass matrix and the total stiffness (hydrostatics,
        gravity, mooring, elasticity) [SI], about the platform reference point.
    wamit : WamitHydrodynamics
        ``frequencies``, ``added_mass``, ``added_mass_zero``, ``added_mass_infinite``.
    platform : sequence of 6 int, keyword-only
        Positions of surge, sway, heave, roll, pitch, yaw among the n DOFs (default the first six).
    names : tuple of str, keyword-only
        The n DOF names (default the six platform DOFs).
    tol, max_iter : keyword-only
        Relative change of ω that ends the fixed-point iteration, and its bound.

    Raises
    ------
    SolverError
        When a mode's iteration does not settle.
    """
    Ms, K = _check(structure_mass, stiffness)
    rows = np.ix_(list(platform), list(platform))

    def with_added(A):
        out = Ms.copy()
        out[rows] += A[:6, :6]
        return out

    first = natural_periods(with_added(wamit.added_mass_infinite), K, names)
    omegas, shapes = first.frequencies.copy(), first.shapes.copy()
    for k in range(len(omegas)):
        if omegas[k] == 0:
            continue
        omega = omegas[k]
        for _ in range(max_iter):
            A = _added_mass_at(omega, wamit.frequencies, wamit.added_mass[:, :6, :6], wamit.added_mass_zero,
                               wamit.added_mass_infinite)
            modes = natural_periods(with_added(A), K, names)
            j = int(np.argmax(np.abs(modes.shapes.T @ shapes[:, k])))  # the same mode (largest overlap)
            new = modes.frequencies[j]
            done = abs(new - omega) <= tol * omega
            omega, shapes[:, k] = new, modes.shapes[:, j]
            if done:
                break
        else:
            raise SolverError(f"the {first.dominant[k]} mode's frequency did not settle with A(omega) "
                              f"({max_iter} iterations, last {omega:.6g} rad/s).")
        omegas[k] = omega
    with np.errstate(divide="ignore"):
        periods = np.where(omegas > 0, 2 * np.pi / np.where(omegas > 0, omegas, 1.0), np.inf)
    return PlatformModes(periods, omegas, shapes, first.dominant)
