"""The linear model ``M δq̈ + C δq̇ + K δq = Q δu`` and its first-order form (a plain record)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["LinearModel", "natural_frequencies"]


@dataclass(frozen=True)
class LinearModel:
    """Linear model ``M δq̈ + C δq̇ + K δq = Q δu``, its first-order form and outputs.

    Attributes
    ----------
    M, C, K : ndarray (n_q, n_q)
        Mass, damping and stiffness matrices (residual Jacobians at ``qdd0``).
    Q : ndarray (n_q, n_u)
        Input matrix.
    A : ndarray (2 n_q, 2 n_q), B : ndarray (2 n_q, n_u)
        ``δẋ = A δx + B δu``, the Jacobians of the first-order rhs for ``x = [q; qd]``.
    coordinates, states, inputs : tuple of str
        Names of q, x and u.
    operating_point : dict
        ``q``, ``qd``, ``qdd`` (the acceleration used for M, C, K), ``u``, ``x``,
        ``xd`` (the rhs, i.e. ``[qd; q̈_op]``), ``y`` (outputs) as arrays, and ``p``
        (dict by name).
    outputs : tuple of str
        Names of the selected outputs ``y`` (empty: none selected).
    Cy : ndarray (n_y, 2 n_q), Dy : ndarray (n_y, n_u)
        ``δy = Cy δx + Dy δu``.
    output_units : tuple of str
    method : str
        ``"exact"``, ``"fd"`` or ``"elastodyn-fd"`` (how A and Cy were obtained).
    """

    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    Q: np.ndarray
    A: np.ndarray
    B: np.ndarray
    coordinates: tuple[str, ...]
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    operating_point: dict = field(default_factory=dict)
    outputs: tuple[str, ...] = ()
    Cy: np.ndarray | None = None
    Dy: np.ndarray | None = None
    output_units: tuple[str, ...] = ()
    method: str = "exact"

    def __post_init__(self) -> None:
        if self.Cy is None:
            object.__setattr__(self, "Cy", np.zeros((0, len(self.states))))
        if self.Dy is None:
            object.__setattr__(self, "Dy", np.zeros((0, len(self.inputs))))

    def frequencies(self) -> tuple[np.ndarray, np.ndarray]:
        """Natural frequencies [Hz] and damping ratios [-] of the eigenvalues of A.

        One entry per complex-conjugate pair (and per real eigenvalue), sorted by
        frequency; rigid-body (zero) eigenvalues give frequency 0. See
        :meth:`modes` for one entry per mode with its shape.
        """
        freq, zeta = natural_frequencies(self.A[np.newaxis])
        return freq[0], zeta[0]

    def modes(self, *, rigid_tol: float = 1e-4) -> list:
        """Modes of A (:func:`mbsym.modal.modal_analysis`): frequency, damping, shape, dominant DOF."""
        from ..modal import modal_analysis

        return modal_analysis(self.A, self.coordinates, rigid_tol=rigid_tol)

    def to_statespace(self, *, name: str | None = None):
        """A named ``control.StateSpace`` (python-control) of ``(A, B, Cy, Dy)``.

        Without selected outputs, the outputs are the states (``Cy = I``). The
        operating point is attached as the attribute ``operating_point`` (dict, see
        the class attributes); signals are named by ``states``, ``inputs`` and
        ``outputs``.

        Examples
        --------
        >>> import mbsym as mb
        >>> sys = mb.System()
        >>> x = sys.coordinates("x")
        >>> F = sys.inputs("F")
        >>> sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("m", 2.0), axis=[1, 0, 0], coordinate=x))
        >>> sys.add_spring(x, 8.0); sys.add_generalized_force(x, F)
        >>> ss = mb.linearize(sys.equations(), [0.0], outputs=["x"]).to_statespace()
        >>> ss.state_labels, ss.input_labels, ss.output_labels
        (['x', 'x_d'], ['F'], ['x'])
        """
        import control

        if self.outputs:
            C, D, outs = self.Cy, self.Dy, list(self.outputs)
        else:
            C, D, outs = np.eye(len(self.states)), np.zeros((len(self.states), len(self.inputs))), list(self.states)
        B = self.B.reshape(len(self.states), len(self.inputs))
        ss = control.ss(self.A, B, C, D.reshape(len(outs), len(self.inputs)), states=list(self.states),
                        inputs=list(self.inputs), outputs=outs, name=name)
        ss.operating_point = dict(self.operating_point)
        return ss


def natural_frequencies(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies [Hz] and damping ratios of a stack of state matrices (N, n_x, n_x).

    The rule of :meth:`LinearModel.frequencies`: the eigenvalues with Im λ ≥ 0 (one per
    complex-conjugate pair, every real one), ``|λ|/2π`` sorted ascending with
    ``ζ = -Re λ/|λ|`` (1 at λ = 0). Points with fewer such eigenvalues than the most
    (real eigenvalues count once each) are padded with NaN at the end: shape (N, n_max).
    """
    lam = np.linalg.eigvals(A)
    keep = np.imag(lam) >= 0
    wn = np.where(keep, np.abs(lam), np.inf)
    order = np.argsort(wn, axis=1, kind="stable")
    lam, wn, keep = (np.take_along_axis(v, order, axis=1) for v in (lam, wn, keep))
    n_max = int(keep.sum(axis=1).max(initial=0))
    lam, wn, keep = lam[:, :n_max], wn[:, :n_max], keep[:, :n_max]
    zeta = np.where(wn > 0, -np.real(lam) / np.where(wn > 0, wn, 1.0), 1.0)
    return np.where(keep, wn / (2 * np.pi), np.nan), np.where(keep, zeta, np.nan)
