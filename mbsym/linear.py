"""Linearized equations of motion (paper Sect. 2.5, Eqs. 24-26).

About an operating point ``(q0, qd0, qdd0, u0)`` the residual ``e = F - M qdd``
gives ``M0 δq̈ + C0 δq̇ + K0 δq = Q0 δu`` with

``M0 = -∂e/∂q̈``, ``C0 = -∂e/∂q̇``, ``K0 = -∂e/∂q``, ``Q0 = ∂e/∂u``,

all from CasADi's automatic differentiation of the residual (no symbolic
inverse). ``qdd0`` defaults to zero: at an equilibrium that is the operating
point's own acceleration.

The first-order model ``δẋ = A δx + B δu`` is always the Jacobian of the
nonlinear right-hand side ``ẋ = f(x, u) = [q̇; M⁻¹F]`` at ``(x0, u0)``, computed
in residual form at the operating point's own acceleration ``q̈_op = M0⁻¹F0``:

``A = [[0, I], [-M0⁻¹K(q̈_op), -M0⁻¹C0]]``, ``B = [[0], [M0⁻¹Q(q̈_op)]]``,

with a numeric (≤ 8 DOF: symbolic QR of the small M0) solve. Away from an
equilibrium (q̈_op ≠ 0, e.g. OpenFAST's linearization at the initial state)
``K(q̈_op) = K(0) + ∂(M q̈_op)/∂q`` carries the ``-M⁻¹(∂M/∂q) q̈_op`` terms
of OpenFAST's A; then ``A`` is *not* ``[[0, I], [-M0⁻¹K0, -M0⁻¹C0]]`` with the
``K0`` at ``qdd0 = 0`` (pass ``qdd0="rhs"`` to get the consistent ``K0``).

Options: outputs (``C``, ``D`` of OpenFAST-named channels), finite-difference
Jacobians that reproduce OpenFAST (``method="elastodyn-fd"``, steps in
:mod:`mbsym._fd`), batches of operating points (:func:`linearize_batch`, in
:mod:`mbsym.linear_batch`) and parameter sensitivities (:func:`sensitivities`, in
:mod:`mbsym.sensitivity`); those names are re-exported here.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import casadi as ca
import numpy as np

from ._fd import _fd_function, _fd_rhs, elastodyn_steps
from .equations import SYMBOLIC_SOLVE_MAX_DOF, EquationsOfMotion, check_nonsingular
from .exceptions import DimensionError, SolverError

__all__ = ["LinearModel", "LinearBatch", "Sensitivity", "linearize", "linearize_batch", "sensitivities",
           "jacobian_function", "linear_function", "elastodyn_steps", "METHODS"]

#: Linearization methods: exact automatic differentiation, or central differences of the rhs.
METHODS = ("exact", "fd", "elastodyn-fd")


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
        freq, zeta = _natural_frequencies(self.A[np.newaxis])
        return freq[0], zeta[0]

    def modes(self, *, rigid_tol: float = 1e-4) -> list:
        """Modes of A (:func:`mbsym.modal.modal_analysis`): frequency, damping, shape, dominant DOF."""
        from .modal import modal_analysis

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


def _natural_frequencies(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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


# --------------------------------------------------------------------------- CasADi Functions
def _cached(eom: EquationsOfMotion, key, build):
    """``build()`` once per model and ``key``, kept in the model's one private cache dict.

    Every derived Function of the linearization modules (``linear``, ``linear_batch``,
    ``sensitivity``, ``_fd``, ``operating``) is cached here; the model stays otherwise
    unchanged.
    """
    cache = eom.__dict__.setdefault("_mbsym_cache", {})
    if key not in cache:
        cache[key] = build()
    return cache[key]


def _residual_parts(eom: EquationsOfMotion) -> dict[str, ca.Function]:
    """The residual's Jacobians from one ``casadi.cse`` pass, the only derivation the linearization pays.

    ``"parts"``: ``(q, qd, u, p) -> (M, C0, K0, Q0, F)`` at zero acceleration;
    ``"inertia"``: ``(q, u, p, a) -> (∂(M a)/∂q, ∂(M a)/∂u)``; ``"jacobians"``:
    ``(q, qd, qdd, u, p) -> (M, C, K, Q)`` at any acceleration, ``K = K0 + ∂(M qdd)/∂q``,
    ``Q = Q0 - ∂(M qdd)/∂u`` (the Jacobians of ``e = F - M qdd``).
    """
    def build():
        d = eom.symbolic
        a = ca.SX.sym("qdd", eom.n_q)
        Ma = d.M @ a
        M, C, K, Q, F, Hq, Hu = ca.cse([ca.densify(v) for v in (
            d.M, -ca.jacobian(d.F, d.qd), -ca.jacobian(d.F, d.q), ca.jacobian(d.F, d.u), d.F,
            ca.jacobian(Ma, d.q), ca.jacobian(Ma, d.u))])
        return {"parts": ca.Function(f"{eom.name}_residual_parts", [d.q, d.qd, d.u, d.p], [M, C, K, Q, F],
                                     ["q", "qd", "u", "p"], ["M", "C", "K", "Q", "F"]),
                "inertia": ca.Function(f"{eom.name}_inertia_gradient", [d.q, d.u, d.p, a], [Hq, Hu],
                                       ["q", "u", "p", "a"], ["Hq", "Hu"]),
                "jacobians": ca.Function(f"{eom.name}_linearization", [d.q, d.qd, a, d.u, d.p],
                                         [M, C, K + Hq, Q - Hu], ["q", "qd", "qdd", "u", "p"],
                                         ["M", "C", "K", "Q"])}

    return _cached(eom, "residual_parts", build)


def jacobian_function(eom: EquationsOfMotion) -> ca.Function:
    """``(q, qd, qdd, u, p) -> (M0, C0, K0, Q0)``: the residual's Jacobians, built once per model."""
    return _residual_parts(eom)["jacobians"]


def linear_function(eom: EquationsOfMotion) -> ca.Function:
    """``(q, qd, u, p) -> (M, C, K, Q, A, B, xd)``, all dense, built once per model.

    M, C, K, Q at zero acceleration (``K = -∂F/∂q``, ``Q = ∂F/∂u`` when nothing but
    F depends on q, u); A, B the exact Jacobians of the rhs, at ``q̈_op = M⁻¹F``
    (``K(q̈_op) = K + ∂(M a)/∂q`` at ``a = q̈_op``, see the module docstring);
    ``xd = [qd; q̈_op]``. SX with a symbolic solve of the small M up to 8 DOF, MX
    with a numeric QR beyond.
    """
    return _cached(eom, "linear_function", lambda: _build_linear_function(eom))


def _build_linear_function(eom: EquationsOfMotion) -> ca.Function:
    n, nu = eom.n_q, eom.n_u
    built = _residual_parts(eom)
    first, second = built["parts"], built["inertia"]
    sym = ca.SX.sym if n <= SYMBOLIC_SOLVE_MAX_DOF else ca.MX.sym
    args = [sym(s, k) for s, k in (("q", n), ("qd", n), ("u", nu), ("p", eom.n_p))]
    M, C, K, Q, F = first(*args)
    if n <= SYMBOLIC_SOLVE_MAX_DOF:                # symbolic QR of the small M
        qdd_op = ca.solve(M, F)
        Hq, Hu = second(args[0], args[2], args[3], qdd_op)
        sol = ca.solve(M, ca.horzcat(K + Hq, C, Q - Hu))
        opts = {"cse": True}
    else:
        qdd_op = ca.solve(M, F, "qr")
        Hq, Hu = second(args[0], args[2], args[3], qdd_op)
        sol = ca.solve(M, ca.horzcat(K + Hq, C, Q - Hu), "qr")
        opts = {}
    A = ca.vertcat(ca.horzcat(ca.DM.zeros(n, n), ca.DM.eye(n)), -sol[:, : 2 * n])
    B = ca.vertcat(ca.DM.zeros(n, nu), sol[:, 2 * n:])
    outs = [ca.densify(v) for v in (M, C, K, Q, A, B, ca.vertcat(args[1], qdd_op))]
    return ca.Function(f"{eom.name}_linear", args, outs, ["q", "qd", "u", "p"],
                       ["M", "C", "K", "Q", "A", "B", "xd"], opts)


# --------------------------------------------------------------------------- model resolution
class _Target:
    """An EquationsOfMotion, or a model object with ``eom`` and optional hooks (mbsym.simulate's protocol)."""

    def __init__(self, model: Any) -> None:
        if isinstance(model, EquationsOfMotion):
            self.eom, self.owner = model, None
        elif isinstance(getattr(model, "eom", None), EquationsOfMotion):
            self.eom, self.owner = model.eom, model
        else:
            raise TypeError(f"model must be an EquationsOfMotion or an object whose attribute 'eom' is one; "
                            f"got {type(model).__name__}.")

    def _hook(self, name: str):
        f = getattr(self.owner, name, None) if self.owner is not None else None
        return f() if callable(f) else None

    def state(self, q0, qd0) -> tuple[np.ndarray, np.ndarray]:
        eom, n = self.eom, self.eom.n_q
        x = np.zeros(eom.n_x)
        if q0 is None or qd0 is None:
            default = self._hook("default_state")
            if default is not None:
                from .simulate.checks import initial_state

                x = initial_state(default, eom.states, x)
        q = x[:n] if q0 is None else _named(q0, eom.coordinates, x[:n], "q0", eom)
        qd = x[n:] if qd0 is None else _named(qd0, eom.speeds, x[n:], "qd0", eom)
        return q, qd

    def inputs(self, u0) -> np.ndarray:
        eom = self.eom
        default = np.zeros(eom.n_u)
        hook = self._hook("default_inputs")
        if hook:
            from .simulate.inputs import input_signal

            default = input_signal(hook, eom.inputs, 0.0).at(0.0)
        if u0 is None:
            return default
        return _named(u0, eom.inputs, default, "u0", eom)

    def parameters(self, p) -> np.ndarray:
        merged = dict(self._hook("default_parameters") or {})
        if p is not None and not isinstance(p, Mapping):
            return self.eom.parameter_vector(p)      # raises the ParameterError for a non-dict
        merged.update(p or {})
        return self.eom.parameter_vector(merged)

    def output_function(self):
        """(function, names, units) of the owner's output channels, or None."""
        hook = getattr(self.owner, "output_function", None) if self.owner is not None else None
        if not callable(hook):
            return None
        out = hook()
        f = getattr(out, "function", out)
        names = tuple(getattr(out, "names", None) or getattr(self.owner, "output_names", None) or f.name_out())
        units = tuple(getattr(out, "units", ("",) * len(names)))
        return f, names, units


def _named(value, names, default: np.ndarray, what: str, eom: EquationsOfMotion) -> np.ndarray:
    """A vector from an array (all entries) or a dict by name (missing names keep ``default``)."""
    if isinstance(value, Mapping):
        unknown = sorted(set(value) - set(names))
        if unknown:
            raise DimensionError(f"{what} names unknown entries {unknown}; expected names from {list(names)}.")
        arr = default.copy()
        for i, n in enumerate(names):
            if n in value:
                arr[i] = float(value[n])
        return eom._vec(arr, len(names), what, names)
    return eom._vec(value, len(names), what, names)


def _resolve_outputs(target: _Target, outputs) -> tuple[tuple[str, ...], tuple[str, ...], Any, list]:
    """Selected output names, units, the channel Function (or None) and, per output, a channel or state index."""
    if outputs is None:
        return (), (), None, []
    eom = target.eom
    chan = target.output_function()
    if isinstance(outputs, str):
        outputs = None if outputs == "all" else [outputs]
        if outputs is None:
            if chan is None:
                raise DimensionError("outputs='all' needs a model with output_function(); name states instead.")
            outputs = list(chan[1])
    names, units, picks, unknown = [], [], [], []
    for raw in outputs:
        name = re.sub(r"_\[[^\]]*\]$", "", str(raw))        # accept OpenFAST headers 'TTDspFA_[m]'
        if chan is not None and name in chan[1]:
            i = chan[1].index(name)
            picks.append(("y", i))
            units.append(chan[2][i])
        elif name in eom.states:
            picks.append(("x", eom.states.index(name)))
            units.append("")
        else:
            unknown.append(raw)
        names.append(name)
    if unknown:
        known = list(chan[1]) if chan is not None else []
        raise DimensionError(f"unknown outputs {unknown}; choose output channels {known} or states {list(eom.states)}.")
    return tuple(names), tuple(units), (chan[0] if chan is not None else None), picks


def _output_functions(eom: EquationsOfMotion, f_out: ca.Function) -> tuple[ca.Function, ca.Function]:
    """``(x, u, p) -> (y, ∂y/∂x, ∂y/∂u)`` and the central-difference ``∂y/∂x``, cached per Function."""
    def build():
        x, u, p = (ca.MX.sym(s, f_out.size1_in(i)) for i, s in enumerate("xup"))
        y = ca.densify(ca.vertcat(*[ca.vec(v) for v in f_out.call([x, u, p])]))      # one or several outputs
        stacked = ca.Function("outputs", [x, u, p], [y])
        jac = ca.Function("outputs_linear", [x, u, p],
                          [y, ca.densify(ca.jacobian(y, x)), ca.densify(ca.jacobian(y, u))])
        return f_out, jac, _fd_function(stacked, eom.n_x, "outputs_fd")

    # keyed by id: the entry holds f_out itself, so that id cannot be reused by another object
    _, jac, fd = _cached(eom, ("output_jacobians", id(f_out)), build)
    return jac, fd


def _output_matrices(target: _Target, sel, x, u, p, h=None):
    """(y0, Cy, Dy) of the selected outputs; Cy by central differences with steps h if given."""
    names, _, f_out, picks = sel
    n_x, n_u = target.eom.n_x, target.eom.n_u
    y0, Cy, Dy = np.zeros(len(picks)), np.zeros((len(picks), n_x)), np.zeros((len(picks), n_u))
    if f_out is not None and any(k == "y" for k, _ in picks):
        jac, fd = _output_functions(target.eom, f_out)
        y_all, cy_all, dy_all = (np.array(v) for v in jac(x, u, p))
        if h is not None:
            cy_all = np.array(fd(x, u, p, h))
    for r, (kind, i) in enumerate(picks):
        if kind == "y":
            y0[r], Cy[r], Dy[r] = y_all[i, 0], cy_all[i], dy_all[i]
        else:
            y0[r], Cy[r, i] = x[i], 1.0
    return y0, Cy, Dy


def _steps(target: _Target, method: str, steps) -> np.ndarray | None:
    """Per-state finite-difference steps (n_x), or None for the exact method."""
    if method not in METHODS:
        raise ValueError(f"unknown linearization method {method!r}; choose one of {list(METHODS)}.")
    eom = target.eom
    if method == "exact":
        if steps is not None:
            raise TypeError("steps= is used only with method='fd' (finite differences).")
        return None
    if method == "elastodyn-fd":
        if steps is not None:
            raise TypeError("method='elastodyn-fd' uses ElastoDyn's own steps; for other steps use method='fd'.")
        table = elastodyn_steps(target.owner if target.owner is not None else eom)
        h = np.array([table[c] for c in eom.coordinates])
        return np.concatenate([h, h])
    if steps is None:
        raise TypeError("method='fd' needs steps=: a dict by coordinate (speeds use the same step) or n_x numbers.")
    if isinstance(steps, Mapping):
        return _step_dict(steps, eom)
    h = np.asarray(steps, dtype=float).reshape(-1)
    h = np.concatenate([h, h]) if h.size == eom.n_q else h
    if h.size != eom.n_x or not np.all(np.isfinite(h) & (h > 0)):
        raise DimensionError(f"steps must be {eom.n_q} or {eom.n_x} positive finite numbers; got {h.tolist()}.")
    return h


def _step_dict(steps: Mapping, eom: EquationsOfMotion) -> np.ndarray:
    """Steps by coordinate name (the speed uses the same one): every coordinate, each finite and > 0."""
    unknown = sorted(set(steps) - set(eom.coordinates))
    missing = [c for c in eom.coordinates if c not in steps]
    if unknown or missing:
        raise DimensionError(f"steps must name every coordinate once; unknown {unknown}, missing {missing} "
                             f"(coordinates: {list(eom.coordinates)}).")
    bad = {}
    for c in eom.coordinates:
        try:
            value = float(steps[c])
        except (TypeError, ValueError):
            value = steps[c]
        if not (isinstance(value, float) and np.isfinite(value) and value > 0):
            bad[c] = value
    if bad:
        raise DimensionError(f"steps must be positive finite numbers [m or rad]; got {bad}.")
    h = np.array([float(steps[c]) for c in eom.coordinates])
    return np.concatenate([h, h])


def _qdd(eom: EquationsOfMotion, qdd0, n_points: int | None = None):
    """``None``/"rhs" flags or the numeric accelerations for M, C, K."""
    if qdd0 is None or (isinstance(qdd0, str) and qdd0 == "rhs"):
        return qdd0
    if isinstance(qdd0, str):
        raise ValueError(f"qdd0 must be None, 'rhs' or {eom.n_q} numbers; got {qdd0!r}.")
    if n_points is None:
        return eom._vec(qdd0, eom.n_q, "qdd0", eom.coordinates)
    return _rows(qdd0, n_points, eom.n_q, "qdd0")


def _rows(value, n_points: int, width: int, what: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim <= 1 and arr.size == width:
        arr = np.broadcast_to(arr.reshape(1, width), (n_points, width))
    if arr.shape != (n_points, width):
        raise DimensionError(f"{what} must have shape ({n_points}, {width}) or ({width},); got {arr.shape}.")
    if not np.all(np.isfinite(arr)):
        raise DimensionError(f"{what} must be finite.")
    return np.ascontiguousarray(arr)


# --------------------------------------------------------------------------- linearize
def linearize(model, q0=None, qd0=None, u0=None, p: Mapping[str, float] | None = None, *, qdd0=None,
              outputs: Sequence[str] | str | None = None, method: str = "exact", steps=None) -> LinearModel:
    """Linearize the equations of motion about an operating point.

    Parameters
    ----------
    model : EquationsOfMotion or model object
        An object with ``eom`` (e.g. :class:`~mbsym.wind.structure.turbine.TurbineModel`)
        supplies the defaults through its hooks ``default_state()``,
        ``default_inputs()`` (evaluated at t = 0), ``default_parameters()`` and the
        output channels of ``output_function()``.
    q0 : sequence of n_q, dict by name, or OperatingPoint, optional
        Coordinates [m, rad] (default: the model's default state, else zero). An
        :class:`~mbsym.operating.OperatingPoint` supplies q, qd, u and p at once.
    qd0 : sequence of n_q or dict, optional
        Speeds (default: the model's default state, else zero).
    u0 : sequence of n_u or dict by name, optional
        Inputs (default: the model's default inputs at t = 0, else zero).
    p : dict, optional
        Parameter values by name (defaults fill the gaps).
    qdd0 : sequence of n_q or "rhs", optional, keyword-only
        Acceleration at which M, C, K, Q are evaluated: zero by default, ``"rhs"``
        for the operating point's own ``M⁻¹F`` (then ``A = [[0, I], [-M⁻¹K, -M⁻¹C]]``
        exactly). A and B never depend on it.
    outputs : list of str or "all", optional, keyword-only
        Output channels of the model (e.g. ``"TTDspFA"``, ``"QD2_TFA1"``,
        ``"RotSpeed"``, ``"GenSpeed"``; OpenFAST headers ``"TTDspFA_[m]"`` work too)
        or state names: gives ``Cy``, ``Dy``.
    method : {"exact", "fd", "elastodyn-fd"}, keyword-only
        ``"exact"``: automatic differentiation. ``"fd"``: A (and Cy) by central
        differences of the nonlinear rhs (and outputs) with ``steps`` (dict by
        coordinate, the speed uses the same number, or n_x numbers). ``"elastodyn-fd"``:
        ``"fd"`` with ElastoDyn's own steps (:func:`elastodyn_steps`), which
        reproduces OpenFAST's linearization including its finite-step error: its
        steps are large (2° for platform rotations), and around a point that is not
        an equilibrium the O(h²) terms of the strongly nonlinear platform pitch move
        a floating platform's pitch frequency by ~0.8 % (docs/elastodyn_notes.md §8.3).
        B and Dy stay exact (our inputs are not ElastoDyn's).

    Returns
    -------
    LinearModel

    Raises
    ------
    SingularMassMatrixError
        If M0 is singular (naming the coordinates involved). A singular K (a free
        DOF) is fine: it gives a rigid-body mode.
    DimensionError, ParameterError
        For wrong sizes, unknown names or missing parameters.

    Examples
    --------
    >>> import mbsym as mb
    >>> sys = mb.System(gravity=[0, 0, -9.81])
    >>> th = sys.coordinates("th")
    >>> sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[0, 0, -1.0]),
    ...                           axis=[0, 1, 0], coordinate=th))
    >>> lin = mb.linearize(sys.equations(), [0.0])
    >>> round(float(lin.K[0, 0]), 2)    # m g l
    9.81
    """
    target = _Target(model)
    eom, n = target.eom, target.eom.n_q
    q0, qd0, u0, p = _from_operating_point(q0, qd0, u0, p)
    q, qd = target.state(q0, qd0)
    uu, pp = target.inputs(u0), target.parameters(p)
    qdd_in = _qdd(eom, qdd0)
    h = _steps(target, method, steps)
    sel = _resolve_outputs(target, outputs)
    M, C, K, Q, A, B, xd = (np.array(v) for v in linear_function(eom)(q, qd, uu, pp))
    check_nonsingular(M, eom.coordinates)
    xd = xd.reshape(-1)
    qdd = np.zeros(n)
    if isinstance(qdd_in, str):                 # "rhs": M, C, K, Q consistent with A, B
        qdd = xd[n:]
        K, Q = -M @ A[n:, :n], M @ B[n:]
    elif qdd_in is not None:                    # K, Q at the given acceleration
        qdd = qdd_in
        _, _, K, Q = (np.array(v) for v in jacobian_function(eom)(q, qd, qdd, uu, pp))
    x = np.concatenate([q, qd])
    if h is not None:
        A = np.array(_fd_rhs(eom)(x, uu, pp, h))
    _check_finite(A, "A", eom)
    y0, Cy, Dy = _output_matrices(target, sel, x, uu, pp, h)
    op = {"q": q, "qd": qd, "qdd": qdd, "u": uu, "x": x, "xd": xd, "y": y0,
          "p": dict(zip(eom.parameters, pp.tolist()))}
    return LinearModel(M, C, K, Q.reshape(n, eom.n_u), A, B.reshape(2 * n, eom.n_u), eom.coordinates,
                       eom.states, eom.inputs, op, sel[0], Cy, Dy, sel[1], method)


def _from_operating_point(q0, qd0, u0, p):
    from .operating import OperatingPoint

    if isinstance(q0, OperatingPoint):
        return q0.q, (q0.qd if qd0 is None else qd0), (q0.u if u0 is None else u0), (q0.p if p is None else p)
    return q0, qd0, u0, p


def _check_finite(A: np.ndarray, what: str, eom: EquationsOfMotion) -> None:
    if not np.all(np.isfinite(A)):
        bad = sorted({eom.states[i] for i in np.argwhere(~np.isfinite(A))[:, 0]})
        raise SolverError(f"the linearization {what} is not finite in the rows of {bad}; check the operating "
                          "point, inputs and parameter values.")


# --------------------------------------------------------------------------- re-exports
# Batches and sensitivities live in their own modules, which import the core above; importing them
# last (the names above already exist) keeps ``from mbsym.linear import linearize_batch`` working.
from .linear_batch import MAP_CHUNK, LinearBatch, compiled, linearize_batch  # noqa: E402, F401
from .sensitivity import Sensitivity, sensitivities  # noqa: E402
