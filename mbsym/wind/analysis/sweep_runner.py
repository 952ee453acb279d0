"""The closed-loop case of a wind sweep, as a picklable runner for :func:`mbsym.sweep` (``run=callable``).

:class:`ClosedLoopRunner` holds the operating turbine's CasADi Functions **serialized**
(``Function.serialize()``: the rhs, the controllers' measurements, the OpenFAST channels, the
baseline controller's law), names, defaults and settings: plain data, built once in the calling
process. The sweep ships it once per worker (the engine's callable plan); the first case in a
worker deserializes the Functions (:meth:`ClosedLoopRunner.prepared`, once per process) and
every case reuses them, so nothing is derived or rebuilt per case.

A case's own numbers travel with it (:class:`WindCase`, computed in the calling process): the
wind specification (parsed in the worker: a Kaimal seed gives the same series everywhere), the
initial state (the deck's initial conditions or the steady-state guess, with the case's
parameters), the parameter vector. Every executor therefore evaluates the same Functions on the
same numbers: the same case gives the same results bit for bit.

Integration is the closed loop of :func:`mbsym.wind.operation.simulate_turbine` with explicit
choices (nothing depends on timing or on the disk cache's state): one RK4 step per controller
sample, ``compile`` decided once per sweep; ``controller="none"`` holds the initial commands and
runs the same fixed step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["WindCase", "ClosedLoopRunner", "CASE_KEY"]

#: Key of the hidden per-case setting that carries a :class:`WindCase` (removed from the table).
CASE_KEY = "__mbsym_wind_case__"

#: Prepared runners of this process, by runner key (deserialized Functions, controllers).
_PREPARED: dict[str, Any] = {}


@dataclass(frozen=True)
class WindCase:
    """The numbers of one wind case: wind spec, initial state, parameters (or why it cannot run)."""

    wind: str
    x0: np.ndarray | None
    p: np.ndarray | None
    failure: BaseException | None = None


@dataclass
class ClosedLoopRunner:
    """``run(case) -> {column: value}`` of one closed-loop case (see the module docstring).

    Attributes
    ----------
    functions : dict of str
        Serialized ``rhs``, ``measurements``, ``channels`` and (baseline) ``law`` Functions.
    names : dict of tuple
        ``states``, ``inputs``, ``parameters``, ``measurements`` (the measured channels),
        ``law_measurements`` (the baseline law's), ``measurement_units``, ``channels``, ``channel_units``,
        controller ``state_names``, ``actuates``.
    controller : dict
        ``kind`` (baseline, discon, none), ``dt`` [s], ``x0`` (baseline state), DISCON ``library``,
        ``input`` and ``n_blades``.
    tmax, dt_out : float
        Simulated time and output spacing [s].
    compile : bool
        Generated C for the loop and the channels (decided once per sweep).
    channels, del_channels, wohler : tuple
        Channels summarized (mean, std, max, min), channels with damage-equivalent loads and
        the Wöhler exponents (:func:`mbsym.sweep.channel_statistics`).
    key : str
        Identity of the prepared Functions in a worker.
    """

    functions: dict
    names: dict
    controller: dict
    tmax: float
    dt_out: float
    compile: bool
    channels: tuple = ()
    del_channels: tuple = ()
    wohler: tuple = (10.0,)
    key: str = field(default="")

    def __post_init__(self) -> None:
        if not self.key:
            import hashlib

            h = hashlib.sha1()
            for k in sorted(self.functions):
                h.update(self.functions[k].encode())
            h.update(repr((sorted(self.names.items()), sorted((k, str(v)) for k, v in self.controller.items()),
                           self.compile)).encode())
            self.key = h.hexdigest()

    # ------------------------------------------------------------------ worker side
    def prepared(self) -> dict:
        """Deserialized Functions, Dynamics and controller of this process (built on the first case)."""
        got = _PREPARED.get(self.key)
        if got is None:
            got = _PREPARED[self.key] = self._prepare()
        return got

    def _prepare(self) -> dict:
        import casadi as ca

        from ...dynamics import Dynamics
        from ...simulate.controller import DiscreteController

        f = {k: ca.Function.deserialize(v) for k, v in self.functions.items()}
        n = self.names
        common = dict(states=n["states"], inputs=n["inputs"], parameters=n["parameters"], name="sweep_turbine",
                      state_units=n.get("state_units"), input_units=n.get("input_units"))
        meas = Dynamics(f["rhs"], outputs=f["measurements"], output_names=n["measurements"],
                        output_units=n["measurement_units"], **common)
        full = Dynamics(f["rhs"], outputs=f["channels"], output_names=n["channels"], output_units=n["channel_units"],
                        **common)
        c = self.controller
        law = None
        if c["kind"] == "baseline":
            law = DiscreteController(f["law"], c["dt"], c["x0"], measurements=n["law_measurements"],
                                     actuates=n["actuates"], state_names=n["controller_states"], name="baseline")
        return {"measured": meas, "full": full, "law": law}

    def __call__(self, case):
        from ...exceptions import SweepError

        wc = case.settings.get(CASE_KEY) if hasattr(case, "settings") else None
        if not isinstance(wc, WindCase):
            raise SweepError("a wind-sweep case lost its numbers (internal error): run it through sweep_turbine.")
        if wc.failure is not None:
            raise wc.failure
        return self.summary(self.run(wc))

    def summary(self, res) -> dict:
        """Statistics (and DELs) of the channels of one run, on its output grid."""
        from ...sweep import channel_statistics

        cols = dict(zip(res.output_names, np.asarray(res.y).T))
        return channel_statistics(np.asarray(res.t), cols, channels=self.channels, del_channels=self.del_channels,
                                  wohler=self.wohler)

    def run(self, wc: WindCase):
        """Simulate one case; a :class:`~mbsym.simulate.SimulationResult` whose outputs are the channels."""
        from ...simulate.api import simulate
        from ..inflow import parse_wind_spec

        prep = self.prepared()
        wind = parse_wind_spec(wc.wind, duration=self.tmax)
        n = self.names
        x = dict(zip(n["states"], wc.x0))
        inputs = {"Wind1VelX": wind, "BlPitchCom": float(x["BlPitch"]), "GenTqCom": float(x["GenTq"])}
        t_out = _output_times(self.tmax, self.dt_out)
        p = dict(zip(n["parameters"], wc.p))
        c = self.controller
        handle = None
        controller = prep["law"]
        if c["kind"] == "discon":
            from ..control.discon import DisconController
            from ..operation.controllers import SI_FACTORS, discon_in_loop

            handle = DisconController(c["library"], c["input"], dt=c["dt"], n_blades=c["n_blades"])
            # every channel the plant measures that has a swap record (23 GenTq, 53 YawBrTAxp as ServoDyn fills them)
            controller = discon_in_loop(handle, measurements=[m for m in n["measurements"] if m in SI_FACTORS])
        try:
            res = simulate(prep["measured"] if controller is not None else prep["full"], self.tmax, x0=wc.x0,
                           inputs=inputs, p=p, controller=controller, method="rk4", dt=c["dt"], t_out=t_out,
                           compile=self.compile)
        finally:
            if handle is not None:
                handle.close()
        return self._with_channels(res, prep["full"], wc.p) if controller is not None else res

    def _with_channels(self, res, full, p_vec):
        """``res`` with the OpenFAST channels (evaluated from the states afterwards) as its outputs."""
        import dataclasses

        from ...simulate.model import evaluate_outputs

        Y = evaluate_outputs(full, full.outputs, np.asarray(res.x), np.asarray(res.u), np.asarray(p_vec, float),
                             self.compile)
        return dataclasses.replace(res, y=Y, output_names=tuple(full.output_names),
                                   output_units=tuple(full.output_units))


def _output_times(tmax: float, dt_out: float) -> np.ndarray:
    """``0, dt_out, ...`` up to ``tmax`` (included), as ``mbsym simulate`` spaces its outputs."""
    n = int(math.floor(tmax / dt_out + 1e-9))
    t = np.round(np.arange(n + 1) * dt_out, 12)
    if t[-1] < tmax - 1e-9:
        t = np.append(t, tmax)
    return t
