"""Radiation memory as a linear state-space block, and its accuracy against the WAMIT ``.1`` data.

The radiation load beyond the infinite-frequency added mass is a convolution of the platform
velocity with the retardation kernel; in the frequency domain
``F(iω) = −[B(ω) + iω (A(ω) − A∞)] q̇(iω)`` (Cummins' equation; HydroDyn ``Conv_Radiation.f90``
builds its kernel from B(ω)). A state-space fit replaces it by ``ẋ = A x + B q̇``,
``F = C x`` (HydroDyn ``SS_Radiation.f90``, ``RdtnMod = 2``, matrices from SS_Fitting's ``.ss``).

:class:`RadiationStateSpace` holds such a block, gives its state derivative and load as numbers or
CasADi expressions, its frequency response, and :meth:`RadiationStateSpace.accuracy`: the largest
difference from the ``.1`` data per matrix entry, relative to that entry's peak, and whether the fit
is passive (it never gives energy to the platform: the Hermitian part of −H(iω) positive
semidefinite at every tabulated frequency).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import DimensionError
from ..deck.wamit import RadiationFit, WamitHydrodynamics
from ._casadi import _in, _out

__all__ = ["RadiationStateSpace", "radiation_reference"]


def radiation_reference(wamit: WamitHydrodynamics) -> np.ndarray:
    """−[B(ω) + iω (A(ω) − A∞)] at the ``.1`` frequencies, ``k × 6 × 6`` complex [N s/m, …]."""
    omega = wamit.frequencies[:, None, None]
    return -(wamit.damping[:, :6, :6] + 1j * omega * (wamit.added_mass[:, :6, :6] - wamit.added_mass_infinite[:6, :6]))


@dataclass(frozen=True, eq=False)
class RadiationStateSpace:
    """``ẋ = A x + B q̇``, ``F = C x`` (see the module docstring); ``q̇`` the six platform velocities."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray

    def __post_init__(self) -> None:
        A, B, C = (np.array(m, dtype=float) for m in (self.A, self.B, self.C))
        n = A.shape[0]
        if A.shape != (n, n) or B.shape != (n, 6) or C.shape != (6, n):
            raise DimensionError(f"radiation state space: A {A.shape}, B {B.shape}, C {C.shape}; expected "
                                 "(n, n), (n, 6), (6, n).")
        for name, m in (("A", A), ("B", B), ("C", C)):
            m.setflags(write=False)
            object.__setattr__(self, name, m)

    @classmethod
    def from_fit(cls, fit: RadiationFit) -> "RadiationStateSpace":
        """The block of a ``.ss`` file (:func:`mbsym.wind.deck.wamit.read_wamit_ss`); every DOF must be enabled."""
        if any(flag != 1 for flag in fit.enabled):
            raise DimensionError(f"{fit.path}: enabled DOFs {fit.enabled}; HydroDyn's state-space radiation needs all "
                                 "six (its own note in SS_Radiation.f90). Refit with every DOF enabled.")
        return cls(fit.A, fit.B, fit.C)

    @property
    def n_states(self) -> int:
        return self.A.shape[0]

    def derivative(self, x, qd):
        """ẋ = A x + B q̇ (numbers or CasADi)."""
        out = ca.mtimes(ca.DM(self.A), _in(x, self.n_states, "x")) + ca.mtimes(ca.DM(self.B), _in(qd, 6, "qd"))
        return _out(out, x, qd)

    def load(self, x):
        """The radiation force and moment C x [N, N m] (numbers or CasADi)."""
        return _out(ca.mtimes(ca.DM(self.C), _in(x, self.n_states, "x")), x)

    def frequency_response(self, omega) -> np.ndarray:
        """H(iω) = C (iω I − A)⁻¹ B at each ω [rad/s], ``len(ω) × 6 × 6`` complex."""
        eye = np.eye(self.n_states)
        return np.array([self.C @ np.linalg.solve(1j * w * eye - self.A, self.B) for w in np.atleast_1d(omega)])

    def accuracy(self, wamit: WamitHydrodynamics, *, max_frequency: float = np.inf) -> dict:
        """How well the block reproduces the ``.1`` data up to ``max_frequency`` [rad/s] (module docstring).

        Returns
        -------
        dict
            ``"error"``: 6×6 max |H − H_ref| / max |H_ref| per entry (nan where the reference is 0);
            ``"damping_error"``: the same for the real parts (the damping B(ω));
            ``"passive"``: bool; ``"min_dissipation"``: the smallest eigenvalue of the Hermitian part
            of −H(iω) over the frequencies [mixed units: N s/m, N m s/rad]; ``"relative_dissipation"``: the
            same after scaling each DOF by the square root of its peak damping B_ii (dimensionless, so
            translations and rotations count alike); ``"stable"``: all eigenvalues of A in the left
            half-plane.
        """
        band = wamit.frequencies <= max_frequency
        H = self.frequency_response(wamit.frequencies[band])
        ref = radiation_reference(wamit)[band]
        with np.errstate(invalid="ignore", divide="ignore"):
            peak = np.abs(ref).max(axis=0)
            error = np.where(peak > 0, np.abs(H - ref).max(axis=0) / peak, np.nan)
            peak_b = np.abs(ref.real).max(axis=0)
            error_b = np.where(peak_b > 0, np.abs(H.real - ref.real).max(axis=0) / peak_b, np.nan)
        dissipation = min(np.linalg.eigvalsh(-(h + h.conj().T).real / 2).min() for h in H)
        diagonal = np.abs(np.diagonal(ref.real, axis1=1, axis2=2)).max(axis=0)
        scale = np.where(diagonal > 0, 1.0 / np.sqrt(np.where(diagonal > 0, diagonal, 1.0)), 1.0)
        relative = min(np.linalg.eigvalsh(-scale[:, None] * (h + h.conj().T).real / 2 * scale[None, :]).min()
                       for h in H)
        return {"error": error, "damping_error": error_b, "passive": bool(dissipation >= 0),
                "min_dissipation": float(dissipation), "relative_dissipation": float(relative), "stable": bool(np.linalg.eigvals(self.A).real.max() < 0)}
