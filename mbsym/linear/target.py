"""What the linearization accepts as a model: an EquationsOfMotion or an object with ``eom`` and hooks.

:class:`Target` resolves the defaults (state, inputs, parameters, output channels) through the
hooks of the simulation protocol (:mod:`mbsym.simulate.model`).
"""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..equations import EquationsOfMotion
from ..exceptions import ArgumentTypeError, DimensionError

__all__ = ["Target", "named"]


class Target:
    """An EquationsOfMotion, or a model object with ``eom`` and optional hooks (mbsym.simulate's protocol)."""

    def __init__(self, model: Any) -> None:
        if isinstance(model, EquationsOfMotion):
            self.eom, self.owner = model, None
        elif isinstance(getattr(model, "eom", None), EquationsOfMotion):
            self.eom, self.owner = model.eom, model
        else:
            why = (" A Dynamics without equations of motion (e.g. a system with velocity constraints: more "
                   "coordinates than speeds) has no residual M q̈ = F to linearize; take casadi.jacobian of its "
                   "rhs instead." if type(model).__name__ == "Dynamics" else "")
            raise ArgumentTypeError(f"model must be an EquationsOfMotion or an object whose attribute 'eom' is "
                                    f"one; got {type(model).__name__}.{why}")

    def _hook(self, name: str):
        f = getattr(self.owner, name, None) if self.owner is not None else None
        return f() if callable(f) else None

    def state(self, q0, qd0, *, hook: str = "default_state") -> tuple[np.ndarray, np.ndarray]:
        """``(q, qd)``: given values, else the owner's ``hook`` (falling back to ``default_state``), else zeros."""
        eom, n = self.eom, self.eom.n_q
        x = np.zeros(eom.n_x)
        if q0 is None or qd0 is None:
            default = self._hook(hook)
            if default is None and hook != "default_state":
                default = self._hook("default_state")
            if default is not None:
                from ..protocol import initial_state

                x = initial_state(default, eom.states, x)
        q = x[:n] if q0 is None else named(q0, eom.coordinates, x[:n], "q0", eom)
        qd = x[n:] if qd0 is None else named(qd0, eom.speeds, x[n:], "qd0", eom)
        return q, qd

    def inputs(self, u0) -> np.ndarray:
        eom = self.eom
        default = np.zeros(eom.n_u)
        hook = self._hook("default_inputs")
        if hook:
            from ..simulate.inputs import input_signal

            default = input_signal(hook, eom.inputs, 0.0).at(0.0)
        if u0 is None:
            return default
        return named(u0, eom.inputs, default, "u0", eom)

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


def named(value, names, default: np.ndarray, what: str, eom: EquationsOfMotion) -> np.ndarray:
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
