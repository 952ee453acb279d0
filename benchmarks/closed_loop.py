"""A discrete controller in the loop: one generated loop vs a Python law per sample (issue 12.5, general part).

Scene: paper45 (NREL 5 MW, tower FA1 + SS1 + free generator), 600 s. The rotor is driven by an aerodynamic
torque series RotTorq(t) = 2.1 MN m x (U(t) / 9 m/s)^2 with U(t) a reproducible sum of sinusoids around
9 m/s (a stand-in for a turbulent wind: this benchmark is about the loop, not aerodynamics), sampled every
0.05 s as a table (an exogenous input alongside the controller's). The controller, sampled at 100 Hz with
zero-order hold, low-pass filters the generator speed (first order, 0.25 Hz; its state) and sets the
generator torque GenTq = k w_f^2 (k = 2.332 N m s^2, the NREL 5 MW region-2 gain 0.0255764 N m/rpm^2),
limited to [0, 47.4 kN m].

Runs (integration wall time, the median of 3 after a warm-up; real-time factor = 600 s / wall):

- CasADi Function law, the accuracy-driven default (accuracy 1e-3), compiled from the disk cache:
  ``mapaccum`` over the 60 000 samples of (law + RK4 sub-steps); its time includes the step-doubling check;
- the same with ``method="rk4", dt=0.01`` (one RK4 step per sample), compiled and in the virtual machine;
- the same law as a Python callable ``law(t, xc, y)`` (a DISCON library would be called like this), with
  the plant's RK4 step compiled: one Python call per sample.

Accuracy: ε (benchmark metric, states) against the Function law with 16 sub-steps per sample.
Writes the ``closed_loop`` section of benchmarks/README.md. Run: ``python benchmarks/closed_loop.py``.
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

import casadi as ca
import numpy as np
from _report import write_section

from mbsym import codegen
from mbsym.simulate import DiscreteController, simulate
from mbsym.simulate.auto import epsilon

DECK = Path(__file__).resolve().parents[2] / "shared" / "openfast" / "cases" / "paper45_fa_ss_gen" / \
    "paper45_fa_ss_gen.fst"
TMAX, DT_C, GEAR, K_GEN, TQ_MAX = 600.0, 0.01, 97.0, 2.332, 47_403.0


def wind_torque():
    rng = np.random.default_rng(5)
    t = np.arange(0.0, TMAX + 0.05, 0.05)
    f = np.linspace(0.01, 1.0, 40)
    amp = 0.8 * f ** (-5 / 6) / np.sqrt(np.sum(f ** (-5 / 3)))            # a Kaimal-like decay, 0.8 m/s std
    u = 9.0 + np.sum(amp[:, None] * np.sin(2 * np.pi * f[:, None] * t[None, :] + rng.uniform(0, 2 * np.pi, 40)[:,
                                                                                                     None]), 0)
    return t, 2.1e6 * (u / 9.0) ** 2


def law():
    wf, w = ca.SX.sym("wf"), ca.SX.sym("w")
    a = np.exp(-2 * np.pi * 0.25 * DT_C)
    wf1 = a * wf + (1 - a) * GEAR * w
    return ca.Function("torque_law", [wf, w], [wf1, ca.fmin(ca.fmax(K_GEN * wf1 ** 2, 0.0), TQ_MAX)])


def run(model, ctrl, inputs, x0, **kw):
    simulate(model, TMAX, x0=x0, inputs=inputs, controller=ctrl, **kw)                     # prepare / warm up
    codegen.wait_for_background()
    res, walls = None, []
    for _ in range(3):
        res = simulate(model, TMAX, x0=x0, inputs=inputs, controller=ctrl, **kw)
        walls.append(res.statistics["integration_wall_s"])
    return res, statistics.median(walls)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    from mbsym.wind import read_openfast
    from mbsym.wind.structure.turbine import TurbineModel

    model = TurbineModel(read_openfast(DECK))
    t, q = wind_torque()
    inputs = {"RotTorq": (t, q)}
    x0 = {"GeAz_d": 1.0}
    f_law = law()

    def py_law(tk, xc, y):
        a, b = f_law(xc, y)
        return np.array(a).reshape(-1), np.array(b).reshape(-1)

    kw = dict(measurements=["GeAz_d"], actuates=["GenTq"], state_names=["GenSpeedF"])
    fn = DiscreteController(f_law, DT_C, [GEAR * 1.0], **kw)
    py = DiscreteController(py_law, DT_C, [GEAR * 1.0], **kw)
    t_out = np.round(np.arange(0.0, TMAX + 1e-9, 0.05), 10)
    ref = simulate(model, TMAX, x0=x0, inputs=inputs, controller=fn, method="rk4", dt=DT_C / 16, t_out=t_out,
                   compile=True)
    runs = [("Function law, default (accuracy 1e-3)", fn, {}),
            ("Function law, rk4 dt = 0.01 s, compiled", fn, {"method": "rk4", "dt": DT_C, "compile": True}),
            ("Function law, rk4 dt = 0.01 s, virtual machine", fn, {"method": "rk4", "dt": DT_C, "compile": False}),
            ("Python callable law, rk4 dt = 0.01 s, plant compiled", py, {"method": "rk4", "dt": DT_C,
                                                                          "compile": True})]
    lines = ["| run (paper45 + torque controller at 100 Hz, 600 s) | ε vs 16 sub-steps | integration [ms] | "
             "real-time factor | sub-steps per sample | compiled |", "|---|---:|---:|---:|---:|---|"]
    for label, ctrl, kw_run in runs:
        res, wall = run(model, ctrl, inputs, x0, t_out=t_out, **kw_run)
        s = res.statistics
        eps = epsilon(res.x, ref.x)
        lines.append(f"| {label} | {eps:.1e} | {1e3 * wall:.1f} | {TMAX / wall:.0f}x | {s['substeps']} | "
                     f"{s['compiled']} |")
        print(lines[-1], flush=True)
    final = ref.output("GenSpeedF")[-1] / GEAR
    text = "\n".join(lines) + (f"\n\n60 000 controller samples. The rotor settles near {final:.2f} rad/s "
                               f"(generator torque {ref.u[-1, ref.inputs.index('GenTq')] / 1e3:.1f} kN m). "
                               "The default's time includes its step-doubling check (here one run with two "
                               "sub-steps per sample, whose result is returned).")
    print("\n" + text)
    if not args.no_write:
        write_section("closed_loop", text)


if __name__ == "__main__":
    main()
