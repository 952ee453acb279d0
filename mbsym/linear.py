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
Jacobians that reproduce OpenFAST (``method="elastodyn-fd"``), batches of
operating points (:func:`linearize_batch`) and parameter sensitivities
(:func:`sensitivities`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import casadi as ca
import numpy as np

from .equations import SYMBOLIC_SOLVE_MAX_DOF, EquationsOfMotion, check_nonsingular
from .exceptions import DimensionError, ModelDefinitionError, SolverError

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
        lam = np.linalg.eigvals(self.A)
        lam = lam[np.imag(lam) >= 0]
        wn = np.abs(lam)
        zeta = np.where(wn > 0, -np.real(lam) / np.where(wn > 0, wn, 1.0), 1.0)
        order = np.argsort(wn)
        return wn[order] / (2 * np.pi), zeta[order]

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


# --------------------------------------------------------------------------- CasADi Functions
def jacobian_function(eom: EquationsOfMotion) -> ca.Function:
    """``(q, qd, qdd, u, p) -> (M0, C0, K0, Q0)``: the residual's Jacobians, built once per model."""
    cached = getattr(eom, "_jacobian_function", None)
    if cached is not None:
        return cached
    d = eom.symbolic
    e = d.F - d.M @ d.qdd
    outs = [-ca.jacobian(e, d.qdd), -ca.jacobian(e, d.qd), -ca.jacobian(e, d.q), ca.jacobian(e, d.u)]
    outs = ca.cse([ca.densify(v) for v in outs])
    f = ca.Function(f"{eom.name}_linearization", [d.q, d.qd, d.qdd, d.u, d.p], outs,
                    ["q", "qd", "qdd", "u", "p"], ["M", "C", "K", "Q"])
    eom._jacobian_function = f     # private cache: the model itself stays unchanged
    return f


def linear_function(eom: EquationsOfMotion) -> ca.Function:
    """``(q, qd, u, p) -> (M, C, K, Q, A, B, xd)``, all dense, built once per model.

    M, C, K, Q at zero acceleration (``K = -∂F/∂q``, ``Q = ∂F/∂u`` when nothing but
    F depends on q, u); A, B the exact Jacobians of the rhs, at ``q̈_op = M⁻¹F``
    (``K(q̈_op) = K + ∂(M a)/∂q`` at ``a = q̈_op``, see the module docstring);
    ``xd = [qd; q̈_op]``. SX with a symbolic solve of the small M up to 8 DOF, MX
    with a numeric QR beyond.
    """
    cached = getattr(eom, "_mbsym_linear_function", None)
    if cached is not None:
        return cached
    d, n, nu = eom.symbolic, eom.n_q, eom.n_u
    a = ca.SX.sym("a", n)              # K(a) - K(0) = ∂(M a)/∂q, Q(a) - Q(0) = -∂(M a)/∂u
    Ma = d.M @ a
    parts = ca.cse([ca.densify(v) for v in (d.M, -ca.jacobian(d.F, d.qd), -ca.jacobian(d.F, d.q),
                                            ca.jacobian(d.F, d.u), d.F, ca.jacobian(Ma, d.q), ca.jacobian(Ma, d.u))])
    if n <= SYMBOLIC_SOLVE_MAX_DOF:
        args = [d.q, d.qd, d.u, d.p]
        M, C, K, Q, F, Hq, Hu = parts
        qdd_op = ca.solve(M, F)
        sol = ca.solve(M, ca.horzcat(K + ca.substitute(Hq, a, qdd_op), C, Q - ca.substitute(Hu, a, qdd_op)))
        opts = {"cse": True}
    else:
        first = ca.Function("parts", [d.q, d.qd, d.u, d.p], parts[:5])
        second = ca.Function("inertia_gradient", [d.q, d.u, d.p, a], parts[5:])
        args = [ca.MX.sym(s, k) for s, k in (("q", n), ("qd", n), ("u", nu), ("p", eom.n_p))]
        M, C, K, Q, F = first(*args)
        qdd_op = ca.solve(M, F, "qr")
        Hq, Hu = second(args[0], args[2], args[3], qdd_op)
        sol = ca.solve(M, ca.horzcat(K + Hq, C, Q - Hu), "qr")
        opts = {}
    A = ca.vertcat(ca.horzcat(ca.DM.zeros(n, n), ca.DM.eye(n)), -sol[:, : 2 * n])
    B = ca.vertcat(ca.DM.zeros(n, nu), sol[:, 2 * n:])
    outs = [ca.densify(v) for v in (M, C, K, Q, A, B, ca.vertcat(args[1], qdd_op))]
    f = ca.Function(f"{eom.name}_linear", args, outs, ["q", "qd", "u", "p"],
                    ["M", "C", "K", "Q", "A", "B", "xd"], opts)
    eom._mbsym_linear_function = f
    return f


def _fd_function(f: ca.Function, n_x: int, name: str) -> ca.Function:
    """``(x, u, p, h) -> (∂f/∂x)`` by central differences with per-state steps ``h``, as a Function.

    Differentiable in ``p`` (sensitivities of the finite-difference A) and mappable.
    """
    x, u, p, h = (ca.MX.sym(s, k) for s, k in (("x", n_x), ("u", f.size1_in(1)), ("p", f.size1_in(2)), ("h", n_x)))
    H = ca.diag(h)
    X = ca.horzcat(ca.repmat(x, 1, n_x) + H, ca.repmat(x, 1, n_x) - H)
    Y = f.map(2 * n_x)(X, u, p)
    J = (Y[:, :n_x] - Y[:, n_x:]) @ ca.diag(0.5 / h)
    return ca.Function(name, [x, u, p, h], [ca.densify(J)], ["x", "u", "p", "h"], ["J"])


def _fd_rhs(eom: EquationsOfMotion) -> ca.Function:
    cached = getattr(eom, "_mbsym_fd_rhs", None)
    if cached is None:
        cached = _fd_function(eom.functions.rhs, eom.n_x, f"{eom.name}_rhs_fd")
        eom._mbsym_fd_rhs = cached
    return cached


def elastodyn_steps(model) -> dict[str, float]:
    """ElastoDyn's central-difference steps of its linearization, by coordinate name.

    ``ED_Init_Jacobian_x`` (docs/elastodyn_notes.md §7): platform translations
    0.2°·max(TowerHt, 1) [rad·m], platform rotations 2°, first tower modes
    0.02°·TwrFlexL, second tower modes 0.002°·TwrFlexL, yaw / generator azimuth /
    drivetrain 2°, blade first flap and edge modes 0.2°·BldFlexL, second flap
    0.02°·BldFlexL, each at least √eps. ElastoDyn perturbs a speed by the same number
    as its coordinate.

    Parameters
    ----------
    model : TurbineModel
        A wind-turbine model (attribute ``turbine``: TurbineParameters).

    Raises
    ------
    ModelDefinitionError
        If the model has no turbine data, or a coordinate has no ElastoDyn step.
    """
    t = getattr(model, "turbine", None)
    if t is None or not hasattr(t, "tower_height"):
        raise ModelDefinitionError(f"method='elastodyn-fd' needs a wind-turbine model (TurbineModel); got "
                                   f"{type(model).__name__}. Use method='fd' with steps=... instead.")
    deg = np.pi / 180.0
    twr = t.tower_height - t.tower_base_height
    bld = t.tip_radius - t.hub_radius
    table = {"Sg": 0.2 * deg * max(t.tower_height, 1.0), "R": 2 * deg, "TFA1": 0.02 * deg * twr,
             "TFA2": 0.002 * deg * twr, "Yaw": 2 * deg}
    table.update(Sw=table["Sg"], Hv=table["Sg"], P=table["R"], Y=table["R"], TSS1=table["TFA1"],
                 TSS2=table["TFA2"], GeAz=table["Yaw"], DrTr=table["Yaw"], RFrl=table["Yaw"], TFrl=table["Yaw"],
                 Teet=table["Yaw"])
    steps, missing = {}, []
    for c in model.eom.coordinates:
        blade = re.fullmatch(r"B\d+(F1|E1|F2)", c)
        value = table.get(c) if blade is None else (0.02 if blade.group(1) == "F2" else 0.2) * deg * bld
        if value is None:
            missing.append(c)
        else:
            steps[c] = max(value, np.sqrt(np.finfo(float).eps))
    if missing:
        raise ModelDefinitionError(f"no ElastoDyn linearization step for coordinates {missing}; pass "
                                   "method='fd' with steps={name: step} instead.")
    return steps


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
    cache = eom.__dict__.setdefault("_mbsym_output_jacobians", {})
    hit = cache.get(id(f_out))
    if hit is not None and hit[0] is f_out:
        return hit[1], hit[2]
    x, u, p = (ca.MX.sym(s, f_out.size1_in(i)) for i, s in enumerate("xup"))
    y = ca.densify(ca.vertcat(*[ca.vec(v) for v in f_out.call([x, u, p])]))      # one or several outputs
    stacked = ca.Function("outputs", [x, u, p], [y])
    jac = ca.Function("outputs_linear", [x, u, p], [y, ca.densify(ca.jacobian(y, x)), ca.densify(ca.jacobian(y, u))])
    fd = _fd_function(stacked, eom.n_x, "outputs_fd")
    cache[id(f_out)] = (f_out, jac, fd)
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
        h = _named(steps, eom.coordinates, np.full(eom.n_q, np.nan), "steps", eom)
        return np.concatenate([h, h])
    h = np.asarray(steps, dtype=float).reshape(-1)
    h = np.concatenate([h, h]) if h.size == eom.n_q else h
    if h.size != eom.n_x or not np.all(np.isfinite(h) & (h > 0)):
        raise DimensionError(f"steps must be {eom.n_q} or {eom.n_x} positive finite numbers; got {h.tolist()}.")
    return h


def _qdd(eom: EquationsOfMotion, qdd0, n_points: int | None = None):
    """``None``/"rhs" flags or the numeric accelerations for M, C, K."""
    if qdd0 is None or (isinstance(qdd0, str) and qdd0 == "rhs"):
        return qdd0
    if isinstance(qdd0, str):
        raise ValueError(f"qdd0 must be None, 'rhs' or {eom.n_q} numbers; got {qdd0!r}.")
    if n_points is None:
        return eom._vec(qdd0, eom.n_q, "qdd0", eom.coordinates)
    return _rows(qdd0, n_points, eom.n_q, "qdd0")


# --------------------------------------------------------------------------- linearize
def linearize(model, q0=None, qd0=None, u0=None, p: Mapping[str, float] | None = None, *, qdd0=None,
              outputs: Sequence[str] | str | None = None, method: str = "exact", steps=None) -> LinearModel:
    """Linearize the equations of motion about an operating point.

    Parameters
    ----------
    model : EquationsOfMotion or model object
        An object with ``eom`` (e.g. :class:`~mbsym.wind.turbine.TurbineModel`)
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


# --------------------------------------------------------------------------- batches
@dataclass(frozen=True)
class LinearBatch:
    """Linear models at N operating points, stacked along the first axis.

    Attributes
    ----------
    M, C, K : ndarray (N, n_q, n_q); Q : (N, n_q, n_u); A : (N, n_x, n_x); B : (N, n_x, n_u)
    Cy : (N, n_y, n_x); Dy : (N, n_y, n_u)
    x, u, p, y : ndarray (N, n_x), (N, n_u), (N, n_p), (N, n_y)
        Operating points (states, inputs, parameter vectors in the order of
        ``parameters``) and outputs there.
    coordinates, states, inputs, parameters, outputs : tuple of str
    method : str

    ``batch[i]`` is the :class:`LinearModel` of point i; ``len(batch)`` is N.
    """

    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    Q: np.ndarray
    A: np.ndarray
    B: np.ndarray
    Cy: np.ndarray
    Dy: np.ndarray
    x: np.ndarray
    u: np.ndarray
    p: np.ndarray
    y: np.ndarray
    qdd: np.ndarray
    coordinates: tuple[str, ...]
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    parameters: tuple[str, ...]
    outputs: tuple[str, ...] = ()
    output_units: tuple[str, ...] = ()
    method: str = "exact"

    def __len__(self) -> int:
        return self.A.shape[0]

    def __getitem__(self, i: int) -> LinearModel:
        n = len(self.coordinates)
        x = self.x[i]
        op = {"q": x[:n], "qd": x[n:], "qdd": self.qdd[i], "u": self.u[i], "x": x, "y": self.y[i],
              "p": dict(zip(self.parameters, self.p[i].tolist()))}
        return LinearModel(self.M[i], self.C[i], self.K[i], self.Q[i], self.A[i], self.B[i], self.coordinates,
                           self.states, self.inputs, op, self.outputs, self.Cy[i], self.Dy[i], self.output_units,
                           self.method)

    def frequencies(self) -> np.ndarray:
        """|λ|/2π [Hz] of the eigenvalues of every A, sorted, one per pair, shape (N, n_q).

        Complex-conjugate pairs and double zeros (rigid-body modes) give one entry
        each; use ``batch[i].modes()`` for shapes, damping and names.
        """
        lam = np.linalg.eigvals(self.A)
        return np.sort(np.abs(lam), axis=1)[:, ::2] / (2 * np.pi)


def _rows(value, n_points: int, width: int, what: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim <= 1 and arr.size == width:
        arr = np.broadcast_to(arr.reshape(1, width), (n_points, width))
    if arr.shape != (n_points, width):
        raise DimensionError(f"{what} must have shape ({n_points}, {width}) or ({width},); got {arr.shape}.")
    if not np.all(np.isfinite(arr)):
        raise DimensionError(f"{what} must be finite.")
    return np.ascontiguousarray(arr)


def _batch_parameters(target: _Target, p, n_points: int) -> np.ndarray:
    """(N, n_p): a dict of numbers and/or length-N arrays (parameter sweeps)."""
    eom = target.eom
    p = dict(p or {})
    arrays = {k: np.asarray(v, dtype=float).reshape(-1) for k, v in p.items() if np.ndim(v) > 0}
    base = target.parameters({k: v for k, v in p.items() if k not in arrays})
    P = np.tile(base, (n_points, 1))
    for k, v in arrays.items():
        if k not in eom.parameters:
            raise DimensionError(f"unknown parameter {k!r}; this model's parameters are {list(eom.parameters)}.")
        if v.size != n_points or not np.all(np.isfinite(v)):
            raise DimensionError(f"parameter {k!r} has {v.size} values; expected {n_points} finite values "
                                 "(one per point).")
        P[:, eom.parameters.index(k)] = v
    return P


def linearize_batch(model, x0, u0=None, p: Mapping[str, Any] | None = None, *, qdd0=None,
                    outputs: Sequence[str] | str | None = None, method: str = "exact", steps=None,
                    parallel: str = "serial", compile: bool = False) -> LinearBatch:
    """Linearize at N operating points in one call (a CasADi ``map`` over the linearization Functions).

    Parameters
    ----------
    model : EquationsOfMotion or model object
        As for :func:`linearize`.
    x0 : array (N, n_x)
        States ``[q; qd]``, one operating point per row.
    u0 : array (N, n_u) or (n_u,) or dict by name, optional
        Inputs (default: the model's default inputs at t = 0).
    p : dict, optional
        Parameter values by name: numbers (shared) or arrays of N values (sweeps).
    qdd0, outputs, method, steps : optional, keyword-only
        As for :func:`linearize`; ``qdd0`` may be ``"rhs"`` or an (N, n_q) array.
    parallel : {"serial", "thread", "openmp"}, keyword-only
        CasADi's map parallelization.
    compile : bool, keyword-only
        Evaluate the linearization Function as generated C, compiled once and cached
        on disk (:func:`mbsym.codegen.compile_function`; about 1 s the first time for
        the paper45 model, then ~10x faster than CasADi's virtual machine).

    Returns
    -------
    LinearBatch

    Examples
    --------
    >>> import numpy as np, mbsym as mb
    >>> from mbsym.linear import linearize_batch
    >>> sys = mb.System(gravity=[0, 0, -9.81])
    >>> th = sys.coordinates("th")
    >>> sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[0, 0, -1.0]),
    ...                           axis=[0, 1, 0], coordinate=th))
    >>> batch = linearize_batch(sys.equations(), [[0.0, 0.0], [np.pi / 3, 0.0]])
    >>> np.round(batch.K[:, 0, 0], 3)          # m g l cos(th)
    array([9.81 , 4.905])
    """
    target = _Target(model)
    eom, n = target.eom, target.eom.n_q
    X = np.asarray(x0, dtype=float)
    if X.ndim != 2 or X.shape[1] != eom.n_x:
        raise DimensionError(f"x0 must have shape (N, {eom.n_x}) (states {list(eom.states)} in columns); "
                             f"got {X.shape}.")
    N = X.shape[0]
    X = _rows(X, N, eom.n_x, "x0")
    if isinstance(u0, Mapping) or u0 is None:
        U = _rows(target.inputs(u0), N, eom.n_u, "u0")
    else:
        U = _rows(u0, N, eom.n_u, "u0")
    P = _batch_parameters(target, p, N)
    qdd_in = _qdd(eom, qdd0, N)
    h = _steps(target, method, steps)
    sel = _resolve_outputs(target, outputs)
    f = linear_function(eom)
    if compile:
        f = compiled(f)
    res = _mapped(f, N, parallel, X[:, :n], X[:, n:], U, P)
    M, C, K, Q, A, B, xd = (_unstack(r, N) for r in res)
    qdd = np.zeros((N, n))
    if isinstance(qdd_in, str):
        qdd = xd[:, n:, 0]
        K, Q = -M @ A[:, n:, :n], M @ B[:, n:, :]
    elif qdd_in is not None:
        qdd = qdd_in
        jac = _mapped(jacobian_function(eom), N, parallel, X[:, :n], X[:, n:], qdd, U, P)
        K, Q = (_unstack(r, N) for r in jac[2:])
    if h is not None:
        A = _unstack(_mapped(_fd_rhs(eom), N, parallel, X, U, P, np.tile(h, (N, 1)))[0], N)
    if not np.all(np.isfinite(A)):
        bad = np.flatnonzero(~np.all(np.isfinite(A.reshape(N, -1)), axis=1))
        raise SolverError(f"the linearization is not finite at {bad.size} points (first: {bad[:5].tolist()}); "
                          "is the mass matrix singular there? Check those states, inputs and parameters.")
    Y, Cy, Dy = _batch_outputs(target, sel, X, U, P, h, parallel)
    return LinearBatch(M, C, K, Q, A, B, Cy, Dy, X, U, P, Y, qdd, eom.coordinates, eom.states, eom.inputs,
                       eom.parameters, sel[0], sel[1], method)


#: Points per CasADi map in a batch: building a map costs ~N² for large N (0.8 s at N = 10 000
#: for the 16-DOF turbine), so batches run as maps of this size.
MAP_CHUNK = 500


def _mapped(f: ca.Function, N: int, parallel: str, *rows: np.ndarray) -> list[np.ndarray]:
    """``f.map(N)`` on arguments given as (N, k) rows, outputs as numpy arrays (r, N c).

    Evaluated in chunks of :data:`MAP_CHUNK` points through ``Function.buffer()``: CasADi
    reads and writes numpy memory directly, without DM conversions (which cost more
    than the evaluation for large batches).
    """
    rows = [np.ascontiguousarray(r, dtype=float) for r in rows]
    maps: dict[int, ca.Function] = {}
    parts = []
    for start in range(0, N, MAP_CHUNK):
        k = min(MAP_CHUNK, N - start)
        if k not in maps:
            maps[k] = f.map(k, parallel)
        fm = maps[k]
        buf, trigger = fm.buffer()
        args = [r[start:start + k].reshape(-1) for r in rows]      # (k, m) C order = (m, k) F order
        for i, a in enumerate(args):
            buf.set_arg(i, memoryview(a))
        outs = [np.empty(fm.numel_out(j)) for j in range(fm.n_out())]
        for j, o in enumerate(outs):
            buf.set_res(j, memoryview(o))
        trigger()
        parts.append([o.reshape(fm.size_out(j), order="F") for j, o in enumerate(outs)])
    return [np.concatenate([p[j] for p in parts], axis=1) for j in range(f.n_out())]


def _unstack(a: np.ndarray, N: int) -> np.ndarray:
    """CasADi's horizontally stacked (r, N c) result as (N, r, c)."""
    r = a.shape[0]
    c = a.shape[1] // N
    return a.reshape(r, c, N, order="F").transpose(2, 0, 1)


def _batch_outputs(target, sel, X, U, P, h, parallel):
    N, eom = X.shape[0], target.eom
    names, _, f_out, picks = sel
    Y, Cy, Dy = np.zeros((N, len(picks))), np.zeros((N, len(picks), eom.n_x)), np.zeros((N, len(picks), eom.n_u))
    if f_out is not None and any(k == "y" for k, _ in picks):
        jac, fd = _output_functions(eom, f_out)
        y_all, cy_all, dy_all = _mapped(jac, N, parallel, X, U, P)
        cy_all, dy_all = _unstack(cy_all, N), _unstack(dy_all, N)
        if h is not None:
            cy_all = _unstack(_mapped(fd, N, parallel, X, U, P, np.tile(h, (N, 1)))[0], N)
    for r, (kind, i) in enumerate(picks):
        if kind == "y":
            Y[:, r], Cy[:, r], Dy[:, r] = y_all[i], cy_all[:, i], dy_all[:, i]
        else:
            Y[:, r], Cy[:, r, i] = X[:, i], 1.0
    return Y, Cy, Dy


def compiled(f: ca.Function) -> ca.Function:
    """``f`` as compiled C through :func:`mbsym.codegen.compile_function` (disk cache, gcc -O1).

    Falls back to ``f`` itself (with a ``CompilationWarning``) when no compiler works.
    """
    from .codegen import compile_function

    return compile_function(f).function


# --------------------------------------------------------------------------- sensitivities
@dataclass(frozen=True)
class Sensitivity:
    """Derivatives of a linear model with respect to named parameters.

    Attributes
    ----------
    parameters : tuple of str
        The parameters, in the order of the first axis of every array.
    linear : LinearModel
        The model at the nominal parameters.
    dM, dC, dK : ndarray (n_s, n_q, n_q); dQ : (n_s, n_q, n_u); dA : (n_s, n_x, n_x); dB : (n_s, n_x, n_u)
    modes : list of Mode
        The nominal modes (:meth:`LinearModel.modes`).
    dfreq : ndarray (n_s, n_modes)
        ∂(natural frequency [Hz]) / ∂parameter, per mode (0 for rigid-body modes).
    dzeta : ndarray (n_s, n_modes)
        ∂(damping ratio) / ∂parameter.
    """

    parameters: tuple[str, ...]
    linear: LinearModel
    dM: np.ndarray
    dC: np.ndarray
    dK: np.ndarray
    dQ: np.ndarray
    dA: np.ndarray
    dB: np.ndarray
    modes: list
    dfreq: np.ndarray
    dzeta: np.ndarray

    def of(self, parameter: str) -> dict[str, np.ndarray]:
        """All derivatives with respect to one parameter, by name (``"M"``, ``"A"``, ``"freq"`` …)."""
        if parameter not in self.parameters:
            raise KeyError(f"no sensitivity for {parameter!r}; computed for {list(self.parameters)}.")
        i = self.parameters.index(parameter)
        return {"M": self.dM[i], "C": self.dC[i], "K": self.dK[i], "Q": self.dQ[i], "A": self.dA[i],
                "B": self.dB[i], "freq": self.dfreq[i], "zeta": self.dzeta[i]}


def _sensitivity_function(eom: EquationsOfMotion, fd: bool) -> ca.Function:
    """``(q, qd, qdd, u, p, h) -> ∂vec(M, C, K, Q)/∂p`` at qdd, ∂vec(A, B)/∂p (and ∂vec(A_fd)/∂p)."""
    key = "_mbsym_sensitivity_fd" if fd else "_mbsym_sensitivity"
    cached = getattr(eom, key, None)
    if cached is not None:
        return cached
    n, nu = eom.n_q, eom.n_u
    q, qd, qdd, u, p, h = (ca.MX.sym(s, k) for s, k in (("q", n), ("qd", n), ("qdd", n), ("u", nu),
                                                          ("p", eom.n_p), ("h", 2 * n)))
    mats = list(jacobian_function(eom)(q, qd, qdd, u, p)) + list(linear_function(eom)(q, qd, u, p)[4:6])
    if fd:
        mats.append(_fd_rhs(eom)(ca.vertcat(q, qd), u, p, h))
    outs = [ca.densify(ca.jacobian(ca.vec(m), p)) for m in mats]
    f = ca.Function(key.strip("_"), [q, qd, qdd, u, p, h], outs)
    setattr(eom, key, f)
    return f


def sensitivities(model, parameters: Sequence[str] | str, q0=None, qd0=None, u0=None,
                  p: Mapping[str, float] | None = None, *, qdd0=None, method: str = "exact",
                  steps=None) -> Sensitivity:
    """∂M, ∂C, ∂K, ∂Q, ∂A, ∂B and ∂(frequency), ∂(damping) with respect to named parameters.

    By automatic differentiation of the same Functions :func:`linearize` uses (with
    ``method="fd"``/``"elastodyn-fd"``: the exact derivative of the finite-difference A).
    Arguments as for :func:`linearize`; ``parameters`` names model parameters, e.g.
    ``["tower_stiffness_scale", "nacelle_mass"]``. Mode sensitivities use
    ∂λ = wᴴ ∂A v / (wᴴ v) with the left and right eigenvectors of A.

    Examples
    --------
    >>> import mbsym as mb
    >>> from mbsym.linear import sensitivities
    >>> sys = mb.System()
    >>> x = sys.coordinates("x")
    >>> m, k = sys.parameters("m k", values={"m": 2.0, "k": 8.0})
    >>> sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("b", m), axis=[1, 0, 0], coordinate=x))
    >>> sys.add_spring(x, k)
    >>> s = sensitivities(sys.equations(), ["k"], [0.0])
    >>> float(s.of("k")["K"][0, 0]), round(float(s.of("k")["freq"][-1]), 5)   # 1, 1/(4π sqrt(k m))
    (1.0, 0.01989)
    """
    from .modal import mode_sensitivities

    target = _Target(model)
    eom, n = target.eom, target.eom.n_q
    names = [parameters] if isinstance(parameters, str) else list(parameters)
    unknown = [s for s in names if s not in eom.parameters]
    if unknown or not names:
        raise DimensionError(f"unknown parameters {unknown or '(none given)'}; this model's parameters are "
                             f"{list(eom.parameters)}.")
    lin = linearize(model, q0, qd0, u0, p, qdd0=qdd0, method=method, steps=steps)
    op = lin.operating_point
    pp = eom.parameter_vector(op["p"])
    h = _steps(target, method, steps)
    qdd = np.zeros(n) if qdd0 is None or isinstance(qdd0, str) else op["qdd"]
    jac = [np.array(j) for j in _sensitivity_function(eom, h is not None)(op["q"], op["qd"], qdd, op["u"], pp,
                                                                            np.ones(2 * n) if h is None else h)]
    cols = [eom.parameters.index(s) for s in names]
    shapes = [(n, n), (n, n), (n, n), (n, eom.n_u), (2 * n, 2 * n), (2 * n, eom.n_u), (2 * n, 2 * n)]
    d = [np.stack([j[:, c].reshape(s, order="F") for c in cols]) for j, s in zip(jac, shapes)]
    dM, dC, dK, dQ, dA, dB = d[:6]
    if isinstance(qdd0, str):                 # exact K = -M A21, Q = M B2 (product rule)
        A21 = -np.linalg.solve(lin.M, lin.K)
        dK = -(dM @ A21 + lin.M @ dA[:, n:, :n])
        dQ = dM @ lin.B[n:] + lin.M @ dB[:, n:]
    if h is not None:
        dA = d[6]                             # the derivative of the finite-difference A
    modes = lin.modes()
    dfreq, dzeta = mode_sensitivities(lin.A, dA, modes)
    return Sensitivity(tuple(names), lin, dM, dC, dK, dQ, dA, dB, modes, dfreq, dzeta)
