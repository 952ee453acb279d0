"""What :func:`mbsym.simulate` accepts as a model: the simulation protocol.

A model is either an :class:`~mbsym.equations.EquationsOfMotion` or any object
with an attribute ``eom`` holding one (a wind-turbine model, say). Such an
object may also provide these optional hooks; each is called once per
:func:`~mbsym.simulate` call:

``default_state() -> array (n_x) or dict by state name``
    Initial state used when ``x0`` is not given, and the values of the states
    a dict ``x0`` leaves out (without the hook: zeros).
``default_parameters() -> dict by parameter name``
    Parameter values that override the model's own defaults; ``p=`` overrides
    both.
``default_inputs() -> dict by input name``
    Input values in any form ``inputs=`` accepts in a dict (numbers, tables,
    callables of time, e.g. a prescribed rotor azimuth). A dict ``inputs=``
    overrides them name by name; an array ``inputs=`` replaces them all.
``output_function() -> casadi.Function``
    ``(x, u, p) -> y`` with column vectors ``x (n_x)``, ``u (n_u)``,
    ``p (n_p)``. Either one output ``y (n_y)`` whose channel names are the
    model's attribute ``output_names`` (a sequence of n_y str), or one scalar
    output per channel, named by the Function's output names
    (``Function.name_out()``) unless ``output_names`` is given. The hook may
    instead return an object with attributes ``function`` (that Function) and
    ``names`` (the channel names). Build it once and return the same object on
    every call.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Protocol, Sequence, runtime_checkable

import casadi as ca
import numpy as np

from ..equations import EquationsOfMotion
from ..exceptions import DimensionError
from .base import compile_key, maybe_compile, prepared
from .checks import initial_state

__all__ = ["SimulationModel", "ResolvedModel", "resolve_model"]


@runtime_checkable
class SimulationModel(Protocol):
    """An object :func:`mbsym.simulate` can run: it has ``eom`` (optional hooks: see the module)."""

    eom: EquationsOfMotion


@dataclass(frozen=True)
class ResolvedModel:
    """The model's equations, default state and parameters, and output function."""

    eom: EquationsOfMotion
    default_x: np.ndarray
    default_p: Mapping[str, float]
    default_u: Mapping[str, Any]
    output_function: ca.Function | None
    output_names: tuple[str, ...]

    def outputs(self, X: np.ndarray, U: np.ndarray, p: np.ndarray, *, compile: bool = False) -> np.ndarray:
        """Outputs at the rows of X (N, n_x) and U (N, n_u), shape (N, n_y); ``compile``: as generated C.

        The output Function mapped over the N rows is built once per (model, N, compile) and kept in the
        cache of prepared Functions (:func:`mbsym.simulate.base.prepared`; the entry holds ``f`` itself,
        so its ``id`` stays unique); it is called through ``Function.buffer()`` on numpy arrays.
        """
        n = X.shape[0]
        if self.output_function is None:
            return np.zeros((n, 0))
        f = self.output_function
        mapped, _ = prepared(self.eom, ("outputs", id(f), n, compile, compile_key(compile)),
                              lambda: (f, _MappedOutputs(f, n, compile)))
        return mapped[1](X, U, p)


class _MappedOutputs:
    """``(X (N, n_x), U (N, n_u), p) -> Y (N, n_y)``: ``f`` mapped over N columns, called through a buffer."""

    def __init__(self, f: ca.Function, n: int, compile: bool) -> None:
        g = maybe_compile(f, True)[0] if compile else f
        serial = g.map(f"{f.name()}_map{n}", "serial", n, [2], [])       # p (input 2) shared by all columns
        X, U, P = (ca.MX.sym(s, g.size1_in(i), n if i < 2 else 1) for i, s in enumerate(("X", "U", "p")))
        Y = ca.vertcat(*[ca.reshape(ca.densify(r), -1, n) for r in serial.call([X, U, P])])
        self.n, self.n_y = n, Y.size1()
        self.function = ca.Function(f"{f.name()}_outputs{n}", [X, U, P], [Y])

    def __call__(self, X: np.ndarray, U: np.ndarray, p: np.ndarray) -> np.ndarray:
        # row-major (N, n) equals column-major (n, N): the layout CasADi reads and writes
        args = [np.ascontiguousarray(a, dtype=float).reshape(-1) for a in (X, U, p)]
        Y = np.empty((self.n, self.n_y))
        buf, trigger = self.function.buffer()
        for i, a in enumerate(args):
            buf.set_arg(i, memoryview(a))
        buf.set_res(0, memoryview(Y.reshape(-1)))
        trigger()
        return Y


def resolve_model(model: Any) -> ResolvedModel:
    """Apply the protocol of the module docstring to ``model``.

    Raises
    ------
    TypeError
        If ``model`` is neither an EquationsOfMotion nor has one as ``eom``, or
        a hook returns the wrong kind of object.
    DimensionError
        If the default state or the output function has the wrong sizes.
    """
    if isinstance(model, EquationsOfMotion):
        eom = model
    elif isinstance(getattr(model, "eom", None), EquationsOfMotion):
        eom = model.eom
    else:
        hint = " Call sys.equations() first." if hasattr(model, "equations") and hasattr(model, "add_joint") else ""
        raise TypeError(f"model must be an EquationsOfMotion or an object whose attribute 'eom' is one; got "
                        f"{type(model).__name__}.{hint}")
    zeros = np.zeros(eom.n_x)
    default_x = zeros
    if eom is not model and callable(getattr(model, "default_state", None)):
        default_x = initial_state(model.default_state(), eom.states, zeros)
    default_p: Mapping[str, float] = {}
    if eom is not model and callable(getattr(model, "default_parameters", None)):
        default_p = model.default_parameters()
        if not isinstance(default_p, Mapping):
            raise TypeError(f"{type(model).__name__}.default_parameters() must return a dict by parameter name; "
                            f"got {type(default_p).__name__}.")
    default_u: Mapping[str, Any] = {}
    if eom is not model and callable(getattr(model, "default_inputs", None)):
        default_u = model.default_inputs()
        if not isinstance(default_u, Mapping):
            raise TypeError(f"{type(model).__name__}.default_inputs() must return a dict by input name; "
                            f"got {type(default_u).__name__}.")
    f_out, names = None, ()
    if eom is not model and callable(getattr(model, "output_function", None)):
        f_out = model.output_function()
        names = getattr(model, "output_names", None)
        if not isinstance(f_out, ca.Function) and isinstance(getattr(f_out, "function", None), ca.Function):
            f_out, names = f_out.function, getattr(f_out, "names", names)
        names = _output_names(f_out, eom, names, type(model).__name__)
    return ResolvedModel(eom, default_x, dict(default_p), dict(default_u), f_out, names)


def _output_names(f: Any, eom: EquationsOfMotion, names: Sequence[str] | None, owner: str) -> tuple[str, ...]:
    if not isinstance(f, ca.Function):
        raise TypeError(f"{owner}.output_function() must return a casadi.Function (x, u, p) -> y; "
                        f"got {type(f).__name__}.")
    expected = [(eom.n_x, 1), (eom.n_u, 1), (eom.n_p, 1)]
    got = [f.size_in(i) for i in range(f.n_in())]
    if [tuple(s) for s in got] != expected:
        raise DimensionError(f"{owner}.output_function() must take (x ({eom.n_x}), u ({eom.n_u}), p ({eom.n_p})) "
                             f"column vectors; it takes inputs of shapes {[tuple(s) for s in got]}.")
    sizes = [f.numel_out(i) for i in range(f.n_out())]
    if names is None:
        if f.n_out() == 1 or any(s != 1 for s in sizes):
            raise DimensionError(f"{owner} must name its outputs: give it an attribute output_names "
                                 f"({sum(sizes)} names), or return one scalar output per channel.")
        names = f.name_out()
    names = tuple(str(n) for n in names)
    if len(names) != sum(sizes) or len(set(names)) != len(names):
        raise DimensionError(f"{owner}.output_names has {len(names)} names (unique: {len(set(names))}); the output "
                             f"function returns {sum(sizes)} values; give one unique name per value.")
    return names
