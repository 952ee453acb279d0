"""The model protocol: what a model object may provide, and how mbsym reads it.

Every use of mbsym (simulation, linearization, control, identification, sweeps) accepts an
:class:`~mbsym.equations.EquationsOfMotion` or any object with an attribute ``eom`` holding one
(a wind-turbine template, say). Such an object may provide these optional hooks:

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

``input_units() -> dict by input name``
    Units of the inputs (docs/units.md: SI), shown with simulation results and linear models.

Uses read further hooks of their own (``dynamics()``, ``linearization_state()``,
``linearization_method()``, ``linearization_steps()``, ``rotating_frame()``,
``resolve_parameter(key)``: see ARCHITECTURE.md). :func:`read_hooks` reads the four above once;
:func:`initial_state` turns an array or a dict by name into a state vector. This module sits below
:mod:`mbsym.dynamics`, :mod:`mbsym.simulate` and :mod:`mbsym.linear`, which all read models through it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import casadi as ca
import numpy as np

from .equations import EquationsOfMotion
from .exceptions import DimensionError

__all__ = ["ModelHooks", "read_hooks", "initial_state", "input_units"]


@dataclass(frozen=True)
class ModelHooks:
    """A model's equations, and its default state, parameters, inputs and output channels."""

    eom: EquationsOfMotion
    default_x: np.ndarray
    default_p: Mapping[str, float]
    default_u: Mapping[str, Any]
    output_function: ca.Function | None
    output_names: tuple[str, ...]


def read_hooks(model: Any) -> ModelHooks:
    """The equations of ``model`` and what its hooks give (module docstring).

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
    # a wrapper object, or a subclass of EquationsOfMotion (a closed loop's) may carry the hooks
    hooked = eom is not model or type(model) is not EquationsOfMotion
    if hooked and callable(getattr(model, "default_state", None)):
        default_x = initial_state(model.default_state(), eom.states, zeros)
    default_p: Mapping[str, float] = {}
    if hooked and callable(getattr(model, "default_parameters", None)):
        default_p = model.default_parameters()
        if not isinstance(default_p, Mapping):
            raise TypeError(f"{type(model).__name__}.default_parameters() must return a dict by parameter name; "
                            f"got {type(default_p).__name__}.")
    default_u: Mapping[str, Any] = {}
    if hooked and callable(getattr(model, "default_inputs", None)):
        default_u = model.default_inputs()
        if not isinstance(default_u, Mapping):
            raise TypeError(f"{type(model).__name__}.default_inputs() must return a dict by input name; "
                            f"got {type(default_u).__name__}.")
    f_out, names = None, ()
    if hooked and callable(getattr(model, "output_function", None)):
        f_out = model.output_function()
        names = getattr(model, "output_names", None)
        if not isinstance(f_out, ca.Function) and isinstance(getattr(f_out, "function", None), ca.Function):
            f_out, names = f_out.function, getattr(f_out, "names", names)
        names = _output_names(f_out, eom, names, type(model).__name__)
    return ModelHooks(eom, default_x, dict(default_p), dict(default_u), f_out, names)


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


def initial_state(x0, states: Sequence[str], default: np.ndarray) -> np.ndarray:
    """Initial state from an array (n_x) or a dict by state name (missing names keep ``default``)."""
    n = len(states)
    if x0 is None:
        return default.copy()
    if isinstance(x0, Mapping):
        unknown = sorted(set(x0) - set(states))
        if unknown:
            raise DimensionError(f"x0 names unknown states {unknown}; the states are {list(states)}.")
        x = default.copy()
        for i, name in enumerate(states):
            if name in x0:
                x[i] = _finite_scalar(x0[name], f"x0[{name!r}]")
        return x
    try:
        x = np.asarray(x0, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise DimensionError(f"x0 must be {n} numbers in order {list(states)} or a dict by state name; "
                             f"got {x0!r}.") from exc
    if x.size != n:
        nq = n // 2
        raise DimensionError(f"x0 has {x.size} entries; expected {n} (q: {nq}, qd: {nq}) in order {list(states)}.")
    if not np.all(np.isfinite(x)):
        bad = [states[i] for i in np.flatnonzero(~np.isfinite(x))]
        raise DimensionError(f"all components of the initial state x0 must be finite; not finite: {bad}.")
    return x


def _finite_scalar(value, what: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise DimensionError(f"{what} must be a number; got {value!r}.") from exc
    if not np.isfinite(v):
        raise DimensionError(f"{what} must be finite; got {v}.")
    return v


def input_units(model: Any, inputs: Sequence[str]) -> tuple[str, ...]:
    """The units of ``inputs`` from the model's hook ``input_units()`` ("" each without it or for names it
    leaves out).

    Raises
    ------
    TypeError
        If the hook does not return a dict by input name.
    """
    hook = getattr(model, "input_units", None)
    if not callable(hook):
        return ("",) * len(inputs)
    units = hook()
    if not isinstance(units, Mapping):
        raise TypeError(f"{type(model).__name__}.input_units() must return a dict by input name; got "
                        f"{type(units).__name__}.")
    return tuple(str(units.get(n, "") or "") for n in inputs)
