"""Result of an identification, and the statistics computed at the optimum.

Standard errors come from the linearization at the optimum (nonlinear
least-squares theory): with ``J`` the Jacobian of the weighted residuals with
respect to all unknowns (estimated initial states and parameters; the condensed
Jacobian of the shooting problem, i.e. the sensitivities of the simulated
channels) and ``σ̂² = ‖r‖² / (M − n)`` the residual variance (``M`` residuals,
``n`` unknowns), the covariance is ``σ̂² (JᵀJ)⁻¹``. This assumes independent
residuals of equal variance after weighting: weight channels by the inverse of
their noise level for meaningful standard errors.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import IdentifiabilityWarning

__all__ = ["IdentificationResult", "covariance", "fit_error"]


@dataclass(frozen=True)
class IdentificationResult:
    """What :func:`mbsym.identify` returns; values in the units of each parameter's label.

    Attributes
    ----------
    parameters, std, initial : dict
        Estimate, standard error and starting value by label (the key as passed,
        e.g. ``"TwrFADmp(1)"`` in %, or the model's parameter name).
    names : tuple of str
        The labels, in the order of ``correlation`` and ``covariance``.
    units : dict
        Unit of each label ("" if unknown).
    correlation, covariance : ndarray (n, n)
        Of the estimates (covariance in label units).
    eps : dict
        Fit error per channel, ``mean|y − y_data| / range(y_data)`` (fraction) of a
        simulation with the estimates from the estimated initial state, over all
        records; :attr:`eps_pct` in percent.
    initial_states : list of dict
        Per record, the initial state used (estimated entries included), by state name.
    iterations : int
    wall_s : float
        Wall time of the whole call [s] (building, compiling, solving, statistics).
    timings : dict
        ``build_s``, ``compile_s``, ``solve_s``, ``statistics_s`` [s].
    success : bool
    message : str
    cost : float
        ``½ Σ r²`` at the optimum (weighted residuals).
    residual_std : float
        ``σ̂`` (weighted units).
    n_residuals : int
    substeps : int
        RK4 sub-steps per sample interval.
    method : str
    compiled : bool
    channels : tuple of str
    weights : dict
        Weight of each channel's residual.
    fit : list of dict
        Per record: ``time`` (N,) and ``y`` (N, n_c) simulated with the estimates.
    initial_state_std : list of dict
        Per record, standard errors of the estimated initial states (inf: not seen by the channels).
    history : list of dict
        Per Gauss–Newton iteration: cost, gap, step, line-search ``alpha``.
    """

    parameters: dict
    std: dict
    initial: dict
    names: tuple
    units: dict
    correlation: np.ndarray
    covariance: np.ndarray
    eps: dict
    initial_states: list
    iterations: int
    wall_s: float
    timings: dict
    success: bool
    message: str
    cost: float
    residual_std: float
    n_residuals: int
    substeps: int
    method: str
    compiled: bool
    channels: tuple
    weights: dict
    fit: list = field(default_factory=list, repr=False)
    history: list = field(default_factory=list, repr=False)
    initial_state_std: list = field(default_factory=list, repr=False)

    @property
    def eps_pct(self) -> dict:
        """:attr:`eps` in percent."""
        return {k: 100.0 * v for k, v in self.eps.items()}

    def to_json(self) -> dict:
        """The CLI contract: parameters, std, initial, eps_pct, iterations, wall_s (plain floats)."""
        return {"parameters": {k: float(v) for k, v in self.parameters.items()},
                "std": {k: float(v) for k, v in self.std.items()},
                "initial": {k: float(v) for k, v in self.initial.items()},
                "eps_pct": {k: float(v) for k, v in self.eps_pct.items()},
                "iterations": int(self.iterations), "wall_s": float(self.wall_s)}

    def summary(self) -> str:
        """A table of estimates, standard errors and fit errors."""
        lines = [f"{'parameter':<28}{'initial':>14}{'estimate':>16}{'std':>12}  unit"]
        for k in self.names:
            lines.append(f"{k:<28}{self.initial[k]:>14.6g}{self.parameters[k]:>16.8g}{self.std[k]:>12.3g}  "
                         f"{self.units.get(k, '')}")
        lines.append(f"{'channel':<28}{'eps [%]':>14}")
        lines += [f"{c:<28}{v:>14.4f}" for c, v in self.eps_pct.items()]
        lines.append(f"{self.method}: {self.message}; {self.iterations} iterations, {self.wall_s:.3f} s "
                     f"(solve {self.timings.get('solve_s', 0.0):.3f} s), {self.substeps} RK4 sub-step(s), "
                     f"{'compiled' if self.compiled else 'virtual machine'}")
        return "\n".join(lines)


def covariance(J: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """``(σ̂² (JᵀJ)⁻¹, σ̂, singular values of the column-scaled J)``; infinite variances for a rank-deficient J."""
    M, n = J.shape
    cs = np.linalg.norm(J, axis=0)
    safe = np.where(cs > 0, cs, 1.0)
    U, s, Vt = np.linalg.svd(J / safe, full_matrices=False)
    dof = max(M - n, 1)
    sigma2 = float(r @ r) / dof
    tiny = s <= s[0] * 1e-13 if s.size else np.zeros(0, bool)
    inv = np.where(tiny, 0.0, 1.0 / np.where(tiny, 1.0, s) ** 2)
    cov = (Vt.T * inv) @ Vt / np.outer(safe, safe) * sigma2
    if np.any(tiny) or np.any(cs == 0):
        weak = np.abs(Vt[tiny]).max(axis=0) > 1e-3 if np.any(tiny) else np.zeros(n, bool)
        idx = np.flatnonzero(weak | (cs == 0))
        cov[idx, :] = cov[:, idx] = np.nan
        cov[idx, idx] = np.inf
    return cov, float(np.sqrt(sigma2)), s


def correlation_of(cov: np.ndarray) -> np.ndarray:
    d = np.sqrt(np.abs(np.diag(cov)))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(d, d)
    np.fill_diagonal(corr, 1.0)
    return corr


def warn_identifiability(names, corr: np.ndarray, std: np.ndarray, threshold: float) -> list[str]:
    """Warn (IdentifiabilityWarning) about parameter pairs with |correlation| > threshold or undetermined ones."""
    problems = []
    bad = [names[i] for i in range(len(names)) if not np.isfinite(std[i])]
    if bad:
        problems.append(f"{bad} are not determined by the data (no or collinear sensitivity)")
    for i in range(len(names)):
        for j in range(i + 1, len(names)):
            c = corr[i, j]
            if np.isfinite(c) and abs(c) > threshold:
                problems.append(f"{names[i]} and {names[j]} are nearly collinear (correlation {c:+.4f})")
    if problems:
        warnings.warn("poorly identifiable parameters: " + "; ".join(problems) + ". Fix one of each pair, add "
                      "channels or records that separate them, or accept the large standard errors.",
                      IdentifiabilityWarning, stacklevel=4)
    return problems


def fit_error(y: np.ndarray, y_data: np.ndarray, period: np.ndarray) -> np.ndarray:
    """``mean|y − y_data| / range(y_data)`` per column (wrapped differences for periodic channels).

    A constant data channel is normalized by ``max|y_data|`` (or not at all if zero).
    """
    e = y - y_data
    if np.any(period):
        P = np.where(period > 0, period, 1.0)
        e = np.where(period > 0, e - P * np.round(e / P), e)
    rng = np.ptp(y_data, axis=0)
    scale = np.where(rng > 0, rng, np.where(np.max(np.abs(y_data), axis=0) > 0, np.max(np.abs(y_data), axis=0), 1.0))
    return np.mean(np.abs(e), axis=0) / scale
