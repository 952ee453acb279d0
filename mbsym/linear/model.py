"""The linear model ``M δq̈ + C δq̇ + K δq = Q δu`` and its first-order form (a plain record)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["LinearModel", "Frequencies", "natural_frequencies"]


class Frequencies(tuple):
    """``(freq_hz, damping_ratio)`` of :meth:`LinearModel.frequencies`, labelled.

    Unpacks as the pair ``f, zeta = lin.frequencies()``; also has the attributes ``freq_hz``
    [Hz], ``damping_ratio`` [-] and ``labels`` (the coordinate carrying most of each entry's
    kinetic energy), and prints as a table.
    """

    def __new__(cls, freq_hz: np.ndarray, damping_ratio: np.ndarray, labels) -> "Frequencies":
        obj = super().__new__(cls, (freq_hz, damping_ratio))
        obj.labels = tuple(labels)
        return obj

    @property
    def freq_hz(self) -> np.ndarray:
        return self[0]

    @property
    def damping_ratio(self) -> np.ndarray:
        return self[1]

    def __repr__(self) -> str:
        rows = [f"{f:12.6g} Hz  zeta {z:9.4g}  {lab}" for f, z, lab in zip(self[0], self[1], self.labels)]
        return "Frequencies(\n" + "\n".join(rows) + "\n)"


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
    units : dict of str to str
        Unit of each state by name (``"m"``, ``"rad/s"`` …; empty if unknown).
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
    units: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.Cy is None:
            object.__setattr__(self, "Cy", np.zeros((0, len(self.states))))
        if self.Dy is None:
            object.__setattr__(self, "Dy", np.zeros((0, len(self.inputs))))

    def frequencies(self) -> "Frequencies":
        """Natural frequencies [Hz] and damping ratios [-] of the eigenvalues of A, labelled.

        One entry per complex-conjugate pair (and per real eigenvalue), sorted by
        frequency; rigid-body (zero) eigenvalues give frequency 0. Unpacks as
        ``f, zeta = lin.frequencies()``; ``.labels`` names the coordinate carrying most
        of each entry's kinetic energy (``|Re(conj(v_i) (M v)_i)|``). See :meth:`modes`
        for one entry per mode with its shape.
        """
        lam, V = np.linalg.eig(self.A)
        keep = np.flatnonzero(np.imag(lam) >= 0)
        wn = np.abs(lam[keep])
        order = keep[np.argsort(wn, kind="stable")]
        lam = lam[order]
        wn = np.abs(lam)
        zeta = np.where(wn > 0, -np.real(lam) / np.where(wn > 0, wn, 1.0), 1.0)
        n = len(self.coordinates)
        labels = []
        for k in order:
            v = V[:n, k]
            share = np.abs((v.conj() * (self.M @ v)).real) if self.M.shape == (n, n) else np.abs(v)
            labels.append(self.coordinates[int(np.argmax(share))] if n else "")
        return Frequencies(wn / (2 * np.pi), zeta, labels)

    def __repr__(self) -> str:
        def named(names, limit=6):
            shown = [f"{s} [{self.units.get(s, '-')}]" for s in names[:limit]]
            return ", ".join(shown) + (f", … ({len(names)} in all)" if len(names) > limit else "") or "none"

        f = self.frequencies()
        modes = ", ".join(f"{fr:.4g} Hz ({lab})" for fr, lab in list(zip(f[0], f.labels))[:6])
        outs = ", ".join(f"{o} [{u}]" for o, u in zip(self.outputs, self.output_units)) or "none"
        return (f"LinearModel(method={self.method!r}; states: {named(self.coordinates)} and their speeds; "
                f"inputs: {', '.join(self.inputs[:4]) or 'none'}{' …' if len(self.inputs) > 4 else ''}; "
                f"outputs: {outs}; frequencies: {modes}{' …' if len(f[0]) > 6 else ''})")

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
