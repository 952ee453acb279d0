"""Tower modes of the operating NREL 5 MW, mbsym vs OpenFAST's own linearization, per inflow choice (issue 22,
item 6).

mbsym: the operating turbine with GenDOF, TwFADOF1, TwSSDOF1 (rigid blades) trimmed at each wind speed and
linearized with ``inflow="dynamic"``, ``"frozen"`` and ``"quasi-steady"``, on both aerodynamic rungs:

* ``rotor``: the built-in NREL 5 MW (rotor-effective surfaces, rotor-averaged DBEMT; thrust along the shaft,
  no side force) with the disk's moment against tilt and yaw rates and its in-plane force (``disk_moments``: the
  model ``mbsym linearize`` linearizes since 2026-11-29), :func:`mbsym.wind.analysis.trim_linear.linearize_point`;
  ``rotor, no disk moment``: the same without it (the time-simulation default on land);
* ``blade`` (``--blade``, ~10 min per wind speed): the shared steady-state deck of that speed with
  blade-element BEM and DBEMT per node, periodic point over 12 azimuths, MBC and average
  (:func:`mbsym.wind.analysis.blade_linear.blade_linear_model`), held pitch and torque of the rotor trim.

OpenFAST: tests/data/openfast_linear_inflow/modes.json (made by ``openfast_linear_inflow.py``): frozen wake
(``DBEMT_Mod = -1``) and quasi-steady BEM (``DBEMT_Mod = 0``). Like for like: mbsym's ``frozen`` with
``-1``, ``quasi-steady`` with ``0``; mbsym's ``dynamic`` is shown against the frozen reference too (OpenFAST's
continuous DBEMT, ``DBEMT_Mod = 3``, was not run). Targets: frequencies within 1 %, damping ratios within
0.5 points.

    python benchmarks/linear_inflow.py [--blade] [--write]

``--write`` puts the table into benchmarks/README.md (section ``linear-inflow``); the blade-element results
are cached in benchmarks/figures/linear_inflow_blade.json (``--blade`` recomputes them).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
from _report import shared_aero, write_section  # noqa: E402

TABLE = HERE.parent / "tests" / "data" / "openfast_linear_inflow" / "modes.json"
BLADE_CACHE = HERE / "figures" / "linear_inflow_blade.json"
CHOICES = ("dynamic", "frozen", "quasi-steady")
MODES = ("1st tower fore-aft", "1st tower side-side")
DOFS = ["GenDOF", "TwFADOF1", "TwSSDOF1"]


def reference() -> dict:
    """``{(inflow, U): {label: (freq_hz, damping_ratio)}}`` of the OpenFAST table."""
    table = json.loads(TABLE.read_text())
    return {(c["inflow"], c["wind_speed"]): {k: (v["freq_hz"], v["damping_ratio"]) for k, v in c["modes"].items()}
            for c in table["cases"]}


def rotor_modes(speeds, disk_moments: bool = True) -> dict:
    """``{(inflow, U): {label: (freq_hz, damping_ratio)}}`` of the rotor-effective rung."""
    from mbsym.wind.analysis.operating_points import operating_points
    from mbsym.wind.analysis.trim_linear import mode_label
    from mbsym.wind.operation import OperatingTurbine, SteadyControl

    ops = operating_points(OperatingTurbine.nrel5mw(disk_moments=disk_moments), speeds, SteadyControl.nrel5mw())
    out = {}
    for inflow in CHOICES:
        for point, lin in zip(ops, ops.linearize(inflow=inflow)):
            out[(inflow, point.wind_speed)] = {mode_label(m): (m.freq_hz, m.damping_ratio) for m in lin.modes()
                                               if mode_label(m) in MODES}
    return out


def blade_modes(speeds) -> dict:
    """The same for the blade-element rung (module docstring), cached in :data:`BLADE_CACHE`."""
    import mbsym as mb
    from mbsym.wind.analysis.blade_linear import blade_linear_model, labelled_modes
    from mbsym.wind.analysis.blade_periodic import periodic_point
    from mbsym.wind.operation import trim

    out = _cached_blade()
    for U in speeds:
        t0 = time.perf_counter()
        fst = shared_aero() / "openfast_inputs" / f"steady_{U:g}" / f"steady_{U:g}.fst"
        start = trim(mb.wind.OperatingTurbine.from_openfast(fst, aero="rotor", dofs=DOFS), U)
        model = mb.wind.OperatingTurbine.from_openfast(fst, aero="blade", dofs=DOFS)
        point = periodic_point(model, U, start=start)
        for inflow in CHOICES:
            lin = blade_linear_model(model, point, outputs=(), keep_azimuth=True, inflow=inflow)
            labels, f, z = labelled_modes(lin)
            out[(inflow, U)] = {lab: (float(fk), float(zk)) for lab, fk, zk in zip(labels, f, z) if lab in MODES}
        print(f"blade-element rung at {U:g} m/s: {time.perf_counter() - t0:.0f} s", flush=True)
        BLADE_CACHE.parent.mkdir(exist_ok=True)
        BLADE_CACHE.write_text(json.dumps([{"inflow": k[0], "wind_speed": k[1], "modes": v}
                                           for k, v in sorted(out.items())], indent=1))
    return out


def _cached_blade() -> dict:
    if not BLADE_CACHE.exists():
        return {}
    return {(c["inflow"], c["wind_speed"]): {k: tuple(v) for k, v in c["modes"].items()}
            for c in json.loads(BLADE_CACHE.read_text())}


def table(ref: dict, rungs: dict) -> str:
    """Markdown: per rung, inflow, wind speed and mode, mbsym vs OpenFAST (like for like where run)."""
    lines = ["| rung | mbsym inflow | OpenFAST DBEMT_Mod | U [m/s] | mode | f mbsym [Hz] | f OpenFAST [Hz] | Δf [%] "
             "| ζ mbsym [%] | ζ OpenFAST [%] | Δζ [points] |", "|" + "---|" * 11]
    for rung, modes in rungs.items():
        for (inflow, U), by_label in sorted(modes.items(), key=lambda kv: (CHOICES.index(kv[0][0]), kv[0][1])):
            ref_inflow = inflow if (inflow, U) in ref else "frozen"
            other = ref.get((ref_inflow, U))
            if other is None:
                continue
            dbemt = {"frozen": -1, "quasi-steady": 0, "dynamic": 3}[ref_inflow]
            for label in MODES:
                if label not in by_label or label not in other:
                    continue
                (f, z), (fo, zo) = by_label[label], other[label]
                lines.append(f"| {rung} | {inflow} | {dbemt} | {U:g} | {label[4:]} | {f:.4f} | {fo:.4f} | "
                             f"{100 * (f / fo - 1):+.2f} | {100 * z:.2f} | {100 * zo:.2f} | {100 * (z - zo):+.2f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--blade", action="store_true", help="recompute the blade-element rung (~10 min per speed)")
    ap.add_argument("--write", action="store_true", help="write the table into benchmarks/README.md")
    args = ap.parse_args(argv)
    ref = reference()
    speeds = sorted({U for _, U in ref})
    t0 = time.perf_counter()
    rungs = {"rotor": rotor_modes(speeds)}
    rotor_s = time.perf_counter() - t0
    rungs["rotor, no disk moment"] = rotor_modes(speeds, disk_moments=False)
    blade = blade_modes(speeds) if args.blade else _cached_blade()
    if blade:
        rungs["blade"] = blade
    text = table(ref, rungs)
    print(text)
    print(f"\nrotor-effective rung: {len(speeds)} trims and {3 * len(speeds)} linear models in {rotor_s:.1f} s")
    if args.write:
        speeds_b = ", ".join(f"{U:g}" for U in sorted({U for _, U in blade}))
        note = (f"Run: `python benchmarks/linear_inflow.py --write` (rotor-effective rung {rotor_s:.0f} s on a "
                "shared 2-core machine)" + (f"; blade-element rung at {speeds_b} m/s from {BLADE_CACHE.name} "
                                            "(`--blade` recomputes it: ~30 min per wind speed on the loaded "
                                            "machine)" if blade else "") + ". OpenFAST: "
                "tests/data/openfast_linear_inflow (frozen wake DBEMT_Mod = -1, quasi-steady BEM 0). Targets: "
                "|Δf| ≤ 1 %, |Δζ| ≤ 0.5 points. The rotor-effective rung has no rotor side force: its side-side "
                "damping is the structure's and its in-plane force's. Its disk's moment against the tilt rate "
                "(docs/operation.md) is what brings its fore-aft damping to OpenFAST's; without it (the "
                "time-simulation default on land) it is 1.3-1.9 points low.")
        write_section("linear-inflow", "## Operating linear models vs OpenFAST's linearization, per inflow "
                                       "choice (`linear_inflow.py`)\n\n" + note + "\n\n" + text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
