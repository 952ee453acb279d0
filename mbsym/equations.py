"""EquationsOfMotion: the CasADi Functions every use of mbsym consumes.

Built once from a :class:`~mbsym.kane.Derivation`; immutable afterwards. The
CasADi Functions (``eom.functions``) take every argument as a vector:
``q (n_q)``, ``qd (n_q)``, ``qdd (n_q)``, ``u (n_u)``, ``p (n_p)``, ``x = [q; qd]``.
The numeric methods of the same names accept plain sequences, take parameters
as a dict by name (defaults fill the gaps) and return numpy arrays.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

import casadi as ca
import numpy as np

from .bodies.rigid import RigidBody
from .exceptions import (
    DimensionError, ModelDefinitionError, ParameterError, SolverError,
)
from .kane import Derivation
from .mass_properties import MassPropertyCheck, check_nonsingular, indefinite_problem  # noqa: F401 (re-exported)
from .spd_solve import spd_solve
from .symbols import check_finite_number

__all__ = ["EquationsOfMotion", "EomFunctions"]

#: Beyond this many coordinates the first-order rhs solves M qdd = F numerically.
SYMBOLIC_SOLVE_MAX_DOF = 8


@dataclass(frozen=True)
class EomFunctions:
    """The CasADi Functions of a model.

    Their expressions come from one common-subexpression elimination
    (``casadi.cse``) over M, F and the energies, done once per model.

    Attributes
    ----------
    mass_matrix : (q, p) -> M, or (q, u, p) -> M when the system has prescribed
        coordinates (their values are inputs and may move mass)
    forcing : (q, qd, u, p) -> F
    residual : (q, qd, qdd, u, p) -> e = F - M qdd
    rhs : (x, u, p) -> xd = [qd; M^-1 F]
    kinetic_energy : (q, qd, u, p) -> T [J]
    potential_energy : (q, u, p) -> V [J] (gravity and springs)

    ``u`` enters the energies only through prescribed coordinates.
    power : (q, qd, u, p) -> power of the non-conservative loads [W]
    reactions : (q, qd, qdd, u, p) -> λ, the reaction generalized forces of the locked
        coordinates (:meth:`mbsym.System.locked`) [N or N m]: what the support exerts to
        hold each at zero; None without locked coordinates
    """

    mass_matrix: ca.Function
    forcing: ca.Function
    residual: ca.Function
    rhs: ca.Function
    kinetic_energy: ca.Function
    potential_energy: ca.Function
    power: ca.Function
    reactions: ca.Function | None = None


class EquationsOfMotion:
    """Equations of motion ``M(q, p) qdd = F(q, qd, u, p)`` of a system.

    Obtain one with :meth:`mbsym.System.equations`. Attributes ``n_q``,
    ``n_u``, ``n_p``, ``n_x`` and the name lists ``coordinates``, ``speeds``,
    ``inputs``, ``parameters``, ``states`` describe the vectors.

    Examples
    --------
    >>> import mbsym as mb
    >>> sys = mb.System(gravity=[0, 0, -9.81])
    >>> th = sys.coordinates("th")
    >>> sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[0, 0, -1]),
    ...                           axis=[0, 1, 0], coordinate=th))
    >>> eom = sys.equations()
    >>> eom.mass_matrix([0.0])
    array([[1.]])
    """

    def __init__(self, d: Derivation, *, name: str = "mbsym", units: Mapping[str, str] | None = None) -> None:
        self._name = name
        self._units = {c: (units or {}).get(c, "-") for c in d.names["coordinate"]}
        self._coordinates = tuple(d.names["coordinate"])
        self._inputs = tuple(d.names["input"])
        self._parameters = tuple(d.names["parameter"])
        self._defaults = MappingProxyType(dict(d.defaults))
        self._derivation = d
        self._functions = _build_functions(d, name)
        rigid = [b for b in d.bodies.values() if isinstance(b, RigidBody)]
        self._mass_check = MassPropertyCheck(rigid, d.p, self._parameters)

    # ------------------------------------------------------------ description
    @property
    def name(self) -> str:
        return self._name

    @property
    def n_q(self) -> int:
        """Number of generalized coordinates."""
        return len(self._coordinates)

    @property
    def n_x(self) -> int:
        """Number of first-order states, ``2 n_q``."""
        return 2 * self.n_q

    @property
    def n_u(self) -> int:
        """Number of inputs."""
        return len(self._inputs)

    @property
    def n_p(self) -> int:
        """Number of parameters."""
        return len(self._parameters)

    @property
    def coordinates(self) -> tuple[str, ...]:
        return self._coordinates

    @property
    def speeds(self) -> tuple[str, ...]:
        return tuple(f"{c}_d" for c in self._coordinates)

    @property
    def states(self) -> tuple[str, ...]:
        """Names of ``x = [q; qd]``."""
        return self._coordinates + self.speeds

    @property
    def units(self) -> dict[str, str]:
        """Unit of each state by name: coordinates ``"m"`` or ``"rad"`` (``"-"`` if unknown), speeds per s."""
        out = dict(self._units)
        out.update({f"{c}_d": (f"{u}/s" if u != "-" else "-") for c, u in self._units.items()})
        return out

    @property
    def inputs(self) -> tuple[str, ...]:
        return self._inputs

    @property
    def parameters(self) -> tuple[str, ...]:
        return self._parameters

    @property
    def defaults(self) -> Mapping[str, float]:
        """Default parameter values (read-only)."""
        return self._defaults

    @property
    def functions(self) -> EomFunctions:
        """The CasADi Functions (vector arguments, see :class:`EomFunctions`)."""
        return self._functions

    @property
    def symbolic(self) -> Derivation:
        """The symbolic derivation (SX expressions of q, qd, qdd, u, p). Do not modify."""
        return self._derivation

    def __repr__(self) -> str:
        return (f"EquationsOfMotion({self._name!r}, n_q={self.n_q}, n_u={self.n_u}, n_p={self.n_p}, "
                f"coordinates={list(self._coordinates)})")

    def linearize(self, q0=None, qd0=None, u0=None, p=None, **options):
        """Linearized model at an operating point: see :func:`mbsym.linearize`."""
        from .linear import linearize

        return linearize(self, q0, qd0, u0, p, **options)

    def point_kinematics(self, body: str, point=(0.0, 0.0, 0.0)) -> ca.Function:
        """Kinematics of a material point of a body, as a CasADi Function.

        Parameters
        ----------
        body : str
            Body name.
        point : sequence of 3, optional
            Undeflected position in body coordinates [m] (root or end for
            flexible bodies); default the body origin.

        Returns
        -------
        casadi.Function
            ``(q, qd, qdd, u, p) -> (r, R, v, w, a, wd)``: position [m], orientation
            (body -> ground), velocity [m/s], angular velocity [rad/s],
            acceleration [m/s^2] and angular acceleration [rad/s^2], ground axes.
        """
        from .kinematics import as_vector3

        d = self._derivation
        if body not in d.bodies:
            raise ModelDefinitionError(f"no body named {body!r}; bodies are {list(d.bodies)}.")
        b = d.bodies[body]
        pt = as_vector3(point, "point")
        kin = d.kinematics
        r, v = kin.point_velocity(b, pt)
        frame = d.frames[body]
        # time derivative along (q, qd) and the prescribed (value, speed, acceleration) inputs
        presc = [self._derivation.u[self._inputs.index(f"{n}{sfx}")] for n in d.prescribed for sfx in ("_d", "_dd")]
        qdd_p = ca.vertcat(*presc[1::2]) if presc else ca.SX(0, 1)
        n_locked = len(d.names.get("locked", ()))
        x = ca.vertcat(kin.q_all, kin.qd_all)
        xd = ca.vertcat(kin.qd_all, d.qdd, qdd_p, ca.SX.zeros(n_locked))   # locked coordinates never move
        a = kin.rate(v, x, xd)
        wd = kin.rate(kin.frame(b).w, x, xd)
        r, v, a, wd = kin.resolve([r, v, a, wd])
        if n_locked:                                        # held at zero, as in the equations
            lz = ca.vertcat(kin.q_all[-n_locked:], kin.qd_all[-n_locked:])
            r, v, a, wd = ca.substitute([r, v, a, wd], [lz], [ca.SX.zeros(2 * n_locked)])
        return ca.Function(f"{self._name}_{body}_kinematics", [d.q, d.qd, d.qdd, d.u, d.p],
                           [r, frame.R, v, frame.w, a, wd], ["q", "qd", "qdd", "u", "p"],
                           ["r", "R", "v", "w", "a", "wd"], {"cse": True})

    # ------------------------------------------------------------ export
    def export_c(self, directory, **options):
        """Write the model's functions as standalone C with a minimal ``main.c``.

        See :func:`mbsym.export.export_c` (options: ``name``, ``functions``, ``main``).
        """
        from .export import export_c

        return export_c(self, directory, **options)

    def export_python(self, path, **options):
        """Write the model's functions as a numpy-only Python module called like :attr:`functions`.

        See :func:`mbsym.export.export_python` (option: ``functions``).
        """
        from .export import export_python

        return export_python(self, path, **options)

    def latex(self, **options) -> str:
        """The mass matrix and forcing of a small model in LaTeX, with the model's symbol names.

        See :func:`mbsym.export.latex` (options: ``form``, ``digits``, ``max_terms``).
        """
        from .export import latex

        return latex(self, **options)

    # ------------------------------------------------------------ numeric
    def parameter_vector(self, p: Mapping[str, float] | None = None) -> np.ndarray:
        """Parameter values as a vector in the order of :attr:`parameters`.

        Raises
        ------
        ParameterError
            If a name is unknown, a value is missing (no default) or not finite.
        MassPropertyError
            If the values give a rigid body a negative mass or an unphysical inertia
            (:mod:`mbsym.mass_properties`).
        """
        p = {} if p is None else p
        if not isinstance(p, Mapping):
            raise ParameterError(
                f"parameters must be a dict by name (e.g. {{'m1': 2.0}}); got {type(p).__name__}. "
                f"Names: {list(self._parameters)}."
            )
        unknown = sorted(set(p) - set(self._parameters))
        if unknown:
            raise ParameterError(f"unknown parameters {unknown}; this model's parameters are {list(self._parameters)}.")
        missing = [n for n in self._parameters if n not in p and n not in self._defaults]
        if missing:
            raise ParameterError(
                f"missing values for parameters {missing} (they have no default); pass them in p, "
                f"e.g. p={{{', '.join(repr(n) + ': ...' for n in missing)}}}."
            )
        vec = np.array([check_finite_number(p[n] if n in p else self._defaults[n], f"parameter {n!r}")
                        for n in self._parameters], dtype=float)
        self._mass_check(vec)       # unphysical mass properties (e.g. a negative mass) -> MassPropertyError
        return vec

    def _vec(self, value, n: int, what: str, names) -> np.ndarray:
        if isinstance(value, Mapping):
            raise DimensionError(f"{what} must be an array of {n} numbers in order {list(names)}; got a dict.")
        try:
            arr = np.array(value, dtype=float).reshape(-1)      # a copy: never alias the caller's array
        except (TypeError, ValueError) as exc:
            raise DimensionError(f"{what} must be {n} numbers in order {list(names)}; got {value!r}.") from exc
        if arr.size != n:
            raise DimensionError(f"{what} has {arr.size} entries; expected {n} in order {list(names)}.")
        if not np.all(np.isfinite(arr)):
            bad = [names[i] for i in np.flatnonzero(~np.isfinite(arr))]
            raise DimensionError(f"{what} has non-finite entries for {bad}; all entries must be finite.")
        return arr

    def _args(self, u, p):
        """Resolve the optional (u, p) pair; a dict in the u slot means p when n_u == 0."""
        if isinstance(u, Mapping) and p is None and self.n_u == 0:
            u, p = None, u
        if u is None and self.n_u:
            raise DimensionError(f"this model has inputs {list(self._inputs)}; pass u (n_u={self.n_u} values).")
        return self._input_vector(u), self.parameter_vector(p)

    def _input_vector(self, u) -> np.ndarray:
        """Inputs as a vector: None (no inputs), a sequence, or a dict by name."""
        if u is None:
            return np.zeros(self.n_u)
        if isinstance(u, Mapping):
            unknown = sorted(set(u) - set(self._inputs))
            missing = [n for n in self._inputs if n not in u]
            if unknown or missing:
                raise DimensionError(f"input dict: unknown {unknown}, missing {missing}; inputs are {list(self._inputs)}.")
            return self._vec([u[n] for n in self._inputs], self.n_u, "u", self._inputs)
        return self._vec(u, self.n_u, "u", self._inputs)

    @property
    def locked(self) -> tuple[str, ...]:
        """Names of the locked coordinates, in the order of :meth:`reactions`."""
        return tuple(self._derivation.names.get("locked", ()))

    def reactions(self, q, qd, qdd, u=None, p: Mapping[str, float] | None = None) -> np.ndarray:
        """Reaction generalized forces of the locked coordinates [N or N m] (see :class:`EomFunctions`).

        Raises
        ------
        ModelDefinitionError
            If the system has no locked coordinates.
        """
        f = self._functions.reactions
        if f is None:
            raise ModelDefinitionError("this model has no locked coordinates; declare them with sys.locked(...) "
                                       "and use them in joints to get reactions.")
        qq = self._vec(q, self.n_q, "q", self._coordinates)
        vv = self._vec(qd, self.n_q, "qd", self.speeds)
        aa = self._vec(qdd, self.n_q, "qdd", self._coordinates)
        uu, pp = self._args(u, p)
        return np.array(f(qq, vv, aa, uu, pp)).reshape(-1)

    @property
    def prescribed(self) -> tuple[str, ...]:
        """Names of the prescribed coordinates (their value, speed, acceleration are inputs)."""
        return tuple(self._derivation.prescribed)

    def mass_matrix(self, q, p: Mapping[str, float] | None = None, *, u=None) -> np.ndarray:
        """Mass matrix ``M(q, p)`` [kg, kg m, kg m^2], shape (n_q, n_q).

        ``u`` (keyword) is needed only when the system has prescribed coordinates.
        """
        qq = self._vec(q, self.n_q, "q", self._coordinates)
        return self._mass(qq, self._energy_inputs(u), self.parameter_vector(p))

    def _mass(self, q: np.ndarray, u: np.ndarray, p: np.ndarray) -> np.ndarray:
        """Evaluate the mass-matrix Function whatever its signature."""
        f = self._functions.mass_matrix
        return np.array(f(q, u, p) if self._derivation.prescribed else f(q, p))

    def forcing(self, q, qd, u=None, p: Mapping[str, float] | None = None) -> np.ndarray:
        """Forcing ``F(q, qd, u, p)`` [N, N m], shape (n_q,).

        With no inputs declared, the third positional argument may be ``p``.
        """
        qq = self._vec(q, self.n_q, "q", self._coordinates)
        vv = self._vec(qd, self.n_q, "qd", self.speeds)
        uu, pp = self._args(u, p)
        return np.array(self._functions.forcing(qq, vv, uu, pp)).reshape(-1)

    def residual(self, q, qd, qdd, u=None, p: Mapping[str, float] | None = None) -> np.ndarray:
        """Residual ``e = F - M qdd``, shape (n_q,)."""
        qq = self._vec(q, self.n_q, "q", self._coordinates)
        vv = self._vec(qd, self.n_q, "qd", self.speeds)
        aa = self._vec(qdd, self.n_q, "qdd", self._coordinates)
        uu, pp = self._args(u, p)
        return np.array(self._functions.residual(qq, vv, aa, uu, pp)).reshape(-1)

    def accelerations(self, q, qd, u=None, p: Mapping[str, float] | None = None) -> np.ndarray:
        """``qdd = M^-1 F`` with a check that M is not singular.

        Raises
        ------
        SingularMassMatrixError
            Naming the coordinates in the null space of M.
        """
        qq = self._vec(q, self.n_q, "q", self._coordinates)
        vv = self._vec(qd, self.n_q, "qd", self.speeds)
        uu, pp = self._args(u, p)
        M = self._mass(qq, uu, pp)
        check_nonsingular(M, self._coordinates)
        F = np.array(self._functions.forcing(qq, vv, uu, pp)).reshape(-1)
        return np.linalg.solve(M, F)

    def rhs(self, x, u=None, p: Mapping[str, float] | None = None) -> np.ndarray:
        """First-order right-hand side ``xd = [qd; qdd]``, shape (n_x,)."""
        xx = self._vec(x, self.n_x, "x", self.states)
        uu, pp = self._args(u, p)
        xd = np.array(self._functions.rhs(xx, uu, pp)).reshape(-1)
        if not np.all(np.isfinite(xd)):
            check_nonsingular(self._mass(xx[: self.n_q], uu, pp), self._coordinates)
            bad = [self.states[i] for i in np.flatnonzero(~np.isfinite(xd))]
            raise SolverError(f"the right-hand side is not finite for {bad} at this state; check the "
                                 "inputs and parameter values.")
        return xd

    def kinetic_energy(self, q, qd, p: Mapping[str, float] | None = None, *, u=None) -> float:
        """Kinetic energy [J]. ``u`` (keyword) is needed only with prescribed coordinates."""
        qq = self._vec(q, self.n_q, "q", self._coordinates)
        vv = self._vec(qd, self.n_q, "qd", self.speeds)
        uu = self._energy_inputs(u)
        return float(self._functions.kinetic_energy(qq, vv, uu, self.parameter_vector(p)))

    def potential_energy(self, q, p: Mapping[str, float] | None = None, *, u=None) -> float:
        """Potential energy of gravity and springs [J]. ``u`` as for :meth:`kinetic_energy`."""
        qq = self._vec(q, self.n_q, "q", self._coordinates)
        uu = self._energy_inputs(u)
        return float(self._functions.potential_energy(qq, uu, self.parameter_vector(p)))

    def _energy_inputs(self, u) -> np.ndarray:
        """Inputs for M and the energies: needed (and required) only with prescribed coordinates."""
        if u is None and self.prescribed:
            raise DimensionError(
                f"this model has prescribed coordinates {list(self.prescribed)}: pass u= with the inputs "
                f"{list(self._inputs)} (their values, speeds and accelerations)."
            )
        return self._input_vector(u)


def _build_functions(d: Derivation, name: str) -> EomFunctions:
    # One common-subexpression elimination over all outputs (cheaper than one per Function).
    opts: dict = {}
    q, qd, qdd, u, p = d.q, d.qd, d.qdd, d.u, d.p
    reactions = d.reactions if d.reactions is not None else ca.SX(0, 1)
    M, F, T, V, P, R = ca.cse([d.M, d.F, d.T, d.V, d.power, reactions])
    e = F - M @ qdd
    if d.prescribed:
        f_M = ca.Function(f"{name}_mass_matrix", [q, u, p], [M], ["q", "u", "p"], ["M"], opts)
    else:
        f_M = ca.Function(f"{name}_mass_matrix", [q, p], [M], ["q", "p"], ["M"], opts)
    f_F = ca.Function(f"{name}_forcing", [q, qd, u, p], [F], ["q", "qd", "u", "p"], ["F"], opts)
    f_e = ca.Function(f"{name}_residual", [q, qd, qdd, u, p], [e], ["q", "qd", "qdd", "u", "p"], ["e"], opts)
    x = ca.vertcat(q, qd)
    if q.numel() <= SYMBOLIC_SOLVE_MAX_DOF:
        xd = ca.vertcat(qd, ca.solve(M, F))
        f_rhs = ca.Function(f"{name}_rhs", [x, u, p], [xd], ["x", "u", "p"], ["xd"], {"cse": True})
    else:
        f_rhs = _numeric_rhs(f_M, f_F, q.numel(), u.numel(), p.numel(), name)
    f_T = ca.Function(f"{name}_kinetic_energy", [q, qd, u, p], [T], ["q", "qd", "u", "p"], ["T"], opts)
    f_V = ca.Function(f"{name}_potential_energy", [q, u, p], [V], ["q", "u", "p"], ["V"], opts)
    f_P = ca.Function(f"{name}_power", [q, qd, u, p], [P], ["q", "qd", "u", "p"], ["P"], opts)
    f_R = None
    if d.reactions is not None:
        f_R = ca.Function(f"{name}_reactions", [q, qd, qdd, u, p], [R], ["q", "qd", "qdd", "u", "p"], ["R"], opts)
    return EomFunctions(f_M, f_F, f_e, f_rhs, f_T, f_V, f_P, f_R)


def _numeric_rhs(f_M: ca.Function, f_F: ca.Function, n: int, nu: int, np_: int, name: str) -> ca.Function:
    """MX glue: M qdd = F solved by an unrolled LDLᵀ of M's pattern (:mod:`mbsym.spd_solve`), not a symbolic
    inverse of the whole right-hand side."""
    x = ca.MX.sym("x", 2 * n)
    u = ca.MX.sym("u", nu)
    p = ca.MX.sym("p", np_)
    q, qd = x[:n], x[n:]
    M = f_M(q, u, p) if f_M.n_in() == 3 else f_M(q, p)
    qdd = spd_solve(M, f_F(q, qd, u, p))         # M is symmetric positive definite (mbsym.spd_solve)
    return ca.Function(f"{name}_rhs", [x, u, p], [ca.vertcat(qd, qdd)], ["x", "u", "p"], ["xd"])
