"""Discrete controllers in the loop of :func:`mbsym.simulate`, with zero-order hold.

A :class:`DiscreteController` runs every ``dt`` seconds, at ``t_k = k dt``: it reads the
measurements ``y_k`` (model outputs or states, by name) at ``t_k``, updates its state and sets
the inputs it actuates, which are then held until ``t_{k+1}``::

    (xc_{k+1}, u_k) = law(xc_k, y_k)        u(t) = u_k on [t_k, t_{k+1})

The plant is integrated between samples by RK4 sub-steps (``m`` per sample; the step never
straddles a sample time, where the held inputs jump). Inputs not actuated by the controller
(e.g. the wind speed as a time series) follow ``inputs=`` as without a controller. A value given
in ``inputs=`` for an actuated input is its value before the first sample (what measurements
with direct feedthrough see at t = 0).

Two kinds of law:

- a CasADi ``Function (xc, y) -> (xc_next, u)``: the whole closed loop is **one generated
  loop**, a ``mapaccum`` over controller samples whose body is the law followed by the ``m``
  RK4 sub-steps of the plant with ``u`` held (compiled to C with the rest when compilation is on);
- a Python callable ``law(t, xc, y) -> (xc_next, u)`` (a DISCON library through ctypes, an
  NMPC step), called once per sample between compiled plant loops.

The result holds the plant states, the inputs as applied (held values included) and, appended
to the outputs, the controller states (after each sample: the value on ``[t_k, t_{k+1})`` is
``xc_{k+1}``), named ``state_names``.

Between output times the states are cubic Hermite interpolants of each sub-step (with the
derivative at a sample's end taken with that sample's held input: one extra rhs evaluation per
sample). The integration itself lives in :mod:`mbsym.simulate.closed_loop`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Sequence

import casadi as ca
import numpy as np

from ..exceptions import DimensionError, SimulationOptionError

__all__ = ["DiscreteController", "BoundController", "bind_controller"]


class DiscreteController:
    """A discrete-time controller with zero-order hold, for ``mbsym.simulate(..., controller=...)``.

    Parameters
    ----------
    law : casadi.Function or callable
        ``Function (xc, y) -> (xc_next, u)`` with column vectors ``xc (n_xc)``, ``y
        (len(measurements))``, ``u (len(actuates))``: kept inside the generated loop. Or a Python
        callable ``law(t, xc, y) -> (xc_next, u)`` [t in s; arrays], called once per sample. The
        accuracy-driven default checks its step by running the loop again; a Python law is run
        again only if it has a method ``reset()`` (back to its initial state) — without one (a
        DISCON library keeps hidden state) the loop runs once at the predicted step.
    dt : float
        Sample time [s].
    x0 : array (n_xc), optional
        Initial controller state (default zeros; a Function law fixes n_xc).
    measurements : sequence of str, keyword-only
        Names of the model outputs or states that form ``y``, in order (outputs are looked up
        first).
    actuates : sequence of str, keyword-only
        Names of the model inputs set by ``u``, in order.
    state_names : sequence of str, optional, keyword-only
        Names of the controller states in the result (default ``<name>.x0``, ``<name>.x1``, ...).
    state_units : sequence of str, optional, keyword-only
        Their units in the result (default "" each, shown as "-").
    name : str, optional, keyword-only
        Default ``"controller"``.
    hidden_states : int, optional, keyword-only
        How many of the last controller states are internal (default 0): carried from sample to sample but not
        recorded in the result (a module with hundreds of states, e.g. moving mooring lines); ``state_names``
        and ``state_units`` then name the others.

    Raises
    ------
    SimulationOptionError
        A sample time that is not a positive finite number.
    DimensionError
        Sizes of the Function, x0 and the names that do not agree; duplicate names.
    TypeError
        A law that is neither a casadi.Function nor callable.

    Examples
    --------
    A discrete integral controller driving a first-order plant ``x' = -x + u`` to ``y = 1``:

    >>> import casadi as ca, mbsym as mb
    >>> x, u, p = ca.SX.sym("x"), ca.SX.sym("u"), ca.SX.sym("p", 0)
    >>> plant = mb.Dynamics(ca.Function("f", [x, u, p], [-x + u]), states=["x"], inputs=["u"])
    >>> xc, y = ca.SX.sym("xc"), ca.SX.sym("y")
    >>> law = ca.Function("I", [xc, y], [xc + 0.1 * (1 - y), xc + 0.1 * (1 - y)])
    >>> ctrl = DiscreteController(law, 0.1, measurements=["x"], actuates=["u"])
    >>> res = mb.simulate(plant, 20.0, controller=ctrl)
    >>> round(float(res.state("x")[-1]), 3)
    1.0
    """

    def __init__(self, law: ca.Function | Callable, dt: float, x0: Sequence[float] | None = None, *,
                 measurements: Sequence[str], actuates: Sequence[str], state_names: Sequence[str] | None = None,
                 state_units: Sequence[str] | None = None, name: str = "controller", hidden_states: int = 0) -> None:
        if isinstance(dt, bool) or not isinstance(dt, (int, float, np.integer, np.floating)) \
                or not math.isfinite(float(dt)) or float(dt) <= 0:
            raise SimulationOptionError(f"controller sample time dt must be a positive finite number [s]; got {dt!r}.")
        self.dt = float(dt)
        self.name = str(name)
        self.measurements = _unique(measurements, "measurements")
        self.actuates = _unique(actuates, "actuates")
        if not self.actuates:
            raise DimensionError("actuates must name at least one model input the controller sets.")
        if isinstance(law, ca.Function):
            n_xc = self._check_function(law, x0)
            self.is_function = True
        elif callable(law):
            n_xc = 0 if x0 is None else np.size(x0)
            self.is_function = False
        else:
            raise TypeError(f"law must be a casadi.Function (xc, y) -> (xc_next, u) or a callable "
                            f"law(t, xc, y) -> (xc_next, u); got {type(law).__name__}.")
        self.law = law
        self.x0 = _vector(np.zeros(n_xc) if x0 is None else x0, n_xc, "x0")
        if isinstance(hidden_states, bool) or not isinstance(hidden_states, (int, np.integer)) \
                or not 0 <= hidden_states <= n_xc:
            raise DimensionError(f"hidden_states must be an integer from 0 to the {n_xc} controller states; got "
                                 f"{hidden_states!r}.")
        self.hidden_states = int(hidden_states)
        shown = n_xc - self.hidden_states
        names = [f"{self.name}.x{i}" for i in range(shown)] if state_names is None else list(state_names)
        self.state_names = _unique(names, "state_names")
        if len(self.state_names) != shown:
            raise DimensionError(f"state_names has {len(self.state_names)} names for {shown} recorded controller "
                                 "states.")
        self.state_units = tuple(str(u) for u in state_units) if state_units is not None else ("",) * shown
        if len(self.state_units) != shown:
            raise DimensionError(f"state_units has {len(self.state_units)} units for {shown} recorded controller "
                                 "states.")

    @property
    def n_xc(self) -> int:
        return self.x0.size

    @property
    def n_shown(self) -> int:
        """The recorded controller states (all but the hidden ones)."""
        return self.x0.size - self.hidden_states

    def _check_function(self, f: ca.Function, x0) -> int:
        if f.n_in() != 2 or f.n_out() != 2:
            raise DimensionError(f"the controller Function must be (xc, y) -> (xc_next, u); {f.name()!r} has "
                                 f"{f.n_in()} inputs and {f.n_out()} outputs.")
        n_xc = f.numel_in(0)
        if f.numel_out(0) != n_xc:
            raise DimensionError(f"the controller Function takes a state of {n_xc} values but returns "
                                 f"{f.numel_out(0)} as xc_next.")
        if f.numel_in(1) != len(self.measurements):
            raise DimensionError(f"the controller Function takes y of {f.numel_in(1)} values; measurements names "
                                 f"{len(self.measurements)}: {list(self.measurements)}.")
        if f.numel_out(1) != len(self.actuates):
            raise DimensionError(f"the controller Function returns u of {f.numel_out(1)} values; actuates names "
                                 f"{len(self.actuates)}: {list(self.actuates)}.")
        if x0 is not None and np.size(x0) != n_xc:
            raise DimensionError(f"x0 has {np.size(x0)} values; the controller Function's state has {n_xc}.")
        return n_xc

    def __repr__(self) -> str:
        kind = f"Function {self.law.name()!r}" if self.is_function else "Python callable"
        return (f"DiscreteController({self.name!r}, {kind}, dt={self.dt:g} s, n_xc={self.n_xc}, "
                f"measurements={list(self.measurements)}, actuates={list(self.actuates)})")


def _unique(names: Sequence[str], what: str) -> tuple[str, ...]:
    if isinstance(names, str):
        raise TypeError(f"{what} must be a sequence of names, e.g. [{names!r}]; got the string {names!r}.")
    out = tuple(str(n) for n in names)
    if len(set(out)) != len(out):
        raise DimensionError(f"{what} names must be unique; got {list(out)}.")
    return out


def _vector(value, n: int, what: str) -> np.ndarray:
    try:
        v = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise DimensionError(f"controller {what} must be {n} numbers; got {value!r}.") from None
    if v.size != n or not np.all(np.isfinite(v)):
        raise DimensionError(f"controller {what} must be {n} finite numbers; got {v.tolist()}.")
    return v


# ------------------------------------------------------------------------------------------- binding
@dataclass
class BoundController:
    """A controller attached to a plant: index maps and the measurement Function."""

    ctrl: DiscreteController
    act: np.ndarray               # indices of the actuated inputs in u
    measure: ca.Function          # (x, u, p) -> y
    substep_dt: float | None      # step given explicitly (method "rk4", dt), else None
    n_columns: int
    method: str = "rk4"           # "rk4", "rk4-held" (the held part once per sub-step), "abm4-held", "ab4-held"
    measure_held: ca.Function | None = None   # (x, u, p, z) -> y, "rk4-held" only
    held_samples: int = 1         # "rk4-held": controller samples between evaluations of the held part
    held_order: int = 0           # "rk4-held": extrapolation of the held part between evaluations (held_carry)


def bind_controller(controller: Any, plant, method: str | None, dt: float | None, tmax: float, *,
                    held_dt: float | None = None, held_order: int = 0) -> BoundController:
    """Check ``controller`` against ``plant`` and the options; build the measurement Function.

    An object with ``as_controller()`` (an :class:`mbsym.control.NMPC`), or a pair ``(estimator, nmpc)``,
    is first turned into a DiscreteController by it.
    """
    if isinstance(controller, tuple) and len(controller) == 2 and hasattr(controller[1], "as_controller"):
        controller = controller[1].as_controller(estimator=controller[0])
    elif not isinstance(controller, DiscreteController) and hasattr(controller, "as_controller"):
        controller = controller.as_controller()
    if not isinstance(controller, DiscreteController):
        raise TypeError(f"controller must be an mbsym.simulate.DiscreteController; got {type(controller).__name__}.")
    from .held_multistep import HELD_METHODS

    if method not in (None, "rk4", *HELD_METHODS):
        raise SimulationOptionError(f"a controller runs with RK4 sub-steps (or, with a held part, Adams steps) between "
                                    f"its samples; method {method!r} is not supported with controller= (leave method "
                                    f"unset, or use one of {['rk4', *HELD_METHODS]}).")
    if method in HELD_METHODS and getattr(plant, "held", None) is None:
        raise SimulationOptionError(f"method {method!r} treats apart the part of the dynamics that {plant.name!r} "
                                    "declares as held (mbsym.held.HeldPart), but this model declares none; use 'rk4'.")
    c = controller
    missing = [n for n in c.actuates if n not in plant.inputs]
    if missing:
        raise DimensionError(f"the controller actuates {missing}, which are not inputs of the model; its inputs are "
                             f"{list(plant.inputs)}.")
    unknown = [n for n in c.measurements if n not in plant.output_names and n not in plant.states]
    if unknown:
        raise DimensionError(f"the controller measures {unknown}, which are neither outputs nor states of the model; "
                             f"outputs: {list(plant.output_names)[:20]}, states: {list(plant.states)[:20]}.")
    clash = [n for n in c.state_names if n in plant.output_names]
    if clash:
        raise DimensionError(f"controller state names {clash} are also model outputs; pass other state_names.")
    h = None
    if dt is not None:
        m = c.dt / dt
        if abs(m - round(m)) > 1e-9 * max(m, 1.0):
            raise SimulationOptionError(f"dt = {dt:g} s must divide the controller sample time {c.dt:g} s (the RK4 "
                                        "steps must not straddle a sample, where the held inputs jump); choose "
                                        f"dt = {c.dt:g} / m or leave method and dt unset.")
        h = c.dt / round(m)
    held = method in HELD_METHODS
    return BoundController(c, np.array([plant.inputs.index(n) for n in c.actuates], dtype=int),
                           _measurement_function(plant, c.measurements), h, c.n_xc, method or "rk4",
                           _held_measurement_function(plant, c.measurements) if held else None,
                           _held_samples(held_dt, c, method, h), _held_order(held_order, method))


def _held_order(order, method: str | None) -> int:
    """The checked extrapolation order of the held part (0 unless method "rk4-held")."""
    from .held_carry import check_held_order

    from .held_multistep import HELD_METHODS

    order = check_held_order(order)
    if order and method not in HELD_METHODS:
        raise SimulationOptionError(f"held_order extrapolates the plant's held part between its evaluations; it needs "
                                    f"method='rk4-held' (or {HELD_METHODS[1:]}) (got {method!r}).")
    return order


def _held_samples(held_dt: float | None, c: DiscreteController, method: str | None, h: float | None) -> int:
    """Controller samples per evaluation of the held part (``held_dt`` / sample time), checked."""
    if held_dt is None:
        return 1
    from .held_multistep import HELD_METHODS

    if method not in HELD_METHODS:
        raise SimulationOptionError(f"held_dt holds the plant's held part over several controller samples; it needs "
                                    f"method='rk4-held' (or {HELD_METHODS[1:]}) (got {method!r}).")
    if not (isinstance(held_dt, (int, float)) and math.isfinite(held_dt) and held_dt > 0):
        raise SimulationOptionError(f"held_dt must be a positive number of seconds; got {held_dt!r}.")
    k = held_dt / c.dt
    if abs(k - round(k)) > 1e-9 * max(k, 1.0) or round(k) < 1:
        raise SimulationOptionError(f"held_dt = {held_dt:g} s must be a whole multiple of the controller's sample "
                                    f"time {c.dt:g} s (e.g. {c.dt:g}, {2 * c.dt:g}, {4 * c.dt:g} s).")
    if round(k) > 1 and h is not None and abs(h - c.dt) > 1e-12 * c.dt:
        raise SimulationOptionError(f"held_dt > the sample time needs one step per controller sample (dt = {c.dt:g} "
                                    f"s, or dt unset); got dt = {h:g} s.")
    return int(round(k))


def _held_measurement_function(plant, names: Sequence[str]) -> ca.Function:
    """``(x, u, p, z) -> y``: the measurements with the plant's held part ``z`` as an argument."""
    held = plant.held
    x, u, p = (ca.MX.sym(s, n) for s, n in (("x", plant.n_x), ("u", plant.n_u), ("p", plant.n_p)))
    z = ca.MX.sym("z", held.n_z)
    y_all = None
    if any(n in plant.output_names for n in names):
        if held.outputs is None:
            raise SimulationOptionError(f"the controller measures outputs of {plant.name!r}, whose held part has no "
                                        "outputs Function (HeldPart.outputs); use method 'rk4'.")
        y_all = _rows_of(held.outputs, [x, u, p, z])
    rows = [y_all[plant.output_names.index(n)] if n in plant.output_names else x[plant.states.index(n)]
            for n in names]
    y = ca.vertcat(*rows) if rows else ca.MX(0, 1)
    return _pruned(ca.Function(f"{plant.name}_held_measurements", [x, u, p, z], [y], ["x", "u", "p", "z"], ["y"]))


def _measurement_function(plant, names: Sequence[str]) -> ca.Function:
    x, u, p = (ca.MX.sym(s, n) for s, n in (("x", plant.n_x), ("u", plant.n_u), ("p", plant.n_p)))
    y_all = None
    if any(n in plant.output_names for n in names):
        y_all = _rows_of(plant.output_function, [x, u, p])
    rows = [y_all[plant.output_names.index(n)] if n in plant.output_names else x[plant.states.index(n)]
            for n in names]
    y = ca.vertcat(*rows) if rows else ca.MX(0, 1)
    return _pruned(ca.Function(f"{plant.name}_measurements", [x, u, p], [y], ["x", "u", "p"], ["y"]))


def _pruned(f: ca.Function) -> ca.Function:
    """``f`` expanded to scalar operations when it can be: only the operations the measured rows need remain (an
    MX call computes every output of the called Function: the NREL 5 MW's outputs call the whole right-hand side
    for the accelerations, which the speed, pitch and power channels do not read; the same arithmetic, ~1 µs
    instead of ~8 µs per sample). Kept as it is when it calls something that cannot be expanded (a lookup)."""
    try:
        return f.expand()
    except RuntimeError:
        return f


def _rows_of(f: ca.Function, args: list) -> ca.MX:
    """Every output of ``f`` at ``args``, stacked; an MX Function is inlined, so that a Function built from a
    few of the rows evaluates only what those rows need (a controller measures 5 of some 200 channels)."""
    inline = f.is_a("MXFunction")
    return ca.vertcat(*[ca.vec(v) for v in f.call(args, inline, False)])
