"""What :func:`mbsym.simulate` accepts as a model: the simulation protocol.

A model is an :class:`mbsym.Dynamics` (named first-order ``ẋ = f(x, u, p)``,
outputs ``y = h(x, u, p)``: how composed models, e.g. a turbine with actuator and
aerodynamic states, are simulated), an object with a hook ``dynamics() ->
Dynamics``, an :class:`~mbsym.equations.EquationsOfMotion`, or any object with
an attribute ``eom`` holding one (a wind-turbine model, say). :func:`plant_of`
turns each into the :class:`Plant` the methods integrate. An object with ``eom``
(or ``dynamics()``) may also provide the optional hooks of the model protocol
(``default_state``, ``default_parameters``, ``default_inputs``, ``output_function``; described in
:mod:`mbsym.protocol`); each is called once per :func:`~mbsym.simulate` call.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Mapping, Protocol, Sequence, runtime_checkable

import casadi as ca
import numpy as np

from ..dynamics import Dynamics
from ..equations import EquationsOfMotion
from ..exceptions import ParameterError
from .base import compile_key, maybe_compile, prepared
from ..protocol import ModelHooks, initial_state, read_hooks  # noqa: F401  (initial_state re-exported)
from ..protocol import input_units as hook_input_units

__all__ = ["SimulationModel", "ResolvedModel", "resolve_model", "Plant", "plant_of"]


@runtime_checkable
class SimulationModel(Protocol):
    """An object :func:`mbsym.simulate` can run: it has ``eom`` (optional hooks: see the module)."""

    eom: EquationsOfMotion


@dataclass(frozen=True)
class ResolvedModel(ModelHooks):
    """The model's hooks read once (:class:`mbsym.protocol.ModelHooks`), with its outputs at many samples."""

    def outputs(self, X: np.ndarray, U: np.ndarray, p: np.ndarray, *, compile: bool | None = False) -> np.ndarray:
        """Outputs at the rows of X (N, n_x) and U (N, n_u), shape (N, n_y) (see :func:`evaluate_outputs`)."""
        return evaluate_outputs(self.eom, self.output_function, X, U, p, compile)


#: Output times per call of the mapped output Function (CasADi's map takes time to build in proportion to
#: its length: 1.4 ms for 512 columns, 34 ms for 3001; blocks of a fixed length are built once per model).
OUTPUT_BLOCK = 256


def evaluate_outputs(owner: Any, f: ca.Function | None, X: np.ndarray, U: np.ndarray, p: np.ndarray,
                     compile: bool | None = False) -> np.ndarray:
    """``f(x, u, p)`` at the rows of X (N, n_x) and U (N, n_u), shape (N, n_y).

    ``f`` is mapped over blocks of :data:`OUTPUT_BLOCK` columns (one Function per model, cached in
    :func:`mbsym.simulate.base.prepared`), called through ``Function.buffer()`` on numpy arrays.
    ``compile``: True as generated C; False in CasADi's virtual machine; None: compiled when the
    library is already in the disk cache, else the virtual machine (and, when that takes more than
    10 ms, a compilation into the disk cache in the background for the next runs).
    """
    n = X.shape[0]
    if f is None:
        return np.zeros((n, 0))
    block = min(OUTPUT_BLOCK, max(n, 1))
    sym, _ = prepared(owner, ("outputs", id(f), block, "symbolic"), lambda: (f, _mapped_block(f, block)))
    g = sym[1]
    choice = compile
    if compile is None:
        from .. import codegen

        choice = codegen.cached_library(g) is not None
    run, _ = prepared(owner, ("outputs", id(f), block, bool(choice), compile_key(bool(choice))),
                      lambda: (f, _BlockOutputs(maybe_compile(g, True)[0] if choice else g, block)))
    t0 = time.perf_counter()
    Y = run[1](X, U, p)
    if compile is None and not choice and time.perf_counter() - t0 > 0.01:
        from .. import codegen

        codegen.compile_in_background(g)
    return Y


def _mapped_block(f: ca.Function, block: int) -> ca.Function:
    """``(X (n_x, B), U (n_u, B), P (n_p, B)) -> Y (n_y, B)``: ``f`` mapped over B columns, outputs stacked.

    Its disk-cache key is that of ``f`` and this construction (:func:`mbsym.codegen.set_identity`): the
    map wrapper serializes to about 3x the size of ``f``, and a new process pays that to find the library.
    """
    from .. import codegen

    serial = f.map(block, "serial")
    X, U, P = (ca.MX.sym(s, f.size1_in(i), block) for i, s in enumerate(("X", "U", "p")))
    Y = ca.vertcat(*[ca.reshape(ca.densify(r), -1, block) for r in serial.call([X, U, P])])
    g = ca.Function(f"{f.name()}_outputs{block}", [X, U, P], [Y])
    return codegen.set_identity(g, f"mbsym output block v1|{block}|serial|{f.serialize()}")


class _BlockOutputs:
    """``(X (N, n_x), U (N, n_u), p) -> Y (N, n_y)`` through a block Function of B columns (last block padded)."""

    def __init__(self, g: ca.Function, block: int) -> None:
        self.g, self.block, self.n_y = g, block, g.size1_out(0)

    def __call__(self, X: np.ndarray, U: np.ndarray, p: np.ndarray) -> np.ndarray:
        n, B = X.shape[0], self.block
        n_pad = -(-n // B) * B
        # row-major (N, n) equals column-major (n, N): the layout CasADi reads and writes
        Xp, Up = np.zeros((n_pad, X.shape[1])), np.zeros((n_pad, U.shape[1]))
        Xp[:n], Up[:n] = X, U
        Xp[n:], Up[n:] = X[-1:], U[-1:] if n else 0.0          # padding: repeat a valid row
        P = np.ascontiguousarray(np.broadcast_to(np.asarray(p, dtype=float), (B, np.size(p))))
        Y = np.empty((n_pad, self.n_y))
        buf, trigger = self.g.buffer()
        buf.set_arg(2, memoryview(P.reshape(-1)))
        for k in range(0, n_pad, B):
            xs, us = Xp[k:k + B].reshape(-1), Up[k:k + B].reshape(-1)
            ys = Y[k:k + B].reshape(-1)
            buf.set_arg(0, memoryview(xs))
            buf.set_arg(1, memoryview(us))
            buf.set_res(0, memoryview(ys))
            trigger()
        return Y[:n]


def resolve_model(model: Any) -> ResolvedModel:
    """Apply the model protocol (:func:`mbsym.protocol.read_hooks`, which lists what it raises) to ``model``."""
    h = read_hooks(model)
    return ResolvedModel(h.eom, h.default_x, h.default_p, h.default_u, h.output_function, h.output_names)


@dataclass(frozen=True, eq=False)
class Plant:
    """What the integration methods integrate: ``ẋ = rhs(x, u, p)`` with names, defaults and outputs.

    Attributes
    ----------
    rhs : casadi.Function
        ``(x, u, p) -> xd``.
    states, inputs, parameters : tuple of str
        Names of x, u and p.
    name : str
    eom : EquationsOfMotion or None
        The structural equations when ``x`` is exactly their ``[q; qd]`` and ``rhs`` their
        first-order form: what the second-order methods (newmark, generalized-alpha) and the
        residual form of idas need. None for other dynamics.
    default_x : ndarray (n_x)
        Initial state when ``x0`` is not given.
    default_p : dict
        Parameter values that override the model's own defaults (``p=`` overrides both).
    default_u : dict
        Inputs by name (numbers, tables, callables) when ``inputs=`` leaves them out.
    output_function : casadi.Function or None
        ``(x, u, p) -> y`` (one vector, or one output per channel).
    output_names, output_units : tuple of str
    held : HeldPart or None
        The held-part split of the dynamics (:mod:`mbsym.held`), for the method ``"rk4-held"``.
    state_units, input_units : tuple of str
        Units of x and u ("" where unknown; :attr:`mbsym.Dynamics.state_units`).
    """

    rhs: ca.Function
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    parameters: tuple[str, ...]
    name: str
    eom: EquationsOfMotion | None
    default_x: np.ndarray
    default_p: Mapping[str, float]
    default_u: Mapping[str, Any]
    output_function: ca.Function | None
    output_names: tuple[str, ...]
    output_units: tuple[str, ...]
    _parameter_vector: Any = None
    n_q: int | None = None
    held: Any = None
    state_units: tuple[str, ...] = ()
    input_units: tuple[str, ...] = ()

    n_x = property(lambda self: len(self.states))
    n_u = property(lambda self: len(self.inputs))
    n_p = property(lambda self: len(self.parameters))

    @property
    def owner(self) -> Any:
        """Key of the prepared-Function cache: the EquationsOfMotion when ``rhs`` is its own, else ``rhs``."""
        return self.eom if self.eom is not None else self.rhs

    def parameter_vector(self, p: Mapping[str, float] | None) -> np.ndarray:
        """Parameter vector: ``p`` by name over :attr:`default_p` over the model's defaults (ParameterError)."""
        if p is not None and not isinstance(p, Mapping):
            self._parameter_vector(p)          # raises the model's own ParameterError (names the parameters)
            raise ParameterError(f"p must be a dict by parameter name; got {type(p).__name__}.")
        return self._parameter_vector({**self.default_p, **(p or {})})

    def outputs(self, X: np.ndarray, U: np.ndarray, p: np.ndarray, *, compile: bool | None = False) -> np.ndarray:
        """Outputs at the rows of X (N, n_x) and U (N, n_u), shape (N, n_y) (see :func:`evaluate_outputs`)."""
        return evaluate_outputs(self.owner, self.output_function, X, U, p, compile)


def plant_of(model: Any) -> Plant:
    """The :class:`Plant` of any model :func:`mbsym.simulate` accepts (see the module docstring).

    Raises
    ------
    TypeError
        If ``model`` is none of the accepted kinds, or a hook returns the wrong kind of object.
    DimensionError
        If the default state or the output function has the wrong sizes.
    """
    if isinstance(model, Dynamics):
        return _from_dynamics(model, model)
    hook = getattr(model, "dynamics", None)
    if callable(hook) and not isinstance(model, EquationsOfMotion):
        dyn = hook()
        if not isinstance(dyn, Dynamics):
            raise TypeError(f"{type(model).__name__}.dynamics() must return an mbsym.Dynamics; "
                            f"got {type(dyn).__name__}.")
        return _from_dynamics(dyn, model)
    r = resolve_model(model)
    eom = r.eom
    units: Sequence[str] | None = None
    if r.output_function is not None:
        hook_out = getattr(model, "output_function", None)
        units = getattr(hook_out(), "units", None) if callable(hook_out) else None   # Channels carry units
        units = getattr(model, "output_units", None) if units is None else units
    units = tuple(str(u) for u in units) if units is not None and len(tuple(units)) == len(r.output_names) \
        else ("",) * len(r.output_names)
    return Plant(eom.functions.rhs, eom.states, eom.inputs, eom.parameters, eom.name, eom, r.default_x,
                 dict(r.default_p), dict(r.default_u), r.output_function, r.output_names, units,
                 eom.parameter_vector, eom.n_q, state_units=tuple(eom.units.get(s, "") for s in eom.states),
                 input_units=hook_input_units(model, eom.inputs))


def _from_dynamics(dyn: Dynamics, model: Any) -> Plant:
    """A Dynamics (given, or from the hook of ``model``); ``model``'s optional hooks override its defaults."""
    eom = dyn.eom
    if eom is not None and not (dyn.rhs is eom.functions.rhs and tuple(dyn.states) == tuple(eom.states)
                                and tuple(dyn.inputs) == tuple(eom.inputs)
                                and tuple(dyn.parameters) == tuple(eom.parameters)):
        eom = None                                  # composed dynamics: x is more than [q; qd]
    default_x = dyn.x0
    default_u: dict[str, Any] = {n: float(v) for n, v in zip(dyn.inputs, dyn.u0) if v != 0.0}
    default_p: dict[str, float] = {}
    if model is not dyn:
        if callable(getattr(model, "default_state", None)):
            default_x = initial_state(model.default_state(), dyn.states, default_x)
        if callable(getattr(model, "default_inputs", None)):
            extra = model.default_inputs()
            if not isinstance(extra, Mapping):
                raise TypeError(f"{type(model).__name__}.default_inputs() must return a dict by input name; "
                                f"got {type(extra).__name__}.")
            default_u.update(extra)
        if callable(getattr(model, "default_parameters", None)):
            default_p = dict(model.default_parameters())
    return Plant(dyn.rhs, tuple(dyn.states), tuple(dyn.inputs), tuple(dyn.parameters), dyn.name, eom, default_x,
                 default_p, default_u, dyn.outputs, tuple(dyn.output_names), tuple(dyn.output_units),
                 dyn.parameter_vector, _coordinates(dyn), dyn.held, tuple(dyn.state_units), tuple(dyn.input_units))


def _coordinates(dyn: Dynamics) -> int | None:
    """Number of coordinates when the states start with the structural ``[q; qd]`` of ``dyn.eom``, else None."""
    eom = dyn.eom
    if eom is not None and tuple(dyn.states[: eom.n_x]) == tuple(eom.states):
        return eom.n_q
    return None
