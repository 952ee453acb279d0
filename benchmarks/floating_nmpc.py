"""The NMPC on the floating IEA 15 MW in irregular waves against the baseline with ROSCO's floating feedback (issue 20, item 5).

Plant: mbsym's floating operating turbine of the shared ``fl_steady_13`` deck (rotor-effective rotor with DBEMT,
six platform DOFs, HydroDyn's radiation and first-order waves, MoorDyn's lines on their quasi-static shape) with a
JONSWAP sea (``--hs``, ``--tp``; the deck's seed) and AeroDyn's unsteady aerodynamics and tower influence off (what
the rotor-effective model holds; the same edit as ``floating_waves.py``), in a Kaimal hub wind (``--wind``,
``--ti``, ``--seed``). Controllers, each in the same wind and sea:

``baseline``        mbsym's ROSCO law with the deck's DISCON.IN (``Fl_Mode 2``: nacelle pitching feedback); it
                    equals the ROSCO 2.10.6 library to 1e-4 deg on this deck (docs/offshore.md §7).
``rosco``           the ROSCO 2.10.6 library itself (``libdiscon.so`` of the wheel, in the tests' cache
                    ``~/.cache/mbsym/rosco/2.10.6``) with the same DISCON.IN, called every sample.
``nmpc``            the product path (``mbsym simulate DECK --controller nmpc``): prediction model with the
                    platform's surge and pitch, EKF with the nacelle IMU and the platform's pitch and surge,
                    :meth:`NMPCTuning.floating` carried to the turbine.
``nmpc-land``       the same NMPC and EKF on a prediction model without the platform (GenDOF, TwFADOF1): the
                    NMPC the package had before.
``nmpc-ideal``      the platform NMPC with the plant's true state and wind (no estimator): the bound.

Prints, after ``--settle`` s, the platform's pitch and surge standard deviations, the tower-base fore-aft DEL
(``TwrBsMyt``, Wöhler exponent 4, rainflow), the rotor-speed RMS error about rated, the pitch-rate RMS, the energy,
the largest power and the fairlead-1 tension std, with ratios to the baseline, and each run's wall time.

    python benchmarks/floating_nmpc.py [--tmax 600] [--wind 13] [--ti 0.1] [--seed 1] [--hs 4] [--tp 10]
        [--controllers baseline,nmpc,nmpc-land,nmpc-ideal] [--plot FILE.png]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))
from floating_waves import deck  # noqa: E402  (the shared deck with the sea and the aerodynamic edits)

CONTROLLERS = ("baseline", "rosco", "nmpc", "nmpc-land", "nmpc-ideal")
CHANNELS = ("Wind1VelX", "Wave1Elev", "PtfmSurge", "PtfmPitch", "RotSpeed", "BldPitch1", "GenPwr", "TwrBsMyt",
            "FAIRTEN1")


def rainflow_del(x: np.ndarray, m: float, duration: float) -> float:
    """Damage-equivalent range over one second (1 Hz equivalent count) of ``x`` for Wöhler exponent ``m``
    (ASTM E1049 four-point rainflow on the turning points; half cycles for the residue)."""
    x = np.asarray(x, dtype=float)
    turning = [x[0]] + [x[i] for i in range(1, len(x) - 1) if (x[i] - x[i - 1]) * (x[i + 1] - x[i]) < 0] + [x[-1]]
    stack: list[float] = []
    ranges: list[tuple[float, float]] = []
    for p in turning:
        stack.append(p)
        while len(stack) >= 3:
            a, b = abs(stack[-1] - stack[-2]), abs(stack[-2] - stack[-3])
            if a < b:
                break
            if len(stack) == 3:
                ranges.append((b, 0.5))
                stack.pop(0)
            else:
                ranges.append((b, 1.0))
                last = stack.pop()
                del stack[-2:]
                stack.append(last)
    ranges += [(abs(stack[i + 1] - stack[i]), 0.5) for i in range(len(stack) - 1)]
    r, n = np.array(ranges).T
    return float((np.sum(n * r ** m) / duration) ** (1.0 / m))


def loop_for(kind: str, model, deck_, wind):
    """The :class:`~mbsym.wind.mpc.TurbineLoop` of a controller name (module docstring)."""
    from mbsym.cli.operate_mpc import MpcOptions
    from mbsym.wind.control.baseline import BaselineController
    from mbsym.wind.mpc import (NMPCTuning, PredictionModel, SetPoints, TurbineEstimator, TurbineLoop, TurbineNMPC,
                                estimation_model)
    from mbsym.wind.mpc.estimator import steady_estimate

    settings = deck_.baseline_settings()
    if kind == "baseline":
        return TurbineLoop(model, deck_.controller_dt, baseline=BaselineController(settings))
    if kind == "nmpc":
        return MpcOptions("nmpc", None, "ekf").loop(deck_, model, wind)
    setpoints = SetPoints.from_settings(settings, model.rotor)
    if kind == "nmpc-ideal":
        tuning = NMPCTuning(platform_pitch_rate_scale=5e-4).for_turbine(setpoints)
        return TurbineLoop(model, deck_.controller_dt, nmpc=TurbineNMPC(PredictionModel(model), setpoints,
                                                                         tuning=tuning), preview=0.0, wind=wind)
    observed = estimation_model(model)
    estimator = TurbineEstimator(observed, "ekf", x0=steady_estimate(observed, float(wind(0.0)), settings=settings))
    prediction = PredictionModel(model, dofs=("GenDOF", "TwFADOF1"))
    nmpc = TurbineNMPC(prediction, setpoints, tuning=NMPCTuning.estimated_wind().for_turbine(setpoints))
    return TurbineLoop(model, deck_.controller_dt, nmpc=nmpc, estimator=estimator, wind=wind)


def run(kind: str, fst: Path, args) -> tuple[dict[str, np.ndarray], float]:
    from mbsym.cli.operate import _initial_state
    from mbsym.wind.inflow import parse_wind_spec
    from mbsym.wind.mpc import simulate_with_loop
    from mbsym.wind.operation.deck import operating_deck

    t0 = time.perf_counter()
    d = operating_deck(fst)
    model = d.model(aero="rotor")
    wind = parse_wind_spec(f"kaimal:{args.wind:g}:{args.ti:g}:{args.seed}", duration=args.tmax)
    if kind == "rosco":
        return _rosco(d, model, wind, args), time.perf_counter() - t0
    loop = loop_for(kind, model, d, wind)
    res = simulate_with_loop(model, wind, args.tmax, loop, x0=_initial_state(model, d, wind))
    names, y = list(res.output_names), np.asarray(res.y)
    out = {"Time": np.asarray(res.t)} | {n: y[:, names.index(n)] for n in CHANNELS}
    return out, time.perf_counter() - t0


def _rosco(d, model, wind, args) -> dict[str, np.ndarray]:
    """The ROSCO library in the loop of the same plant (``mbsym simulate DECK --controller discon``)."""
    from mbsym.cli.operate import _initial_state
    from mbsym.wind.control.discon import DisconController
    from mbsym.wind.operation.controllers import discon_in_loop
    from mbsym.wind.operation.simulation import simulate_turbine

    library, infile = d.discon_paths()
    handle = DisconController(library, infile, dt=d.controller_dt, n_blades=d.turbine.number_of_blades)
    try:
        res = simulate_turbine(model, wind, args.tmax, controller=discon_in_loop(handle, model=model),
                               x0=_initial_state(model, d, wind))
    finally:
        handle.close()
    names, y = list(res.output_names), np.asarray(res.y)
    return {"Time": np.asarray(res.t)} | {n: y[:, names.index(n)] for n in CHANNELS}


def metrics(s: dict[str, np.ndarray], settle: float, rated_rpm: float) -> dict[str, float]:
    keep = s["Time"] >= settle - 1e-9
    t = s["Time"][keep]
    dt, duration = float(t[1] - t[0]), float(t[-1] - t[0])
    pitch_rate = np.diff(s["BldPitch1"][keep]) / dt
    return {"platform pitch std [deg]": s["PtfmPitch"][keep].std(),
            "platform surge std [m]": s["PtfmSurge"][keep].std(),
            "tower-base FA DEL [kN m]": rainflow_del(s["TwrBsMyt"][keep], 4.0, duration),
            "speed RMS error [rpm]": float(np.sqrt(np.mean((s["RotSpeed"][keep] - rated_rpm) ** 2))),
            "pitch-rate RMS [deg/s]": float(np.sqrt(np.mean(pitch_rate ** 2))),
            "energy [MWh]": float(np.sum(s["GenPwr"][keep]) * dt / 3.6e6),
            "max power [MW]": float(s["GenPwr"][keep].max() / 1e3),
            "fairlead 1 tension std [kN]": s["FAIRTEN1"][keep].std() / 1e3}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--tmax", type=float, default=600.0)
    p.add_argument("--settle", type=float, default=100.0)
    p.add_argument("--wind", type=float, default=13.0)
    p.add_argument("--ti", type=float, default=0.1)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--hs", type=float, default=4.0)
    p.add_argument("--tp", type=float, default=10.0)
    p.add_argument("--controllers", default=",".join(CONTROLLERS))
    p.add_argument("--plot", type=Path, default=None)
    args = p.parse_args()
    kinds = [k.strip() for k in args.controllers.split(",") if k.strip()]
    unknown = sorted(set(kinds) - set(CONTROLLERS))
    if unknown:
        sys.exit(f"--controllers: unknown {unknown}; choose from {list(CONTROLLERS)}")
    warnings.simplefilter("ignore")
    with tempfile.TemporaryDirectory() as tmp:
        fst = deck(Path(tmp), args.hs, args.tp, args.tmax, Path.home() / ".cache" / "mbsym" / "rosco" / "2.10.6")
        from mbsym.wind.operation.deck import operating_deck

        rated = operating_deck(fst).baseline_settings().pitch_reference_speed * 30 / np.pi
        series, walls = {}, {}
        for kind in kinds:
            series[kind], walls[kind] = run(kind, fst, args)
            print(f"{kind}: {walls[kind]:.1f} s wall for {args.tmax:g} s", flush=True)
    table = {k: metrics(s, args.settle, rated) for k, s in series.items()}
    ref = table.get("baseline")
    print(f"\nIEA 15 MW on VolturnUS-S, Kaimal {args.wind:g} m/s TI {args.ti:g} seed {args.seed}, JONSWAP Hs {args.hs:g} m "
          f"Tp {args.tp:g} s, {args.settle:g}-{args.tmax:g} s (ratio to the baseline in brackets)")
    print(f"{'measure':30s}" + "".join(f"{k:>20s}" for k in table))
    for name in next(iter(table.values())):
        cells = "".join(f"{v[name]:11.4g} ({v[name] / ref[name]:5.2f})" if ref else f"{v[name]:20.4g}"
                        for v in table.values())
        print(f"{name:30s}{cells}")
    print(f"{'wall time [s]':30s}" + "".join(f"{walls[k]:20.1f}" for k in table))
    if args.plot is not None:
        _plot(series, args)


def _plot(series: dict[str, dict[str, np.ndarray]], args) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = ("PtfmPitch", "RotSpeed", "BldPitch1", "TwrBsMyt")
    fig, axes = plt.subplots(len(rows), 1, sharex=True, figsize=(10, 9))
    for kind, s in series.items():
        for ax, name in zip(axes, rows):
            ax.plot(s["Time"], s[name], lw=0.8, label=kind)
    for ax, name, unit in zip(axes, rows, ("deg", "rpm", "deg", "kN m")):
        ax.set_ylabel(f"{name} [{unit}]")
        ax.grid(alpha=0.3)
    axes[0].legend(ncol=len(series), fontsize=8)
    axes[0].set_title(f"IEA 15 MW on VolturnUS-S: Kaimal {args.wind:g} m/s, JONSWAP Hs {args.hs:g} m Tp {args.tp:g} s "
                      "(mbsym plant)")
    axes[-1].set_xlabel("time [s]")
    fig.tight_layout()
    fig.savefig(args.plot, dpi=110)
    print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
