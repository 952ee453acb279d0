"""``OCP``: a receding-horizon optimal control problem on any model, transcribed stage by stage.

The model is anything :func:`mbsym.as_dynamics` accepts. Its inputs split into
*controls* (decided by the controller) and *disturbances* (known ahead, e.g. a wind
preview: per-stage OCP parameters). Costs, bounds and constraints refer to states,
inputs and outputs by name. :meth:`OCP.transcribe` returns the discrete
:class:`~mbsym.control.stages.StageProblem` (multiple shooting with RK4 sub-steps,
or Radau IIA collocation) with the variables in stage order, plus what
:class:`~mbsym.control.nmpc.NMPC` needs to fill its parameters.

Cost (per stage k = 0..N-1, then the terminal stage N)::

    Σ_terms (s − ref)ᵀ W (s − ref)  +  Σ_rates w (Δu/dt)²  +  l(x, u, p)        (stage)
    Σ_terminal terms (s − ref)ᵀ W (s − ref)  +  l_N(x, p)                          (terminal)

``s`` are signals picked by name; ``Δu/dt`` uses the previous stage's control (the
last applied input at stage 0): the controls with rate terms are carried as extra
states so the problem keeps its stage structure.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Mapping, Sequence

import casadi as ca
import numpy as np

from ..dynamics import Dynamics, as_dynamics
from ..exceptions import ControlDefinitionError
from ._checks import bound_pair, check_names, finite_number, positive_int, symbolic_call, weight_root
from .discretize import Discretization, discretize, symbolic_function
from .stages import StageProblem

__all__ = ["OCP", "Transcription"]

_KINDS = {"x": "state", "u": "input", "y": "output"}


@dataclass(frozen=True)
class _Term:
    names: tuple[str, ...]
    root: np.ndarray          # L with LᵀL = W
    terminal: bool


class OCP:
    """A receding-horizon optimal control problem.

    Parameters
    ----------
    model : Dynamics, EquationsOfMotion or model object
        Anything :func:`mbsym.as_dynamics` accepts.
    horizon : int, keyword-only
        Number of stages N (≥ 1).
    dt : float, keyword-only
        Sample time [s]; the horizon spans ``N dt`` seconds.
    controls : sequence of str, optional, keyword-only
        Inputs decided by the controller (default: all inputs). The other inputs
        are disturbances given per stage at solve time (default: the model's
        nominal inputs).
    method : {"rk4", "collocation"}, keyword-only
        Multiple shooting with RK4 (default) or direct collocation (Radau IIA, degree 3).
    substeps : int, keyword-only
        Integration sub-steps (or collocation intervals) per stage.
    sensitivities : {"auto", "chained", "inline"}, keyword-only
        How the SQP solvers get the RK4 stage Jacobian (see
        :func:`~mbsym.control.discretize.discretize`): chained forward
        sensitivities keep the generated code small for large models.

    Raises
    ------
    ControlDefinitionError
        Bad horizon, sample time, method or control names.

    Examples
    --------
    >>> import casadi as ca, mbsym as mb
    >>> x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    >>> f = ca.Function("f", [x, u, p], [ca.vertcat(x[1], u)])
    >>> dyn = mb.Dynamics(f, states=["pos", "vel"], inputs=["force"])
    >>> ocp = OCP(dyn, horizon=20, dt=0.1).track({"pos": 1.0, "force": 0.01}).bound("force", -1, 1)
    >>> ocp.transcribe().problem.n_x
    2
    """

    def __init__(self, model: Any, *, horizon: int, dt: float, controls: Sequence[str] | None = None,
                 method: str = "rk4", substeps: int = 1, sensitivities: str = "auto") -> None:
        self._dyn: Dynamics = as_dynamics(model)
        self._N = positive_int(horizon, "horizon")
        self._dt = finite_number(dt, "dt [s]", positive=True)
        dyn = self._dyn
        self._controls = check_names(dyn.inputs if controls is None else controls, dyn.inputs, "controls")
        self._disturbances = tuple(n for n in dyn.inputs if n not in self._controls)
        self._disc = discretize(dyn.rhs, self._dt, method=method, substeps=positive_int(substeps, "substeps"),
                                sensitivities=sensitivities)
        self._terms: list[_Term] = []
        self._rate_weights: dict[str, float] = {}
        self._costs: list[tuple[Any, Any]] = []
        self._bounds: dict[str, tuple[float, float]] = {}
        self._soft: dict[str, tuple[float, float]] = {}
        self._rate_limits: dict[str, tuple[float, float]] = {}
        self._constraints: list[tuple[Any, np.ndarray, np.ndarray, bool, str]] = []
        self._references: dict[str, float] = {}

    # ------------------------------------------------------------ description
    dynamics = property(lambda self: self._dyn, doc="The model as :class:`mbsym.Dynamics`.")
    horizon = property(lambda self: self._N, doc="Number of stages N.")
    dt = property(lambda self: self._dt, doc="Sample time [s].")
    controls = property(lambda self: self._controls, doc="Names of the controlled inputs.")
    disturbances = property(lambda self: self._disturbances, doc="Names of the previewed inputs.")
    discretization = property(lambda self: self._disc, doc="The discrete-time map of one stage.")

    def __repr__(self) -> str:
        return (f"OCP({self._dyn.name!r}, horizon={self._N}, dt={self._dt}, controls={list(self._controls)}, "
                f"method={self._disc.method!r})")

    def _resolve(self, name: str) -> tuple[str, int]:
        """``("x"|"u"|"y", index)`` of a signal name; ``"x:name"``, ``"u:name"``, ``"y:name"`` disambiguate."""
        if not isinstance(name, str):
            raise ControlDefinitionError(f"signal names must be strings; got {name!r}.")
        tables = {"x": self._dyn.states, "u": self._dyn.inputs, "y": self._dyn.output_names}
        if len(name) > 2 and name[1] == ":" and name[0] in tables:
            kind, bare = name[0], name[2:]
            if bare not in tables[kind]:
                raise ControlDefinitionError(f"{bare!r} is not a model {_KINDS[kind]}; {_KINDS[kind]}s are "
                                             f"{list(tables[kind])}.")
            return kind, tables[kind].index(bare)
        hits = [(k, t.index(name)) for k, t in tables.items() if name in t]
        if not hits:
            raise ControlDefinitionError(f"unknown signal {name!r}; states {list(tables['x'])}, inputs "
                                         f"{list(tables['u'])}, outputs {list(tables['y'])}.")
        if len(hits) > 1:
            raise ControlDefinitionError(f"signal {name!r} is ambiguous ({[_KINDS[k] for k, _ in hits]}); "
                                         f"prefix it: 'x:{name}', 'u:{name}' or 'y:{name}'.")
        return hits[0]

    # ------------------------------------------------------------------ costs
    def track(self, weights: Mapping[str, float] | None = None, *, names: Sequence[str] | None = None,
              matrix: Any = None, reference: Mapping[str, float] | None = None, terminal: bool = False) -> "OCP":
        """Add a least-squares term ``(s − ref)ᵀ W (s − ref)`` on states, inputs or outputs.

        Parameters
        ----------
        weights : dict, optional
            Diagonal weights by signal name (≥ 0), in 1/unit².
        names, matrix : optional, keyword-only
            Instead of ``weights``: signal names and a symmetric positive
            semi-definite weight matrix.
        reference : dict, optional, keyword-only
            Default references by signal name (0 otherwise); NMPC steps may override them.
        terminal : bool, keyword-only
            A terminal term (at stage N; states and outputs independent of the controls only).

        Returns
        -------
        OCP
            ``self``, to chain calls.
        """
        if (weights is None) == (names is None and matrix is None):
            raise ControlDefinitionError("give either weights={name: w} or names=[...] with matrix=W.")
        if weights is not None:
            if not isinstance(weights, Mapping) or not weights:
                raise ControlDefinitionError(f"weights must be a non-empty dict by signal name; got {weights!r}.")
            sig = tuple(weights)
            root = weight_root([finite_number(w, f"weight of {n!r}", nonnegative=True) for n, w in weights.items()],
                               len(sig), "weights")
        else:
            if names is None or matrix is None:
                raise ControlDefinitionError("names and matrix must be given together.")
            sig = tuple(names.split() if isinstance(names, str) else names)
            root = weight_root(matrix, len(sig), "matrix")
        kinds = [self._resolve(n) for n in sig]
        if terminal:
            self._check_terminal(sig, kinds, "terminal tracking")
        refs = self._checked_references(reference, sig)
        self._terms.append(_Term(sig, root, bool(terminal)))
        self._references.update(refs)
        return self

    def _checked_references(self, reference: Mapping[str, float] | None, sig: Sequence[str]) -> dict[str, float]:
        if reference is None:
            return {n: self._references.get(n, 0.0) for n in sig}
        if not isinstance(reference, Mapping):
            raise TypeError(f"reference must be a dict by signal name; got {type(reference).__name__}.")
        extra = sorted(set(reference) - set(sig))
        if extra:
            raise ControlDefinitionError(f"reference names {extra} are not tracked by this term ({list(sig)}).")
        return {n: finite_number(reference.get(n, self._references.get(n, 0.0)), f"reference of {n!r}")
                for n in sig}

    def _check_terminal(self, sig: Sequence[str], kinds, what: str) -> None:
        bad = [n for n, (k, i) in zip(sig, kinds) if k == "u" or (k == "y" and self._output_uses_controls(i))]
        if bad:
            raise ControlDefinitionError(f"{what} can use states and outputs independent of the controls only; "
                                         f"{bad} depend on the controls.")

    def _output_uses_controls(self, i: int) -> bool:
        f, sym = symbolic_function(self._dyn.outputs)
        x, u, p = (sym.sym(s, f.size1_in(j)) for j, s in enumerate("xup"))
        ctrl = [self._dyn.inputs.index(n) for n in self._controls]
        return bool(ctrl) and ca.depends_on(f(x, u, p)[i], ca.vertcat(*[u[j] for j in ctrl]))

    def penalize_rates(self, weights: Mapping[str, float]) -> "OCP":
        """Add ``w (Δu/dt)²`` per stage for the named controls; ``w`` in (s/unit)²."""
        if not isinstance(weights, Mapping) or not weights:
            raise ControlDefinitionError(f"weights must be a non-empty dict by control name; got {weights!r}.")
        check_names(list(weights), self._controls, "penalize_rates")
        new = {n: finite_number(w, f"rate weight of {n!r}", nonnegative=True) for n, w in weights.items()}
        self._rate_weights.update(new)
        return self

    def add_cost(self, *, stage: Callable | ca.Function | None = None,
                 terminal: Callable | ca.Function | None = None) -> "OCP":
        """Add general costs: ``stage(x, u, p) -> scalar`` per stage, ``terminal(x, p) -> scalar``.

        ``x``, ``u``, ``p`` are the model's full state, input and parameter vectors
        (CasADi symbols). With SQP/RTI solvers the exact Hessian of these terms is
        used: they should be convex.
        """
        if stage is None and terminal is None:
            raise ControlDefinitionError("add_cost needs stage=... and/or terminal=....")
        self._checked_costs(stage, terminal)
        self._costs.append((stage, terminal))
        return self

    def _checked_costs(self, stage, terminal) -> None:
        d = self._dyn
        x, u, p = ca.SX.sym("x", d.n_x), ca.SX.sym("u", d.n_u), ca.SX.sym("p", d.n_p)
        if stage is not None and not isinstance(stage, ca.Function):
            symbolic_call(stage, [x, u, p], "stage cost", 1)
        if terminal is not None and not isinstance(terminal, ca.Function):
            symbolic_call(terminal, [x, p], "terminal cost", 1)

    # ------------------------------------------------------------ constraints
    def bound(self, name: str, lower: float | None = None, upper: float | None = None, *,
              soft: float | tuple[float, float] | None = None) -> "OCP":
        """Bound a state, a control or an output (``None``: unbounded on that side).

        Hard state bounds apply at stages 1..N (the initial state is measured),
        control bounds at 0..N-1, output bounds at every stage where a control
        can change them.

        ``soft=w`` or ``soft=(w1, w2)`` (states and outputs only) makes the bound
        soft: a slack ``σ ≥ 0`` per stage relaxes it (``lower − σ ≤ s ≤ upper + σ``)
        at the cost ``w1 σ + w2 σ²`` (``w`` alone: ``w1 = w2 = w``). With ``w1``
        above the constraint's multiplier the bound is still met whenever it can
        be (exact penalty); otherwise the problem stays feasible instead of failing.
        Soft bounds apply at stages 0..N-1.
        """
        kind, _ = self._resolve(name)
        if kind == "u" and name.split(":")[-1] not in self._controls:
            raise ControlDefinitionError(f"{name!r} is a disturbance (previewed input), not a control: it cannot "
                                         f"be bounded.")
        lo, hi = bound_pair(lower, upper, 1, f"bound of {name!r}")
        weights = None
        if soft is not None:
            if kind == "u":
                raise ControlDefinitionError(f"control bounds are always feasible: {name!r} cannot be soft.")
            pair = soft if isinstance(soft, (tuple, list)) else (soft, soft)
            if len(pair) != 2:
                raise ControlDefinitionError(f"soft must be a weight or (linear, quadratic) weights; got {soft!r}.")
            weights = tuple(finite_number(w, f"soft weight of {name!r}", nonnegative=True) for w in pair)
            if sum(weights) <= 0:
                raise ControlDefinitionError(f"soft weights of {name!r} must not both be 0.")
        self._bounds[name] = (float(lo[0]), float(hi[0]))
        self._soft.pop(name, None)
        if weights is not None:
            self._soft[name] = weights
        return self

    def limit_rate(self, name: str, lower: float | None = None, upper: float | None = None) -> "OCP":
        """Limit the rate of a control, ``lower ≤ Δu/dt ≤ upper`` [unit/s]."""
        check_names([name], self._controls, "limit_rate")
        lo, hi = bound_pair(lower, upper, 1, f"rate limit of {name!r}")
        self._rate_limits[name] = (float(lo[0]), float(hi[0]))
        return self

    def constrain(self, function: Callable | ca.Function, lower: Any = None, upper: Any = None, *,
                  terminal: bool = False, name: str = "constraint") -> "OCP":
        """Add ``lower ≤ g ≤ upper`` with ``g = function(x, u, p)`` per stage (``function(x, p)`` if terminal)."""
        d = self._dyn
        x, u, p = ca.SX.sym("x", d.n_x), ca.SX.sym("u", d.n_u), ca.SX.sym("p", d.n_p)
        args = [x, p] if terminal else [x, u, p]
        n = symbolic_call(function, args, f"constraint {name!r}").numel() if not isinstance(function, ca.Function) \
            else function.numel_out(0)
        lo, hi = bound_pair(lower, upper, n, f"constraint {name!r}")
        self._constraints.append((function, lo, hi, bool(terminal), name))
        return self

    # ---------------------------------------------------------- transcription
    def transcribe(self) -> "Transcription":
        """The discrete :class:`Transcription` (stage functions, bounds, parameter layout)."""
        if not self._terms and not self._costs and not self._rate_weights:
            raise ControlDefinitionError("the OCP has no cost: add track(...), penalize_rates(...) or add_cost(...).")
        return _Builder(self).build()


@dataclass(frozen=True)
class Transcription:
    """An :class:`OCP` in discrete form, and how to fill its parameters.

    Attributes
    ----------
    problem : StageProblem
    controls, disturbances : tuple of str
    references : tuple of str
        Tracked signal names; their references are stage parameters.
    default_references : dict
    rate_controls : tuple of str
        Controls carried as extra states (previous value) for rate terms.
    n_slacks : int
        Slack variables of soft bounds (stage controls after the model's controls).
    discretization : Discretization
    dynamics : Dynamics
    dt : float
    """

    problem: StageProblem
    controls: tuple[str, ...]
    disturbances: tuple[str, ...]
    references: tuple[str, ...]
    default_references: dict
    rate_controls: tuple[str, ...]
    discretization: Discretization
    dynamics: Dynamics
    dt: float
    n_slacks: int = 0

    @property
    def n_controls(self) -> int:
        return len(self.controls)

    def augmented_state(self, x: np.ndarray, u_prev: np.ndarray) -> np.ndarray:
        """The OCP state ``[x; previous values of the rate controls]``."""
        idx = [self.controls.index(n) for n in self.rate_controls]
        return np.concatenate([x, np.asarray(u_prev, dtype=float)[idx]])

    def stage_parameters(self, preview: Mapping[str, Any] | None = None,
                         reference: Mapping[str, Any] | None = None) -> np.ndarray:
        """``(n_d, N+1)`` stage parameters: disturbances then references, each a number or N+1 values."""
        N = self.problem.N
        dist_default = {n: self.dynamics.u0[self.dynamics.inputs.index(n)] for n in self.disturbances}
        rows = [_row(preview, n, dist_default[n], N, "preview") for n in self.disturbances]
        rows += [_row(reference, n, self.default_references[n], N, "reference") for n in self.references]
        for what, given, known in (("preview", preview, self.disturbances), ("reference", reference, self.references)):
            extra = sorted(set(given or {}) - set(known))
            if extra:
                raise ControlDefinitionError(f"{what} names {extra} are unknown; expected names from {list(known)}.")
        return np.array(rows, dtype=float).reshape(len(rows), N + 1)

    def initial_guess(self, x_aug: np.ndarray, u: np.ndarray) -> np.ndarray:
        """``w`` with every state equal to ``x_aug``, every control ``u`` (clipped to bounds)."""
        P = self.problem
        u = np.clip(np.asarray(u, dtype=float), P.lbu[: self.n_controls], P.ubu[: self.n_controls])
        v = self.discretization.initial_v(x_aug[: self.dynamics.n_x])
        ud = np.concatenate([u, np.zeros(self.n_slacks), v])
        X = np.tile(np.asarray(x_aug, dtype=float).reshape(-1, 1), (1, P.N + 1))
        return P.layout.join(X, np.tile(ud.reshape(-1, 1), (1, P.N)))


def _row(values: Mapping[str, Any] | None, name: str, default: float, N: int, what: str) -> np.ndarray:
    v = default if values is None or name not in values else values[name]
    try:
        arr = np.asarray(v, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ControlDefinitionError(f"{what} of {name!r} must be numbers; got {v!r}.") from None
    if arr.size not in (1, N + 1) or not np.all(np.isfinite(arr)):
        raise ControlDefinitionError(f"{what} of {name!r} must be one finite number or {N + 1} (stages 0..N); "
                                     f"got {arr.size} values.")
    return np.broadcast_to(arr, (N + 1,))


class _Builder:
    """Builds the stage Functions of an OCP (one use)."""

    def __init__(self, ocp: OCP) -> None:
        self.o = ocp
        d = ocp.dynamics
        self.sym = ca.SX
        if ocp.discretization.sym is ca.MX or (d.outputs is not None and symbolic_function(d.outputs)[1] is ca.MX):
            self.sym = ca.MX
        self.rate_controls = tuple(n for n in ocp.controls if n in ocp._rate_weights or n in ocp._rate_limits)
        self.soft = tuple(ocp._soft)
        self.references = tuple(dict.fromkeys(n for t in ocp._terms for n in t.names))

    def build(self) -> Transcription:
        o, d, S = self.o, self.o.dynamics, self.sym
        n_c, n_v, n_s = len(o.controls), o.discretization.n_v, len(self.soft)
        nxa = d.n_x + len(self.rate_controls)
        self.xa, self.ud = S.sym("x", nxa), S.sym("u", n_c + n_s + n_v)
        self.d, self.p = S.sym("d", len(o.disturbances) + len(self.references)), S.sym("p", d.n_p)
        x, uc, v = self.xa[: d.n_x], self.ud[:n_c], self.ud[n_c + n_s:]
        self.slack = self.ud[n_c:n_c + n_s]
        self.u_full = self._full_input(uc, self.d[: len(o.disturbances)])
        self.y = d.outputs(x, self.u_full, self.p) if d.outputs is not None else S(0, 1)
        u_nominal = ca.DM(d.u0[[d.inputs.index(n) for n in o.controls]]) if n_c else S(0, 1)
        u_term = self._full_input(u_nominal, self.d[: len(o.disturbances)])     # terminal: no control symbols
        self.y_term = d.outputs(x, u_term, self.p) if d.outputs is not None else S(0, 1)
        up = self.xa[d.n_x:]
        rate = {n: (uc[o.controls.index(n)] - up[i]) / o.dt for i, n in enumerate(self.rate_controls)}
        f = ca.vertcat(o.discretization.step(x, v, self.u_full, self.p), *[uc[o.controls.index(n)]
                                                                         for n in self.rate_controls])
        c, lc, uc_, c_names = self._path_constraints(x, v, rate)
        r = self._residual(terminal=False, rate=rate)
        l_ = self._general_cost(terminal=False)
        path = ca.Function("ocp_stage", [self.xa, self.ud, self.d, self.p], [f, c, r, l_],
                           ["x", "u", "d", "p"], ["f", "c", "r", "l"])
        cN, lcN, ucN = self._terminal_constraints(x)
        term = ca.Function("ocp_terminal", [self.xa, self.d, self.p],
                           [cN, self._residual(terminal=True, rate={}), self._general_cost(terminal=True)],
                           ["x", "d", "p"], ["c", "r", "l"])
        c0 = np.array([ca.depends_on(c[i], self.ud) for i in range(c.numel())], dtype=bool)
        dyn_jac = self._dynamics_jacobian() if o.discretization.sensitivity is not None else None
        problem = StageProblem(
            N=o.horizon, path=path, terminal=term, initial=None,
            lbx=np.concatenate([self._bound_vec(d.states, "x"), np.full(len(self.rate_controls), -np.inf)]),
            ubx=np.concatenate([self._bound_vec(d.states, "x", upper=True), np.full(len(self.rate_controls), np.inf)]),
            lbu=np.concatenate([self._bound_vec(o.controls, "u"), np.zeros(n_s), np.full(n_v, -np.inf)]),
            ubu=np.concatenate([self._bound_vec(o.controls, "u", upper=True), np.full(n_s, np.inf),
                                np.full(n_v, np.inf)]),
            lbc=lc, ubc=uc_, c0_rows=c0, lbcN=lcN, ubcN=ucN,
            names={"x": list(d.states) + [f"{n}_prev" for n in self.rate_controls],
                   "u": list(o.controls) + [f"slack:{n}" for n in self.soft]
                   + [f"collocation_{i}" for i in range(n_v)],
                   "d": list(o.disturbances) + [f"ref:{n}" for n in self.references], "p": list(d.parameters),
                   "c": c_names}, dynamics_jacobian=dyn_jac)
        return Transcription(problem, o.controls, o.disturbances, self.references,
                             {n: o._references.get(n, 0.0) for n in self.references}, self.rate_controls,
                             o.discretization, d, o.dt, n_s)

    def _dynamics_jacobian(self) -> ca.Function:
        """``(x, u, d, p) -> (f, ∂f/∂[x; u])`` from the chained RK4 sensitivities (MX glue, no expansion)."""
        o, d = self.o, self.o.dynamics
        n_c, nxa, nud = len(o.controls), self.xa.numel(), self.ud.numel()
        xa, ud, dd, p = (ca.MX.sym(s, n) for s, n in (("x", nxa), ("u", nud), ("d", self.d.numel()),
                                                       ("p", d.n_p)))
        uc = ud[:n_c]
        dist = dd[: len(o.disturbances)]
        u_full = ca.vertcat(*[uc[o.controls.index(n)] if n in o.controls else dist[o.disturbances.index(n)]
                              for n in d.inputs]) if d.n_u else ca.MX(0, 1)
        x_next, Sx, Su = o.discretization.sensitivity(xa[: d.n_x], u_full, p)
        ctrl_cols = ca.horzcat(*[Su[:, d.inputs.index(n)] for n in o.controls]) if n_c else ca.MX(d.n_x, 0)
        top = ca.horzcat(Sx, ca.MX(d.n_x, nxa - d.n_x), ctrl_cols, ca.MX(d.n_x, nud - n_c))
        rows = [top]
        for n in self.rate_controls:              # u_prev⁺ = u
            e = ca.DM.zeros(1, nxa + nud)
            e[0, nxa + o.controls.index(n)] = 1.0
            rows.append(ca.MX(e))
        f = ca.vertcat(x_next, *[uc[o.controls.index(n)] for n in self.rate_controls])
        return ca.Function("ocp_dynamics_jacobian", [xa, ud, dd, p], [f, ca.densify(ca.vertcat(*rows))],
                           ["x", "u", "d", "p"], ["f", "J"])

    def _full_input(self, uc, dist):
        o, d = self.o, self.o.dynamics
        parts = [uc[o.controls.index(n)] if n in o.controls else dist[o.disturbances.index(n)] for n in d.inputs]
        return ca.vertcat(*parts) if parts else self.sym(0, 1)

    def _signal(self, name: str, terminal: bool = False):
        kind, i = self.o._resolve(name)
        if kind == "x":
            return self.xa[i]
        if kind == "u":
            return self.u_full[i]
        return self.y_term[i] if terminal else self.y[i]

    def _residual(self, *, terminal: bool, rate: Mapping[str, Any]):
        parts = []
        for t in self.o._terms:
            if t.terminal != terminal:
                continue
            dev = ca.vertcat(*[self._signal(n, terminal) - self.d[len(self.o.disturbances) + self.references.index(n)]
                               for n in t.names])
            parts.append(ca.mtimes(ca.DM(t.root), dev))
        for n, w in self.o._rate_weights.items():
            if not terminal:
                parts.append(np.sqrt(w) * rate[n])
        if not terminal:
            parts += [np.sqrt(self.o._soft[n][1]) * self.slack[i] for i, n in enumerate(self.soft)
                      if self.o._soft[n][1] > 0]
        return ca.vertcat(*parts) if parts else self.sym(0, 1)

    def _general_cost(self, *, terminal: bool):
        x = self.xa[: self.o.dynamics.n_x]
        total = self.sym.zeros(1, 1)
        for stage, term in self.o._costs:
            fn = term if terminal else stage
            if fn is not None:
                args = [x, self.p] if terminal else [x, self.u_full, self.p]
                total = total + symbolic_call(fn, args, "terminal cost" if terminal else "stage cost", 1)
        if not terminal:
            for i, n in enumerate(self.soft):
                total = total + self.o._soft[n][0] * self.slack[i]
        return total

    def _bound_vec(self, names: Sequence[str], kind: str, upper: bool = False) -> np.ndarray:
        out = np.full(len(names), np.inf if upper else -np.inf)
        for key, (lo, hi) in self.o._bounds.items():
            k, i = self.o._resolve(key)
            if k == kind and key not in self.o._soft:
                j = list(names).index(self.o.dynamics.inputs[i] if k == "u" else self.o.dynamics.states[i])
                out[j] = hi if upper else lo
        return out

    def _path_constraints(self, x, v, rate):
        o = self.o
        rows, lo, hi, names = [], [], [], []
        if o.discretization.n_v:
            G = o.discretization.equations(x, v, self.u_full, self.p)
            rows.append(G)
            lo.append(np.zeros(G.numel()))
            hi.append(np.zeros(G.numel()))
            names += [f"collocation_{i}" for i in range(G.numel())]
        for key, (l_, h_) in o._bounds.items():
            if o._resolve(key)[0] == "y" and key not in o._soft:
                rows.append(self._signal(key))
                lo.append([l_])
                hi.append([h_])
                names.append(key)
        for i, key in enumerate(self.soft):
            l_, h_ = o._bounds[key]
            s = self._signal(key)
            for value, (lo_, hi_), tag in ((s + self.slack[i], (l_, np.inf), "lower"),
                                           (s - self.slack[i], (-np.inf, h_), "upper")):
                if np.isfinite(lo_) or np.isfinite(hi_):
                    rows.append(value)
                    lo.append([lo_])
                    hi.append([hi_])
                    names.append(f"soft {tag}:{key}")
        for n, (l_, h_) in o._rate_limits.items():
            rows.append(rate[n])
            lo.append([l_])
            hi.append([h_])
            names.append(f"rate:{n}")
        for fn, l_, h_, terminal, name in o._constraints:
            if not terminal:
                g = symbolic_call(fn, [x, self.u_full, self.p], f"constraint {name!r}", len(l_))
                rows.append(g)
                lo.append(l_)
                hi.append(h_)
                names += [name] * len(l_)
        return self._stack(rows, lo, hi) + (names,)

    def _terminal_constraints(self, x):
        o = self.o
        rows, lo, hi = [], [], []
        for key, (l_, h_) in o._bounds.items():
            kind, i = o._resolve(key)
            if kind == "y" and key not in o._soft and not o._output_uses_controls(i):
                rows.append(self._signal(key, terminal=True))
                lo.append([l_])
                hi.append([h_])
        for fn, l_, h_, terminal, name in o._constraints:
            if terminal:
                rows.append(symbolic_call(fn, [x, self.p], f"constraint {name!r}", len(l_)))
                lo.append(l_)
                hi.append(h_)
        return self._stack(rows, lo, hi)

    def _stack(self, rows, lo, hi):
        if not rows:
            return self.sym(0, 1), np.zeros(0), np.zeros(0)
        return ca.vertcat(*rows), np.concatenate([np.ravel(a) for a in lo]), np.concatenate([np.ravel(a) for a in hi])
