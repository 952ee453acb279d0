"""The description layer: a :class:`System` of bodies, joints and loads.

A System is what users write. It only records and checks; the equations are
derived by :mod:`mbsym.kane` when :meth:`System.equations` is called. Every
``add_*`` method validates its arguments completely before changing anything,
so a failed call leaves the System unchanged.
"""

from __future__ import annotations

from typing import Mapping, Sequence

import casadi as ca

from .bodies.base import Body, Ground
from .exceptions import ModelDefinitionError
from .joints import Joint
from .kinematics import _scalar, as_vector3
from .loads import Damper, DistributedLoad, GeneralizedForce, PointForce, Spring, Torque
from .symbols import SymbolTable, split_names

__all__ = ["System"]


class System:
    """A multibody system: ground frame, gravity, named symbols, bodies, joints, loads.

    Parameters
    ----------
    gravity : sequence of 3, optional
        Gravitational acceleration in ground axes [m/s^2], default zero.
        Entries may be numbers; use :meth:`set_gravity` for an expression of
        parameters.

    Examples
    --------
    >>> import mbsym as mb
    >>> sys = mb.System(gravity=[0.0, 0.0, -9.81])
    >>> q1, q2 = sys.coordinates("q1 q2")
    >>> m, l = sys.parameters("m l")
    >>> b1 = mb.RigidBody("b1", mass=m, com=[0, 0, -l])
    >>> sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    """

    def __init__(self, gravity: Sequence = (0.0, 0.0, 0.0)) -> None:
        self._symbols = SymbolTable()
        self._ground = Ground()
        self._gravity = as_vector3(gravity, "gravity")
        stray = sorted({v.name() for v in ca.symvar(self._gravity)})
        if stray:
            raise ModelDefinitionError(
                f"gravity contains symbols {stray}, but the System has no parameters yet. Create the "
                "System with a numeric gravity, declare the parameters, then call sys.set_gravity([...])."
            )
        self._joints: list[Joint] = []
        self._bodies: dict[str, Body] = {}
        self._loads: list = []
        self._owner: dict[str, str] = {}   # coordinate name -> joint/body name using it
        self._constraints: list = []        # closures of kinematic loops (mbsym.constraints)

    # ------------------------------------------------------------------ symbols
    @property
    def ground(self) -> Ground:
        """The inertial frame (parent of the root joints)."""
        return self._ground

    @property
    def gravity(self) -> ca.SX:
        """Gravity vector in ground axes [m/s^2] (3x1 SX)."""
        return self._gravity

    @property
    def symbols(self) -> SymbolTable:
        """The symbol table (coordinates, speeds, inputs, parameters)."""
        return self._symbols

    def set_gravity(self, gravity: Sequence) -> None:
        """Set the gravity vector [m/s^2]; entries may be expressions of parameters."""
        g = as_vector3(gravity, "gravity")
        self._symbols.check_expression(g, "gravity", speeds=False, inputs=False, coordinates=False)
        self._gravity = g

    def coordinates(self, names: str | Sequence[str]):
        """Declare generalized coordinates; return one SX symbol or a tuple of them.

        Parameters
        ----------
        names : str or sequence of str
            Space- or comma-separated names, e.g. ``"q1 q2"``.
        """
        return _one_or_tuple(self._symbols.declare(split_names(names, "coordinate"), "coordinate"))

    def parameters(self, names: str | Sequence[str], *, values: Mapping[str, float] | Sequence[float] | None = None):
        """Declare named parameters; return one SX symbol or a tuple of them.

        Parameters
        ----------
        names : str or sequence of str
            Space- or comma-separated names.
        values : dict or sequence, optional
            Default values, by name or in the order of ``names``. Parameters
            without a default must be given a value at every numeric call.
        """
        items = split_names(names, "parameter")
        if values is not None and not isinstance(values, Mapping):
            values = list(values)
            if len(values) != len(items):
                raise ModelDefinitionError(
                    f"{len(values)} default values given for {len(items)} parameters {items}; "
                    "give one per name or a dict by name."
                )
            values = dict(zip(items, values))
        return _one_or_tuple(self._symbols.declare(items, "parameter", values))

    def inputs(self, names: str | Sequence[str]):
        """Declare named inputs (time-varying signals); return one SX or a tuple."""
        return _one_or_tuple(self._symbols.declare(split_names(names, "input"), "input"))

    def prescribed(self, names: str | Sequence[str]):
        """Declare prescribed (rheonomic) coordinates; return one SX symbol or a tuple.

        A prescribed coordinate moves a joint like a coordinate, but its value,
        speed and acceleration are *inputs* named ``n``, ``n_d`` and ``n_dd``
        (e.g. a rotor spinning at a fixed speed: ``psi = psi0 + Ω t``,
        ``psi_d = Ω``, ``psi_dd = 0``). It has no equation of motion.
        """
        return _one_or_tuple(self._symbols.declare_prescribed(split_names(names, "prescribed coordinate")))

    def locked(self, names: str | Sequence[str]):
        """Declare locked coordinates; return one SX symbol or a tuple.

        A locked coordinate drives a joint that never moves: the equations hold it at
        zero (no equation of motion, no cost), and report the generalized force the
        support must exert to keep it there — its *reaction* — as
        ``eom.functions.reactions(q, qd, qdd, u, p)`` (e.g. the bending moment at a
        tower base: a locked rotation about the base's axis).
        """
        return _one_or_tuple(self._symbols.declare_locked(split_names(names, "locked coordinate")))

    def speed(self, coordinate) -> ca.SX:
        """Time derivative symbol of a coordinate (for loads depending on speeds)."""
        return self._symbols.speed_of(coordinate)

    # ------------------------------------------------------------------ tree
    @property
    def joints(self) -> tuple[Joint, ...]:
        """Joints in the order they were added."""
        return tuple(self._joints)

    @property
    def bodies(self) -> tuple[Body, ...]:
        """Bodies (children of joints) in the order they were added."""
        return tuple(self._bodies.values())

    def body(self, name: str) -> Body:
        """The body called ``name``."""
        if name not in self._bodies:
            raise ModelDefinitionError(f"no body named {name!r}; bodies are {list(self._bodies)}.")
        return self._bodies[name]

    def add_joint(self, joint: Joint) -> None:
        """Add a joint, and with it its child body, to the tree.

        Raises
        ------
        ModelDefinitionError
            If the child already has a joint, a body name is taken by another
            body, a coordinate is unknown or already used, or an expression
            contains undeclared symbols. The System is unchanged on error.
        """
        if not isinstance(joint, Joint):
            raise ModelDefinitionError(f"add_joint expects a Joint (e.g. mb.Revolute); got {joint!r}.")
        child, parent = joint.child, joint.parent
        if child.name in self._bodies:
            other = self._bodies[child.name]
            what = "already has a joint" if other is child else "is the name of another body"
            raise ModelDefinitionError(
                f"body {child.name!r} {what}; each body has exactly one parent joint and a unique name."
            )
        if isinstance(parent, Ground) and parent is not self._ground:
            raise ModelDefinitionError("the joint's parent is the ground of another System; use sys.ground.")
        if not isinstance(parent, Ground) and parent.name in self._bodies and self._bodies[parent.name] is not parent:
            raise ModelDefinitionError(f"parent {parent.name!r} has the name of another body in this system.")
        claimed = self._check_new_coordinates(joint)
        parent.attachment(joint.offset)   # flexible parents accept children at their root or end only
        for expr, what in [(joint.offset, "joint offset"), (joint.rotation, "joint rotation"),
                           *[(v, f"property of body {child.name!r}") for v in child.symbolic_values()]]:
            self._symbols.check_expression(expr, f"{what} of {child.name!r}", speeds=False, inputs=False,
                                           coordinates=False)
        self._joints.append(joint)
        self._bodies[child.name] = child
        for name in claimed:
            self._owner.setdefault(name, child.name)

    def _check_new_coordinates(self, joint: Joint) -> list[str]:
        claimed = []
        geared = getattr(joint, "gear_ratio", None) is not None
        joint_keys = {c.element_hash() for c in joint.coordinates}
        for c in (*joint.coordinates, *joint.child.elastic_coordinates):
            of_joint = c.element_hash() in joint_keys       # SX '==' builds an expression: compare identities
            entry = self._symbols.lookup(c)
            if entry is not None and entry.name in self._symbols.prescribed() and of_joint:
                key = f"prescribed:{entry.name}"
                if geared:
                    continue    # a geared joint follows the prescribed motion of another joint
                if key in self._owner:
                    raise ModelDefinitionError(
                        f"prescribed coordinate {entry.name!r} already moves body {self._owner[key]!r}; "
                        "use gear_ratio= for a second, geared joint."
                    )
                claimed.append(key)
                continue
            if geared and entry is not None and entry.kind == "coordinate" and of_joint:
                continue    # a geared joint follows a coordinate that another joint owns
            if entry is not None and entry.kind == "locked" and not of_joint:
                raise ModelDefinitionError(f"locked coordinate {entry.name!r} can drive a joint only, not the "
                                           f"deflection of {joint.child.name!r}.")
            if entry is None or entry.kind not in ("coordinate", "locked"):
                raise ModelDefinitionError(
                    f"joint of {joint.child.name!r} uses {c!r}, which is not a coordinate of this system; "
                    "pass a symbol returned by sys.coordinates(...)."
                )
            if entry.name in self._owner or entry.name in claimed:
                user = self._owner.get(entry.name, joint.child.name)
                raise ModelDefinitionError(
                    f"coordinate {entry.name!r} already moves body {user!r}; each coordinate drives one joint. "
                    "Declare another coordinate."
                )
            claimed.append(entry.name)
        return claimed

    # ------------------------------------------------------------------ loads
    def add_force(self, body: Body, force: Sequence, *, point: Sequence | None = None,
                  frame: Body | None = None) -> None:
        """Apply a force [N] at a point of a body.

        Parameters
        ----------
        body : Body
            Body the force acts on (already joined to the system).
        force : sequence of 3
            Components, expressions of coordinates, speeds, inputs, parameters.
        point : sequence of 3, optional
            Point of application in body coordinates [m]; default the body origin.
        frame : Body, optional
            Body whose axes the components are given in; default ground axes.
        """
        self._check_body(body, "force")
        self._check_frame(frame)
        f = as_vector3(force, f"force on {body.name!r}")
        pt = as_vector3((0.0, 0.0, 0.0) if point is None else point, f"point of the force on {body.name!r}")
        self._symbols.check_expression(f, f"force on {body.name!r}")
        self._symbols.check_expression(pt, f"point of the force on {body.name!r}", speeds=False, inputs=False,
                                       coordinates=False)
        body.attachment(pt)   # flexible bodies accept loads at their root or end only
        self._loads.append(PointForce(body, f, pt, frame))

    def add_torque(self, body: Body, torque: Sequence, *, frame: Body | None = None) -> None:
        """Apply a torque [N m] to a body; components in ``frame`` axes (default ground)."""
        self._check_body(body, "torque")
        self._check_frame(frame)
        t = as_vector3(torque, f"torque on {body.name!r}")
        self._symbols.check_expression(t, f"torque on {body.name!r}")
        self._loads.append(Torque(body, t, frame))

    def add_distributed_load(self, body: Body, integrals, magnitude) -> None:
        """Apply a distributed force per unit length to a flexible body.

        Parameters
        ----------
        body : FlexibleBody
            The loaded body (already joined to the system).
        integrals : mbsym.beam.DistributedLoadIntegrals
            Profile and direction of the load, integrated against the body's
            shape functions (:func:`mbsym.beam.distributed_load_integrals`).
        magnitude : float or SX
            Load magnitude ``P`` [N/m]: an expression of coordinates, speeds,
            inputs and parameters (e.g. an input for a wind or wave load).
        """
        self._check_body(body, "distributed load")
        n_e = len(body.elastic_coordinates)
        if n_e == 0 or not hasattr(integrals, "generalized"):
            raise ModelDefinitionError(
                f"a distributed load needs a flexible body and DistributedLoadIntegrals; got body {body.name!r} "
                f"({type(body).__name__}) and {type(integrals).__name__}. Use mbsym.beam.distributed_load_integrals."
            )
        if integrals.n_e != n_e:
            raise ModelDefinitionError(
                f"distributed-load integrals were computed for {integrals.n_e} shape functions, but body "
                f"{body.name!r} has {n_e}; integrate against the body's own shapes, in order."
            )
        P = _scalar(magnitude, "distributed load magnitude")
        self._symbols.check_expression(P, f"distributed load magnitude on {body.name!r}")
        self._loads.append(DistributedLoad(body, integrals, P))

    def add_generalized_force(self, coordinate, value) -> None:
        """Add a generalized force [N or N m] to the equation of ``coordinate``."""
        idx = self._coordinate_index(coordinate)
        v = _scalar(value, "generalized force")
        self._symbols.check_expression(v, "generalized force")
        self._loads.append(GeneralizedForce(idx, v))

    def add_spring(self, coordinate, stiffness, *, rest=0.0) -> None:
        """Linear spring on a coordinate: ``Q = -stiffness (q - rest)`` [N/m or N m/rad]."""
        idx = self._coordinate_index(coordinate)
        k = _scalar(stiffness, "spring stiffness")
        r = _scalar(rest, "spring rest position")
        for e, what in [(k, "spring stiffness"), (r, "spring rest position")]:
            self._symbols.check_expression(e, what, speeds=False, inputs=False, coordinates=False)
        self._loads.append(Spring(idx, k, r))

    def add_damper(self, coordinate, damping) -> None:
        """Linear damper on a coordinate: ``Q = -damping * qd`` [N s/m or N m s/rad]."""
        idx = self._coordinate_index(coordinate)
        c = _scalar(damping, "damping")
        self._symbols.check_expression(c, "damping", speeds=False, inputs=False)
        self._loads.append(Damper(idx, c))

    @property
    def loads(self) -> tuple:
        """Load records in the order they were added."""
        return tuple(self._loads)

    def _check_body(self, body: Body, what: str) -> None:
        if not isinstance(body, Body) or isinstance(body, Ground):
            raise ModelDefinitionError(f"a {what} must act on a body of the system; got {body!r}.")
        if self._bodies.get(body.name) is not body:
            raise ModelDefinitionError(
                f"body {body.name!r} is not in this system; add the joint that connects it before loading it."
            )

    def _check_frame(self, frame: Body | None) -> None:
        if frame is None or frame is self._ground:
            return
        if not isinstance(frame, Body) or self._bodies.get(frame.name) is not frame:
            raise ModelDefinitionError(
                f"frame {frame!r} is not a body of this system; use None (ground axes) or a joined body."
            )

    def _coordinate_index(self, coordinate) -> int:
        entry = self._symbols.lookup(coordinate)
        if entry is None or entry.kind != "coordinate":
            raise ModelDefinitionError(
                f"{coordinate!r} is not a coordinate of this system; pass a symbol from sys.coordinates(...)."
            )
        return self._symbols.names("coordinate").index(entry.name)

    # ------------------------------------------------------------------ loops
    def add_closure(self, body_a: Body, point_a: Sequence, body_b: Body, point_b: Sequence, *,
                    directions: str = "xyz", name: str | None = None) -> None:
        """Close a kinematic loop: a point of ``body_a`` and a point of ``body_b`` coincide.

        Cut one joint of the loop, build the rest as a tree, then declare the cut joint here.
        The equations then need the independent coordinates (:meth:`equations`).

        Parameters
        ----------
        body_a, body_b : Body
            The bodies on either side of the cut joint (either may be ``sys.ground``).
        point_a, point_b : sequence of 3
            The coinciding points, each in its body's frame [m] (numbers or parameters).
        directions : str, optional
            Ground axes along which the points coincide: ``"xz"`` for a planar loop moving in
            the x-z plane (a revolute cut joint about y), ``"xyz"`` (default) for a spherical one.
        name : str, optional
            Name of the closure (default ``closure<k>``); its reaction force on ``body_b`` [N,
            ground axes] is the output channel ``<name>_F<axis>``.

        Raises
        ------
        ModelDefinitionError
            Unknown body, same body twice, bad directions, a point that is not 3 numbers or
            parameters, a name already taken. The System is unchanged on error.
        """
        from .constraints import check_name, point_closure

        nm = check_name(name, [c.name for c in self._constraints], f"closure{len(self._constraints) + 1}")
        rec = point_closure(nm, body_a, point_a, body_b, point_b, directions)
        for b in (rec.body_a, rec.body_b):
            if b is not self._ground:
                self._check_body(b, "closure")
        for b, pt in ((rec.body_a, rec.point_a), (rec.body_b, rec.point_b)):
            self._symbols.check_expression(pt, f"closure point on {b.name!r}", speeds=False, inputs=False,
                                           coordinates=False)
            b.attachment(pt)            # flexible bodies: root or end only
        self._constraints.append(rec)

    def add_constraint(self, expression, *, name: str | None = None) -> None:
        """Add a general holonomic constraint ``g(q, p) = 0`` (one expression or a list of them).

        Parameters
        ----------
        expression : SX or sequence of SX
            Expressions of coordinates and parameters that the motion keeps at zero.
        name : str, optional
            Name (default ``constraint<k>``); its multipliers are the output channels
            ``<name>_lambda`` (generalized reaction forces).

        Raises
        ------
        ModelDefinitionError
            If the expression has speeds, inputs or undeclared symbols, or no coordinate.
        """
        from .constraints import check_name, holonomic_constraint

        nm = check_name(name, [c.name for c in self._constraints], f"constraint{len(self._constraints) + 1}")
        rec = holonomic_constraint(nm, expression)
        self._symbols.check_expression(rec.expression, f"constraint {nm!r}", speeds=False, inputs=False)
        coords = {s.element_hash() for s in self._symbols.symbols("coordinate")}
        if not any(s.element_hash() in coords for s in ca.symvar(rec.expression)):
            raise ModelDefinitionError(f"constraint {nm!r} depends on no coordinate; a constraint restricts the "
                                       "motion, so it must contain coordinates from sys.coordinates(...).")
        self._constraints.append(rec)

    def add_velocity_constraint(self, expression, *, name: str | None = None) -> None:
        """Add a non-holonomic constraint ``A(q, p) q̇ + b(q, p) = 0`` (linear in the speeds).

        Write it with the speed symbols of :meth:`speed`, e.g. a knife edge that cannot slide
        sideways: ``-sin(th) * sys.speed(x) + cos(th) * sys.speed(y)``. The equations are then
        first-order dynamics in the coordinates and the independent speeds
        (``sys.equations(independent_speeds=[...])``, :mod:`mbsym.loops.nonholonomic`).

        Raises
        ------
        ModelDefinitionError
            If the expression has inputs or undeclared symbols, no speed, or is not linear in the
            speeds. The System is unchanged on error.
        """
        from .constraints import VelocityConstraint, check_name, holonomic_constraint

        nm = check_name(name, [c.name for c in self._constraints], f"constraint{len(self._constraints) + 1}")
        g = holonomic_constraint(nm, expression).expression
        self._symbols.check_expression(g, f"velocity constraint {nm!r}", inputs=False)
        qd = ca.vertcat(*self._symbols.speeds())
        A = ca.jacobian(g, qd)
        if A.nnz() == 0 or all(A[i].is_zero() for i in range(A.numel())):
            raise ModelDefinitionError(f"velocity constraint {nm!r} has no speed; use sys.speed(q) for the speeds, "
                                       "or sys.add_constraint for a constraint on the coordinates.")
        if ca.depends_on(ca.vec(A), qd):
            raise ModelDefinitionError(f"velocity constraint {nm!r} is not linear in the speeds; write it as "
                                       "A(q) q̇ + b(q) = 0.")
        self._constraints.append(VelocityConstraint(nm, g))

    @property
    def constraints(self) -> tuple:
        """Loop closures, holonomic and velocity constraints in the order they were added."""
        return tuple(self._constraints)

    # ------------------------------------------------------------------ build
    def problems(self) -> list[str]:
        """Every reason the system cannot be turned into equations (empty if none)."""
        out = []
        reach = {id(self._ground)}
        changed = True
        while changed:
            changed = False
            for j in self._joints:
                if id(j.parent) in reach and id(j.child) not in reach:
                    reach.add(id(j.child))
                    changed = True
        for j in self._joints:
            if id(j.child) not in reach:
                out.append(
                    f"body {j.child.name!r} is not connected to the ground (its parent {j.parent.name!r} has no "
                    "joint leading to sys.ground); add the missing joint."
                )
        unused = [n for n in self._symbols.names("coordinate") if n not in self._owner]
        if unused:
            out.append(f"coordinates {unused} are declared but no joint or flexible body uses them.")
        if not self._symbols.names("coordinate"):
            out.append("the system has no coordinates; declare them with sys.coordinates(...).")
        return out

    def validate(self) -> None:
        """Raise ModelDefinitionError listing every problem found, if any."""
        problems = self.problems()
        if problems:
            raise ModelDefinitionError("the system cannot be built:\n  - " + "\n  - ".join(problems))

    def equations(self, *, name: str = "mbsym", independent: Sequence[str] | None = None,
                  guess: Mapping[str, float] | None = None, **options):
        """Derive the equations of motion (Kane's method).

        Parameters
        ----------
        name : str, optional
            Prefix of the CasADi Functions.
        independent : sequence of str, optional
            Systems with closed loops (:meth:`add_closure`, :meth:`add_constraint`) only: the
            names of the independent coordinates, one per degree of freedom.
        guess : dict, optional
            Closed loops only: values of coordinates near the assembled configuration, by name
            (missing ones are 0); the dependent coordinates are found from them, so the guess
            picks the assembly branch.
        **options
            Closed loops only: ``stages``, ``newton_steps`` and ``references`` of the
            dependent-coordinate solver (see :func:`mbsym.loops.closed_equations`). With velocity
            constraints: ``independent_speeds``, the coordinates whose speeds are independent
            (:func:`mbsym.loops.nonholonomic.nonholonomic_dynamics`).

        Returns
        -------
        EquationsOfMotion
            Immutable object holding CasADi Functions and names; for a closed loop a
            :class:`mbsym.loops.ClosedLoopEquations` in the independent coordinates; with velocity
            constraints a :class:`mbsym.Dynamics` (first-order: coordinates and independent speeds).
        """
        from .equations import EquationsOfMotion
        from .kane import derive

        self.validate()
        from .constraints import VelocityConstraint

        if any(isinstance(c, VelocityConstraint) for c in self._constraints) or "independent_speeds" in options:
            from .loops.nonholonomic import nonholonomic_dynamics

            return nonholonomic_dynamics(self, name=name, independent=independent, guess=guess, **options)
        if self._constraints or independent is not None or guess is not None or options:
            from .loops import closed_equations

            return closed_equations(self, independent, guess, name=name, **options)
        return EquationsOfMotion(derive(self), name=name, units=self.coordinate_units())

    def coordinate_units(self) -> dict[str, str]:
        """Unit of each coordinate by name: ``"rad"`` if its joint rotates with it, ``"m"`` if the joint
        translates (or for a flexible body's elastic coordinates, amplitudes of displacement shapes),
        ``"-"`` if unknown (not yet used by a joint)."""
        units = {}
        for joint in self._joints:
            d, R = joint.relative()
            for c in joint.coordinates:
                entry = self._symbols.lookup(c)
                if entry is not None and entry.kind == "coordinate":
                    units.setdefault(entry.name, "rad" if ca.depends_on(ca.vec(R), c) else "m")
            for c in joint.child.elastic_coordinates:
                entry = self._symbols.lookup(c)
                if entry is not None:
                    units.setdefault(entry.name, "m")
        return {n: units.get(n, "-") for n in self._symbols.names("coordinate")}

    def __repr__(self) -> str:
        g = [float(v) for v in ca.evalf(self._gravity).full().ravel()] if self._gravity.is_constant() else "symbolic"
        units = self.coordinate_units()
        coords = ", ".join(f"{n} [{u}]" for n, u in units.items())
        counts = {k: len(self._symbols.names(k)) for k in ("parameter", "input")}
        return (f"System(gravity={g} m/s^2, coordinates: {coords or 'none'}; {counts['parameter']} parameters, "
                f"{counts['input']} inputs, {len(self._bodies)} bodies, {len(self._joints)} joints, "
                f"{len(self._loads)} loads)")


def _one_or_tuple(items: list):
    return items[0] if len(items) == 1 else tuple(items)
