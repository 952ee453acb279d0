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
:mod:`mbsym.linear.fd`), batches of operating points (:func:`linearize_batch`, in
:mod:`mbsym.linear.batch`) and parameter sensitivities (:func:`sensitivities`, in
:mod:`mbsym.linear.sensitivity`); those names are re-exported here.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from ..equations import EquationsOfMotion, check_nonsingular
from ..exceptions import ArgumentTypeError, DimensionError, OptionError, SolverError
from .fd import elastodyn_steps, fd_rhs
from .functions import jacobian_function, linear_function
from .model import LinearModel
from .outputs import output_matrices, resolve_outputs
from .point import OperatingPoint
from ..protocol import input_units as hook_input_units
from .target import Target

__all__ = ["linearize", "METHODS", "resolve_steps", "resolve_qdd", "rows"]

#: Linearization methods: exact automatic differentiation, or central differences of the rhs.
METHODS = ("exact", "fd", "elastodyn-fd")


def resolve_steps(target: Target, method: str, steps) -> np.ndarray | None:
    """Per-state finite-difference steps (n_x), or None for the exact method."""
    if method not in METHODS:
        raise OptionError(f"unknown linearization method {method!r}; choose one of {list(METHODS)}.")
    eom = target.eom
    if method == "exact":
        if steps is not None:
            raise ArgumentTypeError("steps= is used only with method='fd' (finite differences).")
        return None
    if method == "elastodyn-fd":
        if steps is not None:
            raise ArgumentTypeError("method='elastodyn-fd' uses ElastoDyn's own steps; for other steps use method='fd'.")
        table = elastodyn_steps(target.owner if target.owner is not None else eom)
        h = np.array([table[c] for c in eom.coordinates])
        return np.concatenate([h, h])
    if steps is None:
        raise ArgumentTypeError("method='fd' needs steps=: a dict by coordinate (speeds use the same step) or n_x "
                                "numbers.")
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


def resolve_qdd(eom: EquationsOfMotion, qdd0, n_points: int | None = None):
    """``None``/"rhs" flags or the numeric accelerations for M, C, K."""
    if qdd0 is None or (isinstance(qdd0, str) and qdd0 == "rhs"):
        return qdd0
    if isinstance(qdd0, str):
        raise OptionError(f"qdd0 must be None, 'rhs' or {eom.n_q} numbers; got {qdd0!r}.")
    if n_points is None:
        return eom._vec(qdd0, eom.n_q, "qdd0", eom.coordinates)
    return rows(qdd0, n_points, eom.n_q, "qdd0")


def rows(value, n_points: int, width: int, what: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim <= 1 and arr.size == width:
        arr = np.broadcast_to(arr.reshape(1, width), (n_points, width))
    if arr.shape != (n_points, width):
        raise DimensionError(f"{what} must have shape ({n_points}, {width}) or ({width},); got {arr.shape}.")
    if not np.all(np.isfinite(arr)):
        raise DimensionError(f"{what} must be finite.")
    return np.ascontiguousarray(arr)


def linearize(model, q0=None, qd0=None, u0=None, p: Mapping[str, float] | None = None, *, qdd0=None,
              outputs: Sequence[str] | str | None = None, method: str | None = None, steps=None) -> LinearModel:
    """Linearize the equations of motion about an operating point.

    Parameters
    ----------
    model : EquationsOfMotion or model object
        An object with ``eom`` (e.g. :class:`~mbsym.wind.structure.turbine.TurbineModel`)
        supplies the defaults through its hooks ``linearization_state()`` (else
        ``default_state()``), ``linearization_method()``, ``default_inputs()``
        (evaluated at t = 0), ``default_parameters()`` and the output channels of
        ``output_function()``. A wind turbine linearizes as ``mbsym linearize`` and
        OpenFAST do: at the deck's rotor speed with every displacement zero, by
        ElastoDyn's central differences.
    q0 : sequence of n_q, dict by name, or OperatingPoint, optional
        Coordinates [m, rad] (default: the model's linearization state, else zero). An
        :class:`~mbsym.linear.OperatingPoint` supplies q, qd, u and p at once.
    qd0 : sequence of n_q or dict, optional
        Speeds (default: the model's linearization state, else zero).
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
    method : {"exact", "fd", "elastodyn-fd"} or None, keyword-only
        Default None: the model's own (hook ``linearization_method()``: ``"elastodyn-fd"``
        for a wind turbine), else ``"exact"``. ``"exact"``: automatic differentiation. ``"fd"``: A (and Cy) by central
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
    target = Target(model)
    eom, n = target.eom, target.eom.n_q
    q0, qd0, u0, p = _from_operating_point(q0, qd0, u0, p)
    q, qd = target.state(q0, qd0, hook="linearization_state")
    uu, pp = target.inputs(u0), target.parameters(p)
    qdd_in = resolve_qdd(eom, qdd0)
    if method is None:
        method = target._hook("linearization_method") or "exact"
    h = resolve_steps(target, method, steps)
    sel = resolve_outputs(target, outputs)
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
        A = np.array(fd_rhs(eom)(x, uu, pp, h))
    _check_finite(A, "A", eom)
    y0, Cy, Dy = output_matrices(target, sel, x, uu, pp, h)
    op = {"q": q, "qd": qd, "qdd": qdd, "u": uu, "x": x, "xd": xd, "y": y0,
          "p": dict(zip(eom.parameters, pp.tolist()))}
    return LinearModel(M, C, K, Q.reshape(n, eom.n_u), A, B.reshape(2 * n, eom.n_u), eom.coordinates,
                       eom.states, eom.inputs, op, sel[0], Cy, Dy, sel[1], method, units=dict(eom.units),
                       input_units=hook_input_units(target.owner, eom.inputs))


def _from_operating_point(q0, qd0, u0, p):
    if isinstance(q0, OperatingPoint):
        return q0.q, (q0.qd if qd0 is None else qd0), (q0.u if u0 is None else u0), (q0.p if p is None else p)
    return q0, qd0, u0, p


def _check_finite(A: np.ndarray, what: str, eom: EquationsOfMotion) -> None:
    if not np.all(np.isfinite(A)):
        bad = sorted({eom.states[i] for i in np.argwhere(~np.isfinite(A))[:, 0]})
        raise SolverError(f"the linearization {what} is not finite in the rows of {bad}; check the operating "
                          "point, inputs and parameter values.")
