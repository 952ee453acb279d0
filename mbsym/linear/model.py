"""The linear model ``M δq̈ + C δq̇ + K δq = Q δu`` and its first-order form (a plain record)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

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
    input_units : tuple of str
        Unit of each input (empty if unknown).
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
    input_units: tuple[str, ...] = ()

    @property
    def mechanical(self) -> bool:
        """Whether the states are exactly ``[q; q̇]`` (coordinates, then their speeds)."""
        return tuple(self.states) == tuple(self.coordinates) + tuple(f"{c}_d" for c in self.coordinates)

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
        if not self.mechanical:
            from .state_modes import state_modes

            modes = state_modes(self.A, self.states, rigid_tol=0.0)         # one eigen-decomposition for all
            return Frequencies(wn / (2 * np.pi), zeta, [_nearest_group(modes, lam_k) for lam_k in lam])
        labels = []
        for k in order:
            v = V[:n, k]
            share = np.abs((v.conj() * (self.M @ v)).real) if self.M.shape == (n, n) else np.abs(v)
            labels.append(self.coordinates[int(np.argmax(share))] if n else "")
        return Frequencies(wn / (2 * np.pi), zeta, labels)

    def __repr__(self) -> str:
        def named(names, units):
            return ", ".join(f"{s} [{u or '-'}]" for s, u in zip(names, units)) or "none"

        f = self.frequencies()
        modes = ", ".join(f"{fr:.4g} Hz ({lab})" for fr, lab in list(zip(f[0], f.labels))[:12])
        inputs = named(self.inputs, self.input_units or [""] * len(self.inputs))
        if self.mechanical:
            states = named(self.coordinates, [self.units.get(s, "") for s in self.coordinates]) + " and their speeds"
        else:
            states = named(self.states, [self.units.get(s, "") for s in self.states])
        return (f"LinearModel(method={self.method!r}; {len(self.states)} states: {states}; inputs: {inputs}; "
                f"outputs: {named(self.outputs, self.output_units)}; "
                f"frequencies: {modes}{' …' if len(f[0]) > 12 else ''})")

    def without_states(self, names, *, tol: float = 1e-9) -> "LinearModel":
        """The model without the states ``names``, on which no other state and no output depends.

        Removing a state is exact for every other state and output when its columns of ``A``
        and ``Cy`` vanish: the free rotor azimuth (``GeAz``) of an azimuth-independent model only
        integrates the rotor speed. ``M`` and ``coordinates`` are kept (the structure's); the
        operating point records the removed states' values under ``removed_states``.

        Parameters
        ----------
        names : str or sequence of str
        tol : float, keyword-only
            Largest allowed ``|A[i, j]|`` (other states i) and ``|Cy[i, j]|``, relative to the
            largest entry of row i.

        Raises
        ------
        DimensionError
            Unknown state names.
        ModelDefinitionError
            Another state or an output depends on a removed state.
        """
        from ..exceptions import DimensionError, ModelDefinitionError

        names = [names] if isinstance(names, str) else list(names)
        unknown = [n for n in names if n not in self.states]
        if unknown:
            raise DimensionError(f"no states {unknown}; the states are {list(self.states)}.")
        drop = [self.states.index(n) for n in names]
        keep = [i for i in range(len(self.states)) if i not in drop]
        coupled = []
        for label, mat in (("A", self.A[keep]), ("Cy", self.Cy)):
            scale = np.maximum(np.max(np.abs(mat), axis=1, initial=0.0), 1e-300)[:, None]
            coupled += [f"{n} (column of {label})" for j, n in zip(drop, names)
                        if mat.size and np.any(np.abs(mat[:, [j]]) > tol * scale)]
        if coupled:
            raise ModelDefinitionError(f"cannot remove {coupled}: other states or outputs depend on them (e.g. an "
                                       "azimuth-dependent rotor); keep them (keep_azimuth=True, mbsym linearize "
                                       "--keep-azimuth) or average over the azimuth (multi-blade coordinates) first.")
        op = dict(self.operating_point)
        x = op.get("x")
        full = x is not None and np.size(x) == len(self.states)
        op["removed_states"] = {n: float(np.asarray(x)[j]) if full else float("nan") for j, n in zip(drop, names)}
        for key in ("x", "xd"):
            if op.get(key) is not None and np.size(op[key]) == len(self.states):
                op[key] = np.asarray(op[key])[keep]
        return replace(self, A=self.A[np.ix_(keep, keep)], B=self.B.reshape(len(self.states), -1)[keep],
                       Cy=self.Cy[:, keep], states=tuple(self.states[i] for i in keep), operating_point=op,
                       units={s: u for s, u in self.units.items() if s not in names})

    def modes(self, *, rigid_tol: float = 1e-4) -> list:
        """Modes of A, sorted by frequency.

        A mechanical model (states ``[q; q̇]``): :func:`mbsym.modal.modal_analysis` (frequency,
        damping, shape, dominant DOF). Any other (actuator, inflow or controller states, a
        removed azimuth): :func:`mbsym.linear.state_modes.state_modes`, each mode named by the
        state group with the largest participation factor.
        """
        if not self.mechanical:
            from .state_modes import state_modes

            return state_modes(self.A, self.states, rigid_tol=rigid_tol)
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


def _nearest_group(modes, lam: complex) -> str:
    """The dominant state group of the mode (:func:`~.state_modes.state_modes`) whose eigenvalue is nearest ``lam``."""
    return min(modes, key=lambda m: abs(m.eigenvalue - lam)).dominant_dof if modes else ""


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
