"""An operating point to linearize about: state, inputs, parameters and how it was found."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["OperatingPoint"]


@dataclass(frozen=True)
class OperatingPoint:
    """A state, inputs and parameters to linearize about (pass it as ``q0`` to ``linearize``).

    Attributes
    ----------
    q, qd, qdd : ndarray (n_q,)
        Coordinates [m, rad], speeds and accelerations (zero at an equilibrium).
    u : ndarray (n_u,)
        Inputs.
    p : dict
        Parameter values by name.
    coordinates, inputs : tuple of str
    held : tuple of str
        Coordinates kept at their initial value (no stiffness, or the spinning one).
    residual : ndarray (n_q,)
        Generalized forces left at the solution [N, N m] (averaged over azimuth for a
        steady rotation; the spinning coordinate's entry is the torque needed to keep
        the speed constant).
    success : bool
    message : str
    """

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    u: np.ndarray
    p: dict
    coordinates: tuple[str, ...]
    inputs: tuple[str, ...]
    held: tuple[str, ...] = ()
    residual: np.ndarray = field(default_factory=lambda: np.zeros(0))
    success: bool = True
    message: str = ""

    @property
    def x(self) -> np.ndarray:
        """``[q; qd]``."""
        return np.concatenate([self.q, self.qd])
