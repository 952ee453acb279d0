"""Cost of one controller sample of the blade-element turbine in its compiled closed loop, rk4, rk4-held, abm4-held.

The ``ff14_flex`` deck's blade-element model (NREL 5 MW, 15 DOFs, 3 x 19 AeroDyn nodes with DBEMT) with mbsym's
baseline controller (ROSCO's DISCON.IN) in the loop, as :func:`mbsym.wind.operation.simulate_turbine` runs it:
the generated closed-loop body (measurement, control law, one RK4 step, outputs) compiled with the default
flags, called through ``Function.buffer``; CPU time of this process (``time.process_time``: the machine's 2
cores are shared, wall time measures the neighbours), median of 7 batches. Methods:

* ``rk4``: the blade-element aerodynamics evaluated in every RK4 stage, in the measurement and afterwards for
  the channels;
* ``rk4-held``: the aerodynamics evaluated once per step (OpenFAST's coupling), every sample or,
  with ``held_dt`` ("aerodynamics every"), every few samples while the controller and the structure keep the
  sample time, and in between held or extrapolated through the last evaluations (``held_order``; the default
  for this deck, InterpOrder 2: quadratic, every 8 samples, 50 ms: 4 deg of rotor rotation); the same
  evaluation gives the measurements and, at the output times, every channel;
* ``abm4-held`` (the default for this deck, its ElastoDyn ``Method`` 3) and ``ab4-held``: ElastoDyn's
  Adams-Bashforth-Moulton 4 / Adams-Bashforth 4 instead of the RK4 step (2 / 1 right-hand sides per step after
  three RK4 start-up steps), the aerodynamics as ``rk4-held``'s default.

Costs per sample: "held" (the aerodynamics held or extrapolated), "fresh" (evaluated), "with the channels"
(evaluated, and every output channel). The projection to the 660 s case counts each kind: the channels every
50 ms (where the aerodynamics are evaluated too), the aerodynamics every interval. Baseline in the same run:
the rotor-effective model of the same deck (rigid-blade DOFs) at 6.25 ms. ``blade_validation.py`` measures
whole runs (its "run CPU" column) and their accuracy.

    python benchmarks/blade_loop_speed.py [--no-write]
    BLADE_LOOP_VARIANTS=4,7 python benchmarks/blade_loop_speed.py --no-write     (rows 4 and 7 of VARIANTS only)
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _report import write_section  # noqa: E402
from blade_speed import flex_deck, per_call_us  # noqa: E402

INPUTS = next((p / "shared" / "openfast" / "aero" / "openfast_inputs" for p in HERE.parents
               if (p / "shared" / "openfast" / "aero").is_dir()), None)
T_CASE, DT_OUT = 660.0, 0.05
#: (method, controller sample = step [s], interval of the aerodynamics [s] or None: every sample, extrapolation order)
VARIANTS = (("rk4", 0.00625, None, 0), ("rk4-held", 0.00625, None, 0), ("rk4-held", 0.00625, 0.025, 0),
            ("rk4-held", 0.00625, 0.025, 2), ("rk4-held", 0.00625, 0.05, 2), ("rk4-held", 0.0125, None, 0),
            ("rk4-held", 0.025, None, 0), ("abm4-held", 0.00625, 0.05, 2), ("ab4-held", 0.00625, 0.05, 2))


def cpu_us(f, args) -> float:
    """Median CPU time of one call [µs] (the process's time: the wall clock measures the neighbours)."""
    return per_call_us(f, args, n=200, clock=time.process_time)


def sample_costs(model, method: str, dt: float, wind: dict, held_dt=None, order: int = 0) -> tuple[dict, float]:
    """CPU µs of one sample that holds the aerodynamics ("held"), evaluates them ("fresh") and also returns every
    channel ("output"), and the compile time [s] of the body (rk4: "fresh" is the sample, "output" adds the
    channels evaluated afterwards)."""
    from mbsym.simulate.base import maybe_compile
    from mbsym.simulate.closed_loop import _ClosedLoop
    from mbsym.simulate.controller import bind_controller
    from mbsym.simulate.inputs import input_signal
    from mbsym.simulate.model import plant_of
    from mbsym.wind.control.baseline import BaselineController
    from mbsym.wind.operation.controllers import baseline_in_loop

    ctrl = baseline_in_loop(BaselineController.from_discon(INPUTS / "deck" / "DISCON.IN", dt=dt))
    dyn = model.dynamics() if method != "rk4" else model.measurement_dynamics()
    plant = plant_of(dyn)
    bc = bind_controller(ctrl, plant, method, None, T_CASE, held_dt=held_dt, held_order=order)
    x0 = dyn.state_vector(model.initial_state(wind))
    sig = input_signal({**dict(zip(dyn.inputs, dyn.u0)), **wind}, plant.inputs, T_CASE)
    loop = _ClosedLoop(bc, plant, x0, dyn.parameter_vector(), sig, T_CASE)
    loop.end_derivative = False           # the output times (every 50 ms) are sample starts
    t0 = time.perf_counter()
    body, _ = maybe_compile(loop.body(1), True)
    compile_s = time.perf_counter() - t0
    z = loop.initial_carry(1)
    U = np.repeat(sig.at(0.0)[:, None], 3, axis=1)
    p = dyn.parameter_vector()
    if body.numel_in(3) == 1:          # rk4: every channel evaluated afterwards at the output times
        from mbsym import codegen

        full = model.dynamics()
        outputs = codegen.compile_function(full.outputs).function
        c = cpu_us(body, (z, U, p, [dt]))
        return {"held": c, "fresh": c, "output": c + cpu_us(outputs, (x0, full.input_vector(wind), p))}, compile_s
    if body.numel_in(3) == 2:          # every sample evaluates them
        c = cpu_us(body, (z, U, p, [dt, 0.0]))
        return {"held": c, "fresh": c, "output": cpu_us(body, (z, U, p, [dt, 1.0]))}, compile_s
    for _ in range(4):                 # a history to extrapolate from (and, multistep: past the RK4 start-up)
        z = np.array(body(z, U, p, [dt, 0.0, 1.0])[0]).ravel()
    return {"held": cpu_us(body, (z, U, p, [dt, 0.0, 0.0])), "fresh": cpu_us(body, (z, U, p, [dt, 0.0, 1.0])),
            "output": cpu_us(body, (z, U, p, [dt, 1.0, 1.0]))}, compile_s


def projected_cpu(costs: dict, dt: float, every: int) -> float:
    """CPU [s] of the 660 s case: samples of ``dt`` [s], the aerodynamics every ``every`` samples, the channels
    every 50 ms (where the aerodynamics are evaluated too)."""
    k = np.arange(int(round(T_CASE / dt)))
    out = k % max(int(round(DT_OUT / dt)), 1) == 0
    fresh = (k % every == 0) & ~out
    held = ~(out | fresh)
    return float(out.sum() * costs["output"] + fresh.sum() * costs["fresh"] + held.sum() * costs["held"]) * 1e-6


def main() -> None:
    no_write, deck = flex_deck(__doc__.splitlines()[0])
    base = replace(deck, inflow=None).model(aero="rotor", dofs=("GenDOF", "TwFADOF1", "TwSSDOF1"))
    b0, _ = sample_costs(base, "rk4", 0.00625, {"Wind1VelX": 14.0})
    blade = deck.model(aero="blade")
    rows = [("rotor-effective, rigid (baseline)", "rk4", 0.00625, None, 0, b0, 0.0)]
    import os

    only = os.environ.get("BLADE_LOOP_VARIANTS")         # e.g. "4,7,8": rows of VARIANTS (from 0)
    for i, (method, dt, held_dt, order) in enumerate(VARIANTS):
        if only and str(i) not in only.split(","):
            continue
        costs, comp = sample_costs(blade, method, dt, {"WindTime": 30.0}, held_dt, order)
        rows.append(("blade-element, ff14_flex DOFs", method, dt, held_dt, order, costs, comp))
        print(rows[-1], flush=True)
    table = ["| model | method | step = controller sample [ms] | aerodynamics every [ms] (in between) | CPU per "
             "sample [µs]: held / fresh / with the channels | mean per sample [µs] | vs baseline | 660 s case, "
             "projected CPU [s] | faster than real time |",
             "|---|---|---:|---|---|---:|---:|---:|---:|"]
    base_cpu = projected_cpu(b0, 0.00625, 1)
    for label, method, dt, held_dt, order, c, _ in rows:
        every = int(round((held_dt or dt) / dt))
        cpu = projected_cpu(c, dt, every)
        mean = cpu / (T_CASE / dt) * 1e6
        how = "stage" if method == "rk4" else f"{1e3 * (held_dt or dt):g} ({('held', 'linear', 'quadratic')[order]})"
        table.append(f"| {label} | {method} | {1e3 * dt:g} | {how} | {c['held']:.0f} / {c['fresh']:.0f} / "
                     f"{c['output']:.0f} | {mean:.0f} | {cpu / base_cpu:.0f}× | {cpu:.1f} | {T_CASE / cpu:.0f}× |")
    text = "\n".join(table)
    print(text)
    if not no_write:
        write_section("blade-loop-speed", text)


if __name__ == "__main__":
    main()
