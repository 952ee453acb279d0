"""AeroDyn's tower on the blade-element turbine: what its potential flow and drag do to the loads.

The shared ``steady_8`` deck (NREL 5 MW, steady 8 m/s, generator and first tower modes) runs twice on the
blade-element rung: as written (its AeroDyn has the tower off) and with the tower of its AeroDyn table switched on
(``TowerAero``: potential flow as ``TwrPotent = 1``, drag as ``TwrAero = True``; a deck asking for them gets
this by default). The script prints, from 20 s on, blade 1's root flap moment by azimuth (the dip as the blade
passes in front of the tower, at 180°) and the mean tower-base moment with the drag's share.

Run: ``python examples/tower_influence.py [DECK.fst] [--tmax 40]`` (default ``../shared/openfast/aero`` next to the
repository; each model compiles once, ~1 minute). The last line is JSON. docs/blade_aero.md §5 has the model and
its checks against OpenFAST.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

import mbsym as mb
from mbsym.wind.aero.tower import TowerAero
from mbsym.wind.control import BaselineController
from mbsym.wind.deck.aerodyn import read_aerodyn
from mbsym.wind.operation.controllers import baseline_in_loop
from mbsym.wind.operation.deck import operating_deck
from mbsym.wind.operation.simulation import simulate_turbine, wind_at_start

SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "openfast" / "aero" / "openfast_inputs"


def run(fst: Path, tower, tmax: float) -> dict:
    """``RootMyc1`` [kN m] by 20° of azimuth and the mean ``TwrBsMyt`` [kN m] after 20 s."""
    model = mb.wind.OperatingTurbine.from_openfast(fst, aero="blade", tower_aero=tower)
    controller = baseline_in_loop(BaselineController.from_discon(fst.parent.parent / "deck" / "DISCON.IN",
                                                                 dt=0.00625), model=model)
    ic = model.turbine.initial_conditions
    field = operating_deck(fst).inflow.field()                        # the deck's InflowWind (steady 8 m/s)
    x0 = model.initial_state(wind_at_start(model, field), rotor_speed=ic.rotor_speed, pitch=float(ic.blade_pitch[0]))
    res = simulate_turbine(model, field, tmax, x0=x0, controller=controller, t_out=np.arange(0.0, tmax + 1e-9, 0.05))
    late = np.asarray(res.t) >= 20.0
    azimuth = np.mod(np.asarray(res.output("Azimuth"))[late], 360.0)
    root = np.asarray(res.output("RootMyc1"))[late]                 # OpenFAST units: kN m
    bins = np.digitize(azimuth, np.arange(0.0, 361.0, 20.0)) - 1
    return {"root_by_azimuth": [float(root[bins == k].mean()) for k in range(18)],
            "TwrBsMyt": float(np.mean(np.asarray(res.output("TwrBsMyt"))[late]))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("deck", nargs="?", default=str(SHARED / "steady_8" / "steady_8.fst"))
    parser.add_argument("--tmax", type=float, default=40.0)
    args = parser.parse_args()
    fst = Path(args.deck)
    aerodyn = read_aerodyn(mb.wind.read_openfast(fst).source_files["aerodyn"], n_blades=3)
    tower = TowerAero(aerodyn.tower_elevation, aerodyn.tower_diameter, aerodyn.tower_drag, aerodyn.tower_ti,
                      potential=1, drag=True)
    off, on = run(fst, None, args.tmax), run(fst, tower, args.tmax)
    dip = {k: 0.5 * (r["root_by_azimuth"][8] + r["root_by_azimuth"][10]) - r["root_by_azimuth"][9]
           for k, r in (("without", off), ("with", on))}
    print("RootMyc1 by azimuth [kN m], 20° bins (180-200° is the tower passage):")
    for name, r in (("without the tower", off), ("with the tower", on)):
        print(f"  {name:18s}" + " ".join(f"{v:6.0f}" for v in r["root_by_azimuth"]))
    print(f"dip at the tower: {dip['without']:.0f} -> {dip['with']:.0f} kN m; mean TwrBsMyt "
          f"{off['TwrBsMyt']:.0f} -> {on['TwrBsMyt']:.0f} kN m (+{on['TwrBsMyt'] - off['TwrBsMyt']:.0f}: the drag)")
    print(json.dumps({"dip_kNm": dip, "TwrBsMyt_kNm": {"without": off["TwrBsMyt"], "with": on["TwrBsMyt"]}}))


if __name__ == "__main__":
    main()
