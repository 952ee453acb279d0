"""Named first-order dynamics: the common currency of simulation, control, estimation and export.

Every model mbsym can run is, in first-order form, ``ẋ = f(x, u, p)`` with optional
outputs ``y = h(x, u, p)``: the equations of motion of a :class:`~mbsym.System`
(``x = [q; qd]``), or those equations composed with extra states (actuators, an
aerodynamic lag, a controller) by a template such as a wind turbine. A
:class:`Dynamics` holds the two CasADi Functions with the names of every vector and
the default values; :func:`as_dynamics` turns whatever a user passes into one.

Accepted by :func:`as_dynamics`:

- a :class:`Dynamics` (returned as is);
- an :class:`~mbsym.equations.EquationsOfMotion` (``f`` is its ``rhs``, no outputs);
- an object with a hook ``dynamics() -> Dynamics`` (a composed model);
- an object with an attribute ``eom`` and the optional hooks of the simulation
  protocol (:mod:`mbsym.simulate.model`): ``default_state()``,
  ``default_parameters()``, ``default_inputs()`` (numbers only are used here) and
  ``output_function()``.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any, Mapping, Sequence

import casadi as ca
import numpy as np

from .equations import EquationsOfMotion
from .exceptions import DimensionError, ParameterError
from .held import HeldPart
from .protocol import input_units as hook_input_units
from .protocol import read_hooks

__all__ = ["Dynamics", "as_dynamics"]


def _names(value: Sequence[str], what: str) -> tuple[str, ...]:
    names = tuple(str(n) for n in value)
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise DimensionError(f"{what} names must be unique; {dup} appear more than once.")
    return names


class Dynamics:
    """First-order dynamics ``ẋ = f(x, u, p)``, outputs ``y = h(x, u, p)``, every vector named.

    Parameters
    ----------
    rhs : casadi.Function
        ``(x, u, p) -> xd`` with column vectors ``x (n_x)``, ``u (n_u)``, ``p (n_p)``.
    states, inputs, parameters : sequence of str
        Names of x, u and p, in vector order.
    defaults : dict, optional
        Default parameter values by name (parameters without one must be given at
        every numeric call).
    outputs : casadi.Function, optional
        ``(x, u, p) -> y (n_y)``.
    output_names, output_units : sequence of str, optional
        One per entry of y (units default to "").
    state_units, input_units : sequence of str, optional, keyword-only
        One per entry of x and of u (default: the units of the structural coordinates and their speeds
        from ``eom``, "" for the others). docs/units.md states the convention: states and inputs SI.
    x0 : array (n_x), optional
        Default initial state (zeros).
    u0 : array (n_u), optional
        Default constant inputs (zeros).
    name : str, optional
    eom : EquationsOfMotion, optional
        The structural equations when ``x`` starts with their ``[q; qd]``.
    held : HeldPart, optional
        The same right-hand side (and outputs) split into a part that an integrator may hold over a
        step and the remainder (:mod:`mbsym.held`; used by the method ``"rk4-held"``).

    Raises
    ------
    DimensionError
        If a Function's argument sizes do not match the names.
    TypeError
        If ``rhs`` or ``outputs`` is not a casadi.Function.

    Examples
    --------
    >>> import casadi as ca
    >>> x, u, p = ca.SX.sym("x", 1), ca.SX.sym("u", 1), ca.SX.sym("p", 1)
    >>> f = ca.Function("f", [x, u, p], [-p * x + u])
    >>> dyn = Dynamics(f, states=["x"], inputs=["u"], parameters=["a"], defaults={"a": 2.0})
    >>> float(dyn.rhs_value([1.0], [0.5])[0])
    -1.5
    """

    def __init__(self, rhs: ca.Function, *, states: Sequence[str], inputs: Sequence[str] = (),
                 parameters: Sequence[str] = (), defaults: Mapping[str, float] | None = None,
                 outputs: ca.Function | None = None, output_names: Sequence[str] = (),
                 output_units: Sequence[str] | None = None, x0=None, u0=None, name: str | None = None,
                 eom: EquationsOfMotion | None = None, held: HeldPart | None = None,
                 state_units: Sequence[str] | None = None, input_units: Sequence[str] | None = None) -> None:
        self._states = _names(states, "state")
        self._inputs = _names(inputs, "input")
        self._parameters = _names(parameters, "parameter")
        _check_function(rhs, "rhs", (self.n_x, self.n_u, self.n_p), self.n_x)
        unknown = sorted(set(defaults or {}) - set(self._parameters))
        if unknown:
            raise ParameterError(f"defaults name unknown parameters {unknown}; parameters are {list(self._parameters)}.")
        self._defaults = MappingProxyType({k: float(v) for k, v in (defaults or {}).items()})
        self._rhs = rhs
        self._outputs = outputs
        self._output_names = _names(output_names, "output")
        if outputs is not None:
            _check_function(outputs, "outputs", (self.n_x, self.n_u, self.n_p), len(self._output_names))
        elif self._output_names:
            raise DimensionError("output_names were given without an outputs Function.")
        units = tuple(output_units) if output_units is not None else ("",) * len(self._output_names)
        if len(units) != len(self._output_names):
            raise DimensionError(f"output_units has {len(units)} entries; expected {len(self._output_names)}.")
        self._output_units = tuple(str(v) for v in units)
        self._state_units = _units(state_units, self._states, "state_units") if state_units is not None else \
            _eom_state_units(self._states, eom)
        self._input_units = _units(input_units, self._inputs, "input_units")
        self._x0 = self._fixed(x0, self.n_x, "x0", self._states)
        self._u0 = self._fixed(u0, self.n_u, "u0", self._inputs)
        self._name = name or rhs.name()
        self._eom = eom
        if held is not None:
            if not isinstance(held, HeldPart):
                raise TypeError(f"held must be an mbsym.held.HeldPart; got {type(held).__name__}.")
            held.check(self.n_x, self.n_u, self.n_p, self.n_y if outputs is not None else None)
        self._held = held

    # ------------------------------------------------------------ description
    @property
    def name(self) -> str:
        return self._name

    @property
    def rhs(self) -> ca.Function:
        """``(x, u, p) -> xd``."""
        return self._rhs

    @property
    def outputs(self) -> ca.Function | None:
        """``(x, u, p) -> y``, or None."""
        return self._outputs

    states = property(lambda self: self._states, doc="Names of x.")
    inputs = property(lambda self: self._inputs, doc="Names of u.")
    parameters = property(lambda self: self._parameters, doc="Names of p.")
    output_names = property(lambda self: self._output_names, doc="Names of y.")
    output_units = property(lambda self: self._output_units, doc="Units of y.")
    state_units = property(lambda self: self._state_units, doc="Units of x (\"\" where unknown).")
    input_units = property(lambda self: self._input_units, doc="Units of u (\"\" where unknown).")
    defaults = property(lambda self: self._defaults, doc="Default parameter values (read-only).")
    eom = property(lambda self: self._eom, doc="The structural equations, or None.")
    held = property(lambda self: self._held, doc="The held-part split of the right-hand side (HeldPart), or None.")
    n_x = property(lambda self: len(self._states))
    n_u = property(lambda self: len(self._inputs))
    n_p = property(lambda self: len(self._parameters))
    n_y = property(lambda self: len(self._output_names))

    @property
    def x0(self) -> np.ndarray:
        """Default initial state (a copy)."""
        return self._x0.copy()

    @property
    def u0(self) -> np.ndarray:
        """Default inputs (a copy)."""
        return self._u0.copy()

    def __repr__(self) -> str:
        return (f"Dynamics({self._name!r}, n_x={self.n_x}, n_u={self.n_u}, n_p={self.n_p}, n_y={self.n_y}, "
                f"states={list(self._states)})")

    # ------------------------------------------------------------ numeric vectors
    def parameter_vector(self, p: Mapping[str, float] | None = None) -> np.ndarray:
        """Parameter vector in the order of :attr:`parameters`: ``p`` by name, defaults fill the gaps.

        Raises
        ------
        ParameterError
            For unknown names, missing values or non-finite numbers.
        """
        if p is not None and not isinstance(p, Mapping):
            raise ParameterError(f"p must be a dict by parameter name; got {type(p).__name__}.")
        given = dict(p or {})
        unknown = sorted(set(given) - set(self._parameters))
        if unknown:
            raise ParameterError(f"unknown parameters {unknown}; parameters are {list(self._parameters)}.")
        merged = {**self._defaults, **given}
        missing = [n for n in self._parameters if n not in merged]
        if missing:
            raise ParameterError(f"no value for parameters {missing}; pass them in p={{name: value}}.")
        values = np.array([_finite(merged[n], n) for n in self._parameters], dtype=float)
        return values

    def state_vector(self, x=None) -> np.ndarray:
        """A state vector from an array (n_x) or a dict by name (missing states keep :attr:`x0`)."""
        return self._vector(x, self._x0, "x", self._states)

    def input_vector(self, u=None) -> np.ndarray:
        """An input vector from an array (n_u) or a dict by name (missing inputs keep :attr:`u0`)."""
        return self._vector(u, self._u0, "u", self._inputs)

    def rhs_value(self, x, u=None, p: Mapping[str, float] | None = None) -> np.ndarray:
        """``f(x, u, p)`` as a numpy array (n_x)."""
        out = self._rhs(self.state_vector(x), self.input_vector(u), self.parameter_vector(p))
        return np.array(out, dtype=float).reshape(-1)

    def output_value(self, x, u=None, p: Mapping[str, float] | None = None) -> np.ndarray:
        """``h(x, u, p)`` as a numpy array (n_y); empty without outputs."""
        if self._outputs is None:
            return np.zeros(0)
        out = self._outputs(self.state_vector(x), self.input_vector(u), self.parameter_vector(p))
        return np.array(out, dtype=float).reshape(-1)

    def _vector(self, value, default: np.ndarray, what: str, names: tuple[str, ...]) -> np.ndarray:
        if value is None:
            return default.copy()
        if isinstance(value, Mapping):
            unknown = sorted(set(value) - set(names))
            if unknown:
                raise DimensionError(f"{what} names unknown entries {unknown}; expected names from {list(names)}.")
            arr = default.copy()
            for i, n in enumerate(names):
                if n in value:
                    arr[i] = _finite(value[n], n)
            return arr
        return self._fixed(value, len(names), what, names)

    @staticmethod
    def _fixed(value, n: int, what: str, names: tuple[str, ...]) -> np.ndarray:
        if value is None:
            return np.zeros(n)
        try:
            arr = np.asarray(value, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise DimensionError(f"{what} must be {n} numbers in order {list(names)}; got {value!r}.") from None
        if arr.size != n:
            raise DimensionError(f"{what} has {arr.size} entries; expected {n} in order {list(names)}.")
        if not np.all(np.isfinite(arr)):
            bad = [names[i] for i in np.flatnonzero(~np.isfinite(arr))]
            raise DimensionError(f"{what} must be finite; {bad} are not.")
        return arr.copy()


def _units(value: Sequence[str] | None, names: tuple[str, ...], what: str) -> tuple[str, ...]:
    units = tuple(str(v) for v in value) if value is not None else ("",) * len(names)
    if len(units) != len(names):
        raise DimensionError(f"{what} has {len(units)} entries; expected {len(names)} (one per name: {list(names)}).")
    return units


def _eom_state_units(states: tuple[str, ...], eom: EquationsOfMotion | None) -> tuple[str, ...]:
    """Units of the structural coordinates and speeds (:attr:`EquationsOfMotion.units`), "" for other states."""
    known = eom.units if eom is not None else {}
    return tuple(known.get(s, "") for s in states)


def _finite(value, name: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a number; got {value!r}.") from None
    if not np.isfinite(v):
        raise ParameterError(f"{name} must be finite; got {v}.")
    return v


def _check_function(f: Any, what: str, sizes: tuple[int, int, int], n_out: int) -> None:
    if not isinstance(f, ca.Function):
        raise TypeError(f"{what} must be a casadi.Function (x, u, p) -> vector; got {type(f).__name__}.")
    got = [tuple(f.size_in(i)) for i in range(f.n_in())]
    want = [(k, 1) for k in sizes]
    ok = len(got) == 3 and all(g == w or (w[0] == 0 and g[0] * g[1] == 0) for g, w in zip(got, want))
    if not ok:
        raise DimensionError(f"{what} must take column vectors x ({sizes[0]}), u ({sizes[1]}), p ({sizes[2]}); "
                             f"it takes {got}.")
    total = sum(f.numel_out(i) for i in range(f.n_out()))
    if total != n_out:
        raise DimensionError(f"{what} returns {total} values; expected {n_out}.")


def as_dynamics(model: Any) -> Dynamics:
    """The first-order :class:`Dynamics` of any model mbsym accepts (see the module docstring).

    Raises
    ------
    TypeError
        If ``model`` is none of the accepted kinds.
    """
    if isinstance(model, Dynamics):
        return model
    hook = getattr(model, "dynamics", None)
    if callable(hook):
        dyn = hook()
        if not isinstance(dyn, Dynamics):
            raise TypeError(f"{type(model).__name__}.dynamics() must return an mbsym.Dynamics; "
                            f"got {type(dyn).__name__}.")
        return dyn
    if isinstance(model, EquationsOfMotion) and callable(getattr(model, "output_function", None)):
        return _from_simulation_model(model)     # a subclass with hooks (a closed loop's equations)
    if isinstance(model, EquationsOfMotion):
        return Dynamics(model.functions.rhs, states=model.states, inputs=model.inputs, parameters=model.parameters,
                        defaults=dict(model.defaults), name=model.name, eom=model)
    if isinstance(getattr(model, "eom", None), EquationsOfMotion):
        return _from_simulation_model(model)
    raise TypeError(f"model must be an mbsym.Dynamics, an EquationsOfMotion, or an object with dynamics() or an "
                    f"'eom' attribute; got {type(model).__name__}.")


def _from_simulation_model(model: Any) -> Dynamics:
    """A model object of the simulation protocol (``eom`` and hooks) as Dynamics."""
    r = read_hooks(model)
    eom = r.eom
    defaults = {**dict(eom.defaults), **{k: float(v) for k, v in r.default_p.items()}}
    u0 = np.zeros(eom.n_u)
    for i, n in enumerate(eom.inputs):
        v = r.default_u.get(n)
        if isinstance(v, (int, float, np.floating)):
            u0[i] = float(v)
    outputs, names = r.output_function, r.output_names
    if outputs is not None and outputs.n_out() != 1:
        x, u, p = (ca.MX.sym(s, k) for s, k in (("x", eom.n_x), ("u", eom.n_u), ("p", eom.n_p)))
        y = ca.vertcat(*[ca.vec(v) for v in outputs.call([x, u, p])])
        outputs = ca.Function(f"{eom.name}_outputs", [x, u, p], [y], ["x", "u", "p"], ["y"])
    hook = getattr(model, "output_function", None)
    units = getattr(hook(), "units", None) if callable(hook) else None       # Channels carry units
    units = getattr(model, "output_units", None) if units is None else units
    units = tuple(units) if units is not None and len(tuple(units)) == len(names) else None
    return Dynamics(eom.functions.rhs, states=eom.states, inputs=eom.inputs, parameters=eom.parameters,
                    defaults=defaults, outputs=outputs, output_names=names, output_units=units, x0=r.default_x,
                    u0=u0, name=eom.name, eom=eom, input_units=hook_input_units(model, eom.inputs))
