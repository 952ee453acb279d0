"""The turbine NMPC's step, generated and Python-driven, against acados SQP-RTI on the same OCP (issue 21, item 4).

The OCP is the one ``mbsym export-discon --controller nmpc`` exports for the built-in NREL 5 MW: the
:class:`~mbsym.wind.mpc.TurbineNMPC` on the default prediction model (generator, first tower fore-aft mode,
dynamic inflow, pitch and torque as rate-driven states: 7 states, 2 controls, N = 40, 0.1 s, RK4),
:meth:`NMPCTuning.estimated_wind` (the estimated wind held over the horizon, the steady references of that wind).
Three solvers, each one Gauss–Newton real-time iteration per 0.1 s sample, on the same closed-loop scene (the
prediction model as plant, RK4 with 10 sub-steps; Kaimal 14 m/s TI 16 % seed 3 hub wind, the current wind
given to the controller):

``generated``   the exported library's step: the generated parts of ``sample_functions(...)`` (the QP by
                CasADi's ``qrqp`` warm-started from the previous sample's multipliers, at most 10 iterations)
                and the library's own C sequence (``discon_nmpc.RTI_PART``), compiled with the export's
                flags (gcc -O2) and called through ctypes;
``python``      ``TurbineNMPC.step`` (compiled preparation, CasADi's hpipm interface, Python around it);
``acados``      acados SQP-RTI (partial-condensing HPIPM) on the same transcription (our residuals as
                ``NONLINEAR_LS``, our bounds as ``BGH``, acados' ERK with the same RK4 sub-steps), run by a
                Python with acados (``--acados-python``; see ``benchmarks/README.md`` for
                ``comma-deps-acados`` and why it needs its own virtual environment with CasADi 3.8).

Prints each solver's step wall time (median, 99th percentile, max after the first step) and the tracking
(RMS generator-speed error, pitch-rate RMS), then the ratio of medians to acados'.

    python benchmarks/nmpc_acados.py [--steps 300] [--acados-python PATH]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))


def scene():
    """``(nmpc, estimator, x0, wind)``: the exported OCP of the built-in NREL 5 MW and the closed-loop scene."""
    from mbsym.wind.inflow import parse_wind_spec
    from mbsym.wind.mpc import (NMPCTuning, PredictionModel, SetPoints, TurbineEstimator, TurbineNMPC,
                                estimation_model, reference_state)
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.nrel5mw import nrel5mw_baseline_settings

    model = OperatingTurbine.nrel5mw()
    setpoints = SetPoints.from_settings(nrel5mw_baseline_settings(), model.rotor)
    prediction = PredictionModel(model)
    nmpc = TurbineNMPC(prediction, setpoints, tuning=NMPCTuning.estimated_wind().for_turbine(setpoints))
    estimator = TurbineEstimator(estimation_model(model), "ekf", compile=False)
    wind = np.asarray(parse_wind_spec("kaimal:14:0.16:3", duration=120.0)(np.arange(0.0, 120.0, 0.1)), dtype=float)
    x0 = reference_state(prediction, setpoints, float(wind[0]))
    return nmpc, estimator, x0, wind


class Plant:
    """The prediction model's control form, RK4 with 10 sub-steps per 0.1 s sample."""

    def __init__(self, nmpc) -> None:
        from mbsym.control.discretize import discretize

        self.dyn = nmpc.prediction.control
        self.step_f = discretize(self.dyn.rhs, nmpc.dt, substeps=10).step
        self.p = self.dyn.parameter_vector()
        self.speed = self.dyn.output_names.index("GenSpeed")

    def step(self, x: np.ndarray, wind: float, rates: np.ndarray) -> np.ndarray:
        return np.asarray(self.step_f(x, [], np.concatenate([[wind], rates]), self.p), dtype=float).ravel()

    def gen_speed(self, x: np.ndarray, wind: float) -> float:
        return float(self.dyn.output_value(x, [wind, 0.0, 0.0])[self.speed])


def _loop(solve, nmpc, x0, wind, steps: int) -> dict:
    """Run ``solve(k, x, wind) -> rates`` in the scene; wall times of each call."""
    plant = Plant(nmpc)
    x, walls, speed, rates_seen = x0.copy(), [], [], []
    ref = nmpc.setpoints.rated_generator_speed * 30 / np.pi
    for k in range(steps):
        t0 = time.perf_counter()
        rates = np.asarray(solve(k, x, float(wind[k])), dtype=float).ravel()
        walls.append(time.perf_counter() - t0)
        x = plant.step(x, float(wind[k]), rates)
        speed.append(plant.gen_speed(x, float(wind[k + 1])) - ref)
        rates_seen.append(rates[0])
    w = np.array(walls[1:])
    return {"median_ms": 1e3 * float(np.median(w)), "p99_ms": 1e3 * float(np.percentile(w, 99)),
            "max_ms": 1e3 * float(w.max()), "first_ms": 1e3 * walls[0],
            "speed_rms_rpm": float(np.sqrt(np.mean(np.square(speed[10:])))),
            "pitch_rate_rms_deg_s": float(np.degrees(np.sqrt(np.mean(np.square(rates_seen[10:])))))}


def run_python(steps: int) -> dict:
    nmpc, _, x0, wind = scene()
    return _loop(lambda k, x, u: nmpc.step(x, u), nmpc, x0, wind, steps)


#: The benchmark's C driver around the library's own RTI_PART (mbsym.wind.mpc.discon_nmpc): the step as the
#: exported library runs it, called through ctypes.
DRIVER = r"""
#include <string.h>
typedef long long int casadi_int;
int nmpc_qp_data(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int nmpc_qp(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int nmpc_finish(const double** arg, double** res, casadi_int* iw, double* w, int mem);
int nmpc_startup(const double** arg, double** res, casadi_int* iw, double* w, int mem);
#define NW {n_w}
#define NLAM {n_lam}
static const double *narg[{n_arg}];
static double *nres[{n_res}];
static casadi_int niw[{n_iw}];
static double nw[{n_work}];
static const double SETTINGS[] = {{{settings}}};
{rti_part}
__attribute__((visibility("default"))) int bench_rti(const double *w, const double *z, double pitch, double torque,
        const double *lam, double *w_next, double *rates, double *viol, double *lam_next)
{{ return rti_parts(w, z, pitch, torque, SETTINGS, 0, lam, w_next, rates, viol, lam_next); }}
__attribute__((visibility("default"))) int bench_startup(const double *z, double pitch, double torque,
        double *w_next, double *rates, double *viol, double *lam_next)
{{
    narg[0] = z; narg[1] = &pitch; narg[2] = &torque; narg[3] = SETTINGS;
    nres[0] = w_next; nres[1] = rates; nres[2] = viol; nres[3] = lam_next;
    return nmpc_startup(narg, nres, niw, nw, 0);
}}
"""


def run_generated(steps: int) -> dict:
    import ctypes
    import tempfile

    import casadi as ca

    from mbsym.codegen import compiler_command
    from mbsym.wind.control.discon_export import _compile
    from mbsym.wind.mpc import sample_functions
    from mbsym.wind.mpc.discon_nmpc import rti_part

    nmpc, estimator, x0, wind = scene()
    t0 = time.perf_counter()
    fns = sample_functions(nmpc, estimator, estimator.dt)
    gens = (fns.qp_data, fns.qp, fns.finish, fns.startup)
    folder = Path(tempfile.mkdtemp(prefix="mbsym_rti_"))
    cg = ca.CodeGenerator("rti_gen.c", {"with_header": False, "with_export": False, "casadi_int": "long long int",
                                        "casadi_real": "double"})
    for f in gens:
        cg.add(f)
    cg.generate(str(folder) + os.sep)
    (folder / "driver.c").write_text(DRIVER.format(
        n_w=fns.n_w, n_lam=fns.n_lam, n_arg=max(g.sz_arg() for g in gens), n_res=max(g.sz_res() for g in gens),
        n_iw=max(max(g.sz_iw() for g in gens), 1), n_work=max(g.sz_w() for g in gens), rti_part=rti_part(fns),
        settings=", ".join(repr(float(v)) for v in fns.layout.exported)))
    _compile(compiler_command(), [folder / "rti_gen.c", folder / "driver.c"], folder / "rti.so")  # the export's flags
    lib = ctypes.CDLL(str(folder / "rti.so"))
    build = time.perf_counter() - t0
    states = nmpc.prediction.control.states
    w, lam = np.zeros(fns.n_w), np.zeros(fns.n_lam)
    w_next, lam_next, rates, viol = np.zeros(fns.n_w), np.zeros(fns.n_lam), np.zeros(2), np.zeros(1)
    ptr = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))          # noqa: E731
    started = [False]

    def solve(k, x, u):
        values = dict(zip(states, x)) | {"Wind1VelX": u}
        z = np.array([values.get(n, 0.0) for n in estimator.names])      # the estimate = the plant's state
        pitch, torque = ctypes.c_double(values["BlPitch"]), ctypes.c_double(values["GenTq"])
        if started[0]:
            r = lib.bench_rti(ptr(w), ptr(z), pitch, torque, ptr(lam), ptr(w_next), ptr(rates), ptr(viol),
                              ptr(lam_next))
        else:
            r = lib.bench_startup(ptr(z), pitch, torque, ptr(w_next), ptr(rates), ptr(viol), ptr(lam_next))
        if r != 0 or viol[0] > 1e-6:
            raise RuntimeError(f"the generated step failed at sample {k} (code {r}, violation {viol[0]:.3g})")
        started[0] = True
        w[:], lam[:] = w_next, lam_next
        return rates.copy()

    return {**_loop(solve, nmpc, x0, wind, steps), "build_s": build}


def run_acados(steps: int) -> dict:
    from control_general import acados_solver

    nmpc, _, x0, wind = scene()
    tr = nmpc.nmpc.transcription
    t0 = time.perf_counter()
    solver = acados_solver(tr, nmpc.prediction.control, x0, "turbine_nmpc")
    build = time.perf_counter() - t0
    P, pv = tr.problem, np.asarray(nmpc.nmpc._p, dtype=float)
    internal: list[float] = []

    def solve(k, x, u):
        w = np.full(P.N + 1, u)
        refs = {name: nmpc.references(name.split(":")[-1], w) for name in nmpc._tracked}
        D = tr.stage_parameters({"Wind1VelX": w}, refs)
        for j in range(P.N + 1):
            solver.set(j, "p", np.concatenate([D[:, j], pv]))
        solver.set(0, "lbx", x)
        solver.set(0, "ubx", x)
        for _ in range(1 if k else 30):               # the first step iterates from the cold start
            solver.solve()
        internal.append(solver.get_stats("time_tot"))
        return solver.get(0, "u")[: tr.n_controls]

    result = _loop(solve, nmpc, x0, wind, steps)
    return {**result, "build_s": build, "internal_median_ms": 1e3 * float(np.median(internal[1:]))}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--acados-python", default=os.environ.get("MBSYM_ACADOS_PYTHON"))
    ap.add_argument("--worker", choices=("python", "generated", "acados"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        print(json.dumps({"python": run_python, "generated": run_generated, "acados": run_acados}[args.worker](
            args.steps)))
        return
    results = {}
    for name in ("generated", "python", "acados"):
        python = args.acados_python if name == "acados" else sys.executable
        if python is None:
            print("acados: no --acados-python given; skipped")
            continue
        env = {**os.environ, "PYTHONPATH": str(HERE.parent)}
        proc = subprocess.run([python, __file__, "--worker", name, "--steps", str(args.steps)], capture_output=True,
                              text=True, env=env)
        if proc.returncode:
            print(f"{name} failed: {proc.stderr.strip()[-800:]}")
            continue
        results[name] = json.loads(proc.stdout.strip().splitlines()[-1])
    print(f"\nTurbine NMPC step (NREL 5 MW, 7 states, N = 40, one RTI per sample), {args.steps} steps, "
          f"load {os.getloadavg()[0]:.1f}")
    print(f"{'solver':12s} {'median ms':>10s} {'p99 ms':>8s} {'max ms':>8s} {'first ms':>9s} {'speed RMS rpm':>14s} "
          f"{'pitch rate deg/s':>17s} {'build s':>8s}")
    for name, r in results.items():
        print(f"{name:12s} {r['median_ms']:10.3f} {r['p99_ms']:8.3f} {r['max_ms']:8.3f} {r['first_ms']:9.2f} "
              f"{r['speed_rms_rpm']:14.3f} {r['pitch_rate_rms_deg_s']:17.3f} "
              f"{r.get('build_s', float('nan')):8.1f}")
    if "acados" in results:
        print(f"acados inside its C solve (time_tot; the rest is its Python setting 41 stages' parameters): "
              f"{results['acados']['internal_median_ms']:.3f} ms median")
        for name in ("generated", "python"):
            if name in results:
                print(f"ratio of medians {name} / acados: {results[name]['median_ms'] / results['acados']['median_ms']:.2f}")


if __name__ == "__main__":
    main()
