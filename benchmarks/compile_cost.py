"""What compiling costs and when it pays: the numbers behind the compilation policy of simulate's default.

For the RK4 steps of the work-precision scenes (paper45, paper46, stiff_rotor) and paper45's mapped output
channels (a block of 256 output times), in one run:

- serialized size [kB] and the estimate of ``mbsym.codegen.estimate_compile_seconds`` (its calibration);
- the cold compilation (C generation + gcc -O1) in an empty cache directory, and the load of that library
  from the disk cache as a new process does it (cache key from the serialized Function, then dlopen);
- one step (one block) in CasADi's virtual machine and compiled, timed through ``Function.buffer()``;
- the break-even: how many default runs of the scene (the step count the accuracy-driven default picks at
  accuracy 1e-3, plus its step-doubling check) pay for one compilation.

The policy (``mbsym/simulate/auto.py``): compiled when the library is cached; compiled at once when the run in
the virtual machine would cost more than compiling; otherwise the virtual machine, with a background
compilation when that run exceeds 10 ms. Writes the ``compile_cost`` section of benchmarks/README.md.

Run: ``python benchmarks/compile_cost.py [--no-write]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time

import numpy as np
from _report import write_section

from mbsym import codegen
from mbsym.simulate import simulate
from mbsym.simulate.base import Problem, prepared
from mbsym.simulate.fixed import RK4
from mbsym.simulate.inputs import input_signal
from mbsym.simulate.model import OUTPUT_BLOCK, _mapped_block, plant_of

from work_precision import build_scene


def per_call(f, args, repeat: int = 200) -> float:
    """Median wall time of one buffered call of ``f`` [s]."""
    outs = [np.empty(f.numel_out(i)) for i in range(f.n_out())]
    arrays = [np.ascontiguousarray(np.broadcast_to(a, (f.numel_in(i),)), dtype=float).copy()
              for i, a in enumerate(args)]
    buf, trigger = f.buffer()
    for i, a in enumerate(arrays):
        buf.set_arg(i, memoryview(a))
    for i, o in enumerate(outs):
        buf.set_res(i, memoryview(o))
    walls = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        trigger()
        walls.append(time.perf_counter() - t0)
    return statistics.median(walls)


def measure(label: str, f, args, calls_per_run: float) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        cold = codegen.compile_function(f, directory=tmp)
        t0 = time.perf_counter()
        g = f.deserialize(f.serialize())                    # a new Function object: no in-process key memo
        warm = codegen.compile_function(g, directory=tmp)
        load = time.perf_counter() - t0
        vm, compiled = per_call(f, args), per_call(warm.function, args)
    run_vm, run_c = vm * calls_per_run, compiled * calls_per_run
    return {"label": label, "kB": len(f.serialize()) / 1e3, "estimate": codegen.estimate_compile_seconds(f),
            "cold": cold.wall_s, "load": load, "vm": vm, "compiled": compiled, "run_vm": run_vm, "run_c": run_c,
            "break_even": cold.wall_s / max(run_vm - run_c - load, 1e-12) if run_vm > run_c + load else float("inf"),
            "ok": cold.compiled and warm.cache_hit}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    rows = []
    for name in ("paper45", "paper46", "stiff_rotor"):
        scene = build_scene(name)
        t_out = np.round(np.arange(0.0, scene.tmax + 0.01, 0.02), 10)
        res = simulate(scene.model, scene.tmax, scene.x0, t_out=t_out, compile=False)     # the default's choice
        steps = res.statistics["steps"] + res.statistics.get("check_steps", 0)
        plant = plant_of(scene.model)
        x0 = plant.default_x if scene.x0 is None else scene.x0
        sig = input_signal(dict(plant.default_u) or None, plant.inputs, scene.tmax)
        prob = Problem(plant, x0, plant.parameter_vector(None), sig, t_out, scene.tmax, dt=res.statistics["dt"],
                       n_steps=1)
        step = RK4(prob).symbolic_step()
        U = np.repeat(sig.at(0.0)[:, None], 3, axis=1).reshape(-1, order="F")
        rows.append(measure(f"{name}: RK4 step ({res.statistics['method']}, {steps} steps per default run)",
                            step, [x0, U, prob.p, [res.statistics['dt']]], steps))
        if name == "paper45":
            block = prepared(plant.owner, ("bench block",), lambda: _mapped_block(plant.output_function,
                                                                                    OUTPUT_BLOCK))[0]
            X = np.tile(x0, OUTPUT_BLOCK)
            Uo = np.tile(sig.at(0.0), OUTPUT_BLOCK)
            P = np.tile(prob.p, OUTPUT_BLOCK)
            rows.append(measure(f"{name}: output channels, {OUTPUT_BLOCK} times per call ({t_out.size} outputs)",
                                block, [X, Uo, P], t_out.size / OUTPUT_BLOCK))
        print(rows[-1], flush=True)
    lines = ["| Function | serialized [kB] | compile estimate [s] | cold compile [s] | load from disk [ms] | "
             "one call VM / compiled [µs] | per default run VM / compiled [ms] | runs to pay one compilation |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        lines.append(f"| {r['label']} | {r['kB']:.0f} | {r['estimate']:.2f} | {r['cold']:.2f} | {1e3 * r['load']:.1f} | "
                     f"{1e6 * r['vm']:.1f} / {1e6 * r['compiled']:.2f} | {1e3 * r['run_vm']:.2f} / "
                     f"{1e3 * r['run_c']:.2f} | {r['break_even']:.0f} |")
    text = "\n".join(lines) + (f"\n\nMachine load (1-min average, 2 cores): {os.getloadavg()[0]:.1f}. "
                               "Load from disk = cache key (serializing the Function) + dlopen, what a new process "
                               "pays; the runs to pay one compilation = cold compile / (VM run − compiled run − load).")
    print("\n" + text)
    if not args.no_write:
        write_section("compile_cost", text)


if __name__ == "__main__":
    main()
