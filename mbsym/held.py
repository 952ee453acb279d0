"""A part of the right-hand side held over each integration step (loose coupling).

Some right-hand sides are one expensive, slowly varying algebraic part ``z = g(x, u, p)`` feeding a
cheap remainder: ``ẋ = f(x, u, p, g(x, u, p))``. A wind turbine's blade-element aerodynamics is the
case in point: the BEM solution of every node of every blade costs some hundred times the structure's
mass matrix and forcing. OpenFAST's glue code evaluates AeroDyn once per coupling step and holds (or
extrapolates) its loads while ElastoDyn integrates the step; :class:`HeldPart` lets an
:class:`~mbsym.Dynamics` declare the same split, and the integration method ``"rk4-held"``
(:mod:`mbsym.simulate.held_rk4`) uses it.

The full right-hand side stays the reference: ``Dynamics.rhs(x, u, p)`` equals
``held.rhs(x, u, p, held.part(x, u, p))`` to rounding (whoever builds the split states it in a test), so linearization, trim, optimization and every other method see the exact model; only the
held-part integration holds ``z`` over a step, a first-order error in ``z``'s variation over the step.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from .exceptions import DimensionError

__all__ = ["HeldPart"]


@dataclass(frozen=True, eq=False)
class HeldPart:
    """The split ``ẋ = rhs(x, u, p, part(x, u, p))``, outputs ``y = outputs(x, u, p, part(x, u, p))``.

    Parameters
    ----------
    part : casadi.Function
        ``(x, u, p) -> z``: the held quantities (e.g. every blade-element load and wake derivative).
    rhs : casadi.Function
        ``(x, u, p, z) -> xd``: the right-hand side with the held quantities as an argument.
    outputs : casadi.Function, optional
        ``(x, u, p, z) -> y``: the outputs with the held quantities as an argument.
    description : str, optional
        What is held (for messages and statistics), e.g. ``"blade-element aerodynamics"``.

    Raises
    ------
    TypeError
        A Function is not a casadi.Function.
    DimensionError
        The Functions' argument counts or the size of ``z`` disagree.
    """

    part: ca.Function
    rhs: ca.Function
    outputs: ca.Function | None = None
    description: str = "held part"

    def __post_init__(self) -> None:
        for what, f, n_in in (("part", self.part, 3), ("rhs", self.rhs, 4), ("outputs", self.outputs, 4)):
            if f is None and what == "outputs":
                continue
            if not isinstance(f, ca.Function):
                raise TypeError(f"HeldPart.{what} must be a casadi.Function; got {type(f).__name__}.")
            if f.n_in() != n_in:
                raise DimensionError(f"HeldPart.{what} must take {n_in} arguments "
                                     f"({'x, u, p' if n_in == 3 else 'x, u, p, z'}); it takes {f.n_in()}.")
        n_z = self.n_z
        for what, f in (("rhs", self.rhs), ("outputs", self.outputs)):
            if f is not None and f.numel_in(3) != n_z:
                raise DimensionError(f"HeldPart.{what} takes z of {f.numel_in(3)} entries; part returns {n_z}.")

    @property
    def n_z(self) -> int:
        """Number of held quantities."""
        return self.part.numel_out(0)

    def check(self, n_x: int, n_u: int, n_p: int, n_y: int | None) -> None:
        """Raise DimensionError unless the Functions fit dynamics of these sizes (``n_y`` None: no outputs)."""
        for what, f in (("part", self.part), ("rhs", self.rhs), ("outputs", self.outputs)):
            if f is None:
                continue
            got = tuple(f.numel_in(i) for i in range(3))
            if got != (n_x, n_u, n_p):
                raise DimensionError(f"HeldPart.{what} takes (x, u, p) of sizes {got}; the dynamics have "
                                     f"{(n_x, n_u, n_p)}.")
        if self.rhs.numel_out(0) != n_x:
            raise DimensionError(f"HeldPart.rhs returns {self.rhs.numel_out(0)} values; expected {n_x}.")
        if self.outputs is not None:
            if n_y is None:
                raise DimensionError("HeldPart.outputs was given for dynamics without outputs.")
            if self.outputs.numel_out(0) != n_y:
                raise DimensionError(f"HeldPart.outputs returns {self.outputs.numel_out(0)} values; expected {n_y}.")

    def depends_on_inputs(self, rows) -> bool:
        """Whether ``part`` depends (structurally) on any of the inputs ``rows`` (indices into u)."""
        rows = list(rows)
        if not rows:
            return False
        sp = self.part.jac_sparsity(0, 1)
        return any(sp.colind()[j + 1] > sp.colind()[j] for j in rows)
