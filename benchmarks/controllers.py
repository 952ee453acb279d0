"""Controller cost per call: the ROSCO 2.10.6 DISCON library through ctypes vs our baseline Function.

The NREL 5 MW ``DISCON.IN`` of ``shared/openfast/aero`` (VS_ControlMode 2 with the EKF wind-speed
estimator, set-point smoother, peak shaving), fed the first 10 s of OpenFAST's measurements of the
10 → 14 m/s step every 0.00625 s (1600 calls). Rows:

- ``DisconController.step``: the library through our bridge (dict of measurements in, dict out);
- ``DISCON raw ctypes``: the same library calls with the swap array written directly (no dicts):
  the cost of the library plus one ctypes call;
- ``baseline Function, Python loop``: ``function(x, y)`` called once per step from Python (VM);
- ``baseline mapaccum (VM)`` and ``(compiled)``: 256 steps per CasADi call (``chunk_function``), the
  way a compiled simulation loop would evaluate it; compiled = generated C, gcc -O1 (mbsym.codegen);
- the compiled Function called once per step from Python.

Accuracy column: max |Δpitch| [deg] and |Δtorque| [N m] of each row's commands against the library's
over the same calls. Times are CPU times of this (single-threaded) process, best of ``--repeat`` runs
[µs per controller step] — wall time on the shared 2-core machine swings 3x with the other users; ratios are
against the ``DisconController.step`` row of the same run. Figures go to benchmarks/README.md
(section ``controllers``) with ``--write``. Needs the ROSCO wheel (fetched into a cache like the
tests do) and ../shared; exits with a message otherwise.

Run: ``python benchmarks/controllers.py [--repeat 3] [--write]``.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from mbsym.codegen import compile_function
from mbsym.wind.control import BaselineController, DisconController

HERE = Path(__file__).resolve().parent
DT, STEPS = 0.00625, 1600


def _load(name: str):
    path = HERE.parent / "tests" / "wind" / "control" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"_bench_{name}", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def _best(fn, repeat: int):
    """Best CPU time per step [µs] over ``repeat`` runs; ``fn()`` returns (CPU seconds of its timed part, commands)."""
    best, out = float("inf"), None
    for _ in range(repeat):
        seconds, out = fn()
        best = min(best, seconds)
    return best / STEPS * 1e6, out


def _cpu():
    return time.process_time()      # CPU time of this process: robust on a shared, loaded machine


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--write", action="store_true", help="write the table to benchmarks/README.md")
    args = parser.parse_args()
    sys.path.insert(0, str(HERE.parent / "tests" / "wind" / "control"))
    rosco, data, meas = _load("_rosco"), _load("_ctrl_data"), _load("_measurements")
    lib = rosco.rosco_library()
    csv, discon = data.AERO / "step_10_14.csv", data.DECK / "DISCON.IN"
    if lib is None or not csv.is_file():
        raise SystemExit("needs the ROSCO 2.10.6 wheel (pip download) and ../shared/openfast/aero")
    t, y = meas.openfast_measurements(csv, DT, t_end=(STEPS - 1) * DT)
    names = BaselineController.measurement_names

    def bridge():
        out = np.empty((STEPS, 2))
        with DisconController(lib, discon, dt=DT) as c:     # loading, copying and the init call: not timed
            u = c.step(t[0], dict(zip(names, y[0])))
            out[0] = u["BlPitchCom1"], u["GenTqCom"]
            t0 = _cpu()
            for k in range(1, STEPS):
                u = c.step(t[k], dict(zip(names, y[k])))
                out[k] = u["BlPitchCom1"], u["GenTqCom"]
            return (_cpu() - t0) * STEPS / (STEPS - 1), out

    def raw():
        out = np.empty((STEPS, 2))
        with DisconController(lib, discon, dt=DT) as c:
            u = c.step(t[0], dict(zip(names, y[0])))          # initialization call through the bridge
            out[0] = u["BlPitchCom1"], u["GenTqCom"]
            h = c._handle                                      # then the bare library call per step
            swap, rec = h.swap, [19, 20, 3, 14, 26]            # 0-based records 20, 21, 4, 15, 27
            swap[0] = 1.0
            t0 = _cpu()
            for k in range(1, STEPS):
                swap[1] = t[k]
                swap[rec] = y[k]
                h.call()
                out[k] = swap[41], swap[46]
            return (_cpu() - t0) * STEPS / (STEPS - 1), out

    ctrl = BaselineController.from_discon(discon, dt=float(np.float32(DT)))
    f = ctrl.function

    def python_loop(fun):
        def run():
            x, out = ctrl.x0, np.empty((STEPS, 2))
            t0 = _cpu()
            for k in range(STEPS):
                x, u = fun(x, y[k])
                out[k] = np.asarray(u).ravel()
            return _cpu() - t0, out
        return run

    def chunked(compiled):
        def run():
            t0 = _cpu()
            out = ctrl.run(y, compiled=compiled)[0]
            return _cpu() - t0, out
        return run

    t0 = time.perf_counter()
    ctrl.chunk_function(compiled=True)
    compiled_step = compile_function(f).function
    compile_time = time.perf_counter() - t0
    ctrl.chunk_function()                                  # build the VM chunk before timing
    rows = [("DisconController.step (ROSCO via ctypes)", bridge),
            ("DISCON raw ctypes call (ROSCO)", raw),
            ("baseline Function, Python loop (VM)", python_loop(f)),
            ("baseline Function, Python loop (compiled)", python_loop(compiled_step)),
            ("baseline mapaccum x256 (VM)", chunked(False)),
            ("baseline mapaccum x256 (compiled)", chunked(True))]
    results = [(label, *_best(fn, args.repeat)) for label, fn in rows]
    reference_time, reference = results[0][1], results[0][2]
    lines = ["### Controllers: ROSCO 2.10.6 through ctypes vs our baseline Function (benchmarks/controllers.py)", "",
             f"Controller cost per step, NREL 5 MW DISCON.IN, {STEPS} steps of dt = {DT} s "
             f"(CPU time, best of {args.repeat}; {platform.processor() or platform.machine()}, shared 2-core machine, "
             f"load average {os.getloadavg()[0]:.1f} during the run). "
             f"Compiling the step and the 256-step chunk: {compile_time:.1f} s (once, disk-cached).", "",
             "| row | CPU µs / step | ratio to the bridge | max dpitch [deg] | max dtorque [N m] |",
             "|---|---|---|---|---|"]
    for label, us, out in results:
        dp = np.max(np.abs(np.rad2deg(out[:, 0] - reference[:, 0])))
        dq = np.max(np.abs(out[:, 1] - reference[:, 1]))
        lines.append(f"| {label} | {us:.2f} | {reference_time / us:.1f}x | {dp:.1e} | {dq:.1e} |")
    table = "\n".join(lines)
    print(table)
    if args.write:
        sys.path.insert(0, str(HERE))
        from _report import write_section
        write_section("controllers", table)


if __name__ == "__main__":
    main()
