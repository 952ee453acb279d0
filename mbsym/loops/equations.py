"""ClosedLoopEquations: the equations of a system with closed loops, in its independent coordinates.

:func:`closed_equations` (called by :meth:`mbsym.System.equations` when the System has closures)
derives the tree with every coordinate (:func:`mbsym.kane.derive`), builds the constraint rows
(:mod:`mbsym.constraints`), assembles the loop at the guess (:mod:`.assembly`) and reduces the
equations to the independent speeds (:mod:`.reduce`). The result is an
:class:`~mbsym.equations.EquationsOfMotion` whose coordinates are the independent ones — so
simulation (every method), linearization, modal analysis, control, identification and export
take it as any other — plus the model-protocol hooks that give the dependent coordinates and
speeds, the reactions of the cut joints and the closure residual as output channels.

Drift policy: there is none to correct. The state holds the independent coordinates only; the
dependent ones are recomputed from them at every evaluation (projection onto ``g = 0`` by Newton
steps in the graph), so the constraint holds to the solver's convergence (the channel
``closure_residual``) however long the run.
"""

from __future__ import annotations

import warnings
from typing import Mapping, Sequence

import casadi as ca
import numpy as np

from ..constraints import constraint_rows
from ..equations import SYMBOLIC_SOLVE_MAX_DOF, EquationsOfMotion
from ..exceptions import ConstraintError, ExportError, ModelWarning, OptionError, UnsupportedFeatureError
from ..kane import Derivation, derive
from .assembly import assemble, check_redundant, choose, guess_vector, turn_series
from .reduce import Reduction, periodic_coordinates, reduce_equations

__all__ = ["ClosedLoopEquations", "closed_equations"]


def closed_equations(system, independent: Sequence[str] | None, guess: Mapping[str, float] | None, *,
                     name: str = "mbsym", stages: int | None = None, newton_steps: int = 3,
                     references: int = 64) -> "ClosedLoopEquations":
    """Equations of a system with closed loops in its independent coordinates.

    Parameters
    ----------
    system : mbsym.System
        A validated system with closures (:meth:`~mbsym.System.add_closure`,
        :meth:`~mbsym.System.add_constraint`).
    independent : sequence of str
        Independent coordinates, one per degree of freedom.
    guess : dict
        Coordinate values near the wanted assembly (missing ones 0); the independent values in
        it are where the loop is assembled (the reference of the dependent-coordinate solver).
        When the closures use parameters without default values the loop cannot be assembled
        numerically: a ModelWarning says so and every evaluation assembles it from the guess
        (6 more Newton steps), without the rank checks.
    name : str
    stages : int, optional
        Continuation stages from the assembled configuration (default 2; more for loops whose
        dependent coordinates swing far over the range of the independent ones). Given
        explicitly, the continuation is used even for a crank (no Fourier series).
    newton_steps : int, optional
        Newton corrections per stage after the tangent predictor (default 3; the last stage takes
        two more).
    references : int, optional
        One independent coordinate that turns fully (a crank): the number of configurations per
        turn assembled in advance (default 64, even; 0: none); a Fourier series fitted to them
        predicts the dependent coordinates and ``newton_steps`` Newton steps correct them (no
        path to follow). The path from the assembly serves when the coordinate cannot turn.

    Raises
    ------
    ConstraintError
        Bad ``independent``/``guess``, redundant or inconsistent constraints at the assembly.
    UnsupportedFeatureError
        Prescribed or locked coordinates in a system with closures.
    OptionError
        Non-positive ``stages`` or ``newton_steps``.
    """
    explicit_stages = stages is not None
    stages = 2 if stages is None else stages
    for v, what in ((stages, "stages"), (newton_steps, "newton_steps"), (references, "references")):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < (0 if what == "references" else 1) \
                or (what == "references" and (v % 2 or v == 2)):
            raise OptionError(f"{what}={v!r} must be a positive integer (references: 0 or an even number >= 4; "
                              "the dependent-coordinate solver takes stages x newton_steps Newton steps).")
    st = system.symbols
    if st.prescribed() or st.locked():
        raise UnsupportedFeatureError(
            f"closed loops with prescribed {list(st.prescribed())} or locked {list(st.locked())} coordinates are "
            "not modelled (the constraints would move with the inputs); make them coordinates and close the loop "
            "with a closure.")
    d = derive(system)
    coords = list(d.names["coordinate"])
    g, g_dot, row_names = constraint_rows(system.constraints, d.kinematics)
    if not system.constraints:
        choose(coords, 0, [], independent, guess)            # raises: no closure
    G = ca.jacobian(g, d.q)
    g_fn = ca.Function("closure", [d.q, d.p], [g, ca.densify(G)])
    p_ref, missing = _reference_parameters(d, ca.symvar(g))
    q0 = guess_vector(coords, guess)
    generic = q0 + np.random.default_rng(0).uniform(-0.5, 0.5, q0.size)    # structural redundancy, anywhere
    check_redundant(np.array(g_fn(generic, p_ref)[1]), row_names, where="at any configuration")
    choice = choose(coords, g.numel(), row_names, independent, guess)
    refs, assembly_steps = None, 0
    if missing:                                     # no numbers to assemble with: assemble in the graph
        warnings.warn(f"the closures depend on parameters {missing} that have no default value: the loop cannot be "
                      "assembled (nor checked) now, so every evaluation first assembles it from the guess by Newton "
                      "steps (watch the output closure_residual). Give defaults (sys.parameters(..., values=...)) "
                      "for the checks and a cheaper graph.", ModelWarning, stacklevel=3)
        q_ref, assembly_steps = q0, 6
    else:
        q_ref = assemble(g_fn, choice, p_ref, coords, row_names)
    periodic = periodic_coordinates(ca.Function("g", [d.q, d.p], [g]), q_ref, p_ref, choice.independent)
    if references and not explicit_stages and not missing and len(choice.independent) == 1 and periodic[0]:
        refs = turn_series(g_fn, q_ref, choice.independent[0], choice.dependent, p_ref, samples=references)
    red = reduce_equations(d, g, g_dot, choice.independent, choice.dependent, q_ref, periodic, stages, newton_steps,
                           references=refs, assembly_steps=assembly_steps)
    units = system.coordinate_units()
    return ClosedLoopEquations(d, red, choice, q_ref, row_names, name=name, units=units)


def _reference_parameters(d: Derivation, used: list) -> tuple[np.ndarray, list[str]]:
    """Default parameter values for the assembly (1.0 where none), and the constraint parameters without one."""
    names = d.names["parameter"]
    keys = {s.element_hash() for s in used}
    missing = [n for i, n in enumerate(names) if n not in d.defaults and d.p[i].element_hash() in keys]
    return np.array([d.defaults.get(n, 1.0) for n in names], dtype=float), missing


class ClosedLoopEquations(EquationsOfMotion):
    """Equations ``M_r(q_i) q̈_i = F_r(q_i, q̇_i, u, p)`` of a closed-loop system (module docstring).

    Everything of :class:`~mbsym.equations.EquationsOfMotion` refers to the independent
    coordinates (``coordinates``, ``states = [q_i; q̇_i]``, ``mass_matrix``, ``rhs``, …). Further:
    ``dependent`` (names), ``constraint_names`` (reaction channels), ``reference`` (the assembled
    configuration), :meth:`configuration` and :meth:`constraint_forces`, and the hooks
    ``output_function()`` / ``output_names`` / ``output_units`` / ``default_state()`` that
    :func:`mbsym.simulate` reads: outputs are the dependent coordinates, their speeds (``<q>_d``),
    the reactions and ``closure_residual``.
    """

    def __init__(self, full: Derivation, red: Reduction, choice, q_ref: np.ndarray, row_names: Sequence[str], *,
                 name: str, units: Mapping[str, str]) -> None:
        ind, dep = list(choice.independent), list(choice.dependent)
        coords = list(full.names["coordinate"])
        names = dict(full.names)
        names["coordinate"] = [coords[i] for i in ind]
        names["locked"] = []
        reduced = Derivation(full.q[ind], full.qd[ind], full.qdd[ind], full.u, full.p, names, dict(full.defaults),
                             red.M, red.F, red.T, red.V, red.power, {}, dict(full.bodies), None, (), None)
        super().__init__(reduced, name=name, units=units)
        self._full, self._red = full, red
        self._ind, self._dep = tuple(ind), tuple(dep)
        self._all = tuple(coords)
        self._dep_names = tuple(coords[i] for i in dep)
        self._rows = tuple(row_names)
        self._q_ref = q_ref.copy()
        self._units_all = dict(units)
        self._outputs = self._output_function()

    # ------------------------------------------------------------ description
    @property
    def dependent(self) -> tuple[str, ...]:
        """Names of the dependent coordinates (solved from the constraints)."""
        return self._dep_names

    @property
    def all_coordinates(self) -> tuple[str, ...]:
        """Every coordinate of the tree, in declaration order."""
        return self._all

    @property
    def constraint_names(self) -> tuple[str, ...]:
        """One name per constraint row: the reaction channels (``<closure>_F<axis>``, ``<name>_lambda``)."""
        return self._rows

    @property
    def reference(self) -> dict[str, float]:
        """The assembled configuration (every coordinate by name) at the default parameters."""
        return {n: float(v) for n, v in zip(self._all, self._q_ref)}

    def __repr__(self) -> str:
        return (f"ClosedLoopEquations({self.name!r}, independent={list(self.coordinates)}, "
                f"dependent={list(self._dep_names)}, constraints={list(self._rows)}, n_u={self.n_u}, n_p={self.n_p})")

    # ------------------------------------------------------------ hooks (model protocol)
    @property
    def output_names(self) -> tuple[str, ...]:
        return self._dep_names + tuple(f"{n}_d" for n in self._dep_names) + self._rows + ("closure_residual",)

    @property
    def output_units(self) -> tuple[str, ...]:
        u = [self._units_all.get(n, "-") for n in self._dep_names]
        return (tuple(u) + tuple(f"{v}/s" if v != "-" else "-" for v in u)
                + tuple("N" if "_F" in r else "-" for r in self._rows) + ("-",))

    def output_function(self) -> ca.Function:
        """``(x, u, p) -> y``: dependent coordinates, their speeds, reactions, closure residual."""
        return self._outputs

    def default_state(self) -> np.ndarray:
        """The assembled independent coordinates, at rest."""
        return np.concatenate([self._q_ref[list(self._ind)], np.zeros(self.n_q)])

    def _output_function(self) -> ca.Function:
        d, red = self._derivation, self._red
        x = ca.vertcat(d.q, d.qd)
        y = ca.vertcat(red.q_dep, red.qd_dep, red.lam, red.residual)         # λ depends on q̈_i
        name = f"{self.name}_loop_outputs"
        if self.n_q <= SYMBOLIC_SOLVE_MAX_DOF:
            y = ca.substitute(y, d.qdd, ca.solve(red.M, red.F))
            return ca.Function(name, [x, d.u, d.p], [y], ["x", "u", "p"], ["y"], {"cse": True})
        at = ca.Function(f"{name}_at", [x, d.u, d.p, d.qdd], [y], {"cse": True})
        X, U, P = ca.MX.sym("x", x.numel()), ca.MX.sym("u", d.u.numel()), ca.MX.sym("p", d.p.numel())
        n = self.n_q
        M = self.functions.mass_matrix(X[:n], P)
        qdd = ca.solve(M, self.functions.forcing(X[:n], X[n:], U, P), "qr")    # numeric beyond 8 DOF
        return ca.Function(name, [X, U, P], [at(X, U, P, qdd)], ["x", "u", "p"], ["y"])

    # ------------------------------------------------------------ numeric
    def configuration(self, q, p: Mapping[str, float] | None = None) -> np.ndarray:
        """Every coordinate (order of :attr:`all_coordinates`) at independent coordinates ``q``."""
        qq = self._vec(q, self.n_q, "q", self.coordinates)
        f = ca.Function("configuration", [self._derivation.q, self._derivation.p], [self._red.q_dep])
        out = np.zeros(len(self._all))
        out[list(self._ind)] = qq
        out[list(self._dep)] = np.array(f(qq, self.parameter_vector(p))).reshape(-1)
        return out

    def constraint_forces(self, q, qd, u=None, p: Mapping[str, float] | None = None) -> np.ndarray:
        """Reactions of the cut joints (order of :attr:`constraint_names`) [N for point closures]."""
        x = np.concatenate([self._vec(q, self.n_q, "q", self.coordinates), self._vec(qd, self.n_q, "qd", self.speeds)])
        uu, pp = self._args(u, p)
        y = np.array(self._outputs(x, uu, pp)).reshape(-1)
        m = len(self._dep)
        return y[2 * m: 2 * m + len(self._rows)]

    def point_kinematics(self, body: str, point=(0.0, 0.0, 0.0)) -> ca.Function:
        """Kinematics of a material point, ``(q, qd, qdd, u, p) -> (r, R, v, w, a, wd)`` in the independent
        coordinates (see :meth:`EquationsOfMotion.point_kinematics`)."""
        from ..kinematics import as_vector3

        full, red, d = self._full, self._red, self._derivation
        if body not in full.bodies:
            raise ConstraintError(f"no body named {body!r}; bodies are {list(full.bodies)}.")
        kin = full.kinematics
        b = full.bodies[body]
        r, v = kin.point_velocity(b, as_vector3(point, "point"))
        x, xd = ca.vertcat(kin.q_all, kin.qd_all), ca.vertcat(kin.qd_all, full.qdd)
        a = kin.rate(v, x, xd)
        wd = kin.rate(kin.frame(b).w, x, xd)
        frame = full.frames[body]
        exprs = kin.resolve([r, frame.R, v, frame.w, a, wd])
        qdd_full = red.C @ d.qdd + red.c0
        exprs = ca.substitute(exprs, [full.qdd, full.qd], [qdd_full, red.C @ d.qd])
        exprs = ca.substitute(exprs, [full.q[list(self._dep)]], [red.q_dep])
        return ca.Function(f"{self.name}_{body}_kinematics", [d.q, d.qd, d.qdd, d.u, d.p], exprs,
                           ["q", "qd", "qdd", "u", "p"], ["r", "R", "v", "w", "a", "wd"], {"cse": True})

    def latex(self, **options) -> str:
        """Refused: the reduced equations hold the dependent-coordinate solver (Newton steps)."""
        raise ExportError("a closed-loop model has no LaTeX form: its equations contain the Newton steps that solve "
                          "the dependent coordinates. Export it as C or Python (export_c, export_python) instead.")
