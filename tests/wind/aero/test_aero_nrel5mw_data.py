"""The packaged NREL 5 MW aerodynamics must be exactly what the shared AeroDyn deck gives.

This module is also the generator of ``mbsym/wind/deck/data/nrel5mw_aerodyn.json`` and
``mbsym/wind/deck/data/Cp_Ct_Cq.NREL5MW_mbsym.txt``::

    PYTHONPATH=. python tests/wind/aero/test_aero_nrel5mw_data.py --write

Fact source: the AeroDyn 15 files of the NREL 5 MW deck used for the shared OpenFAST runs
(``shared/openfast/aero/openfast_inputs/deck``; ROSCO 2.10.6 ``Examples/Test_Cases/NREL-5MW``,
the OpenFAST r-test 5MW_Baseline aerodynamics) and the ElastoDyn geometry of the built-in
NREL 5 MW (hub radius, precone, tilt).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

if __package__ in (None, ""):  # run as a script: make "tests.wind.aero" importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[3]))
    from tests.wind.aero.conftest import AERODYN_MAIN, need  # noqa: E402
else:
    from .conftest import AERODYN_MAIN, need

from mbsym.wind import nrel5mw
from mbsym.wind.aero import BEMRotor, nrel5mw_bem_rotor, nrel5mw_rotor, performance_surface
from mbsym.wind.deck.aerodyn import AeroDynInput, read_aerodyn
from mbsym.wind.deck.nrel5mw_aero import (
    AERODYN_DATA, PERFORMANCE_DATA, nrel5mw_aerodyn, nrel5mw_performance_table,
)
from mbsym.wind.deck.performance import read_performance_table, write_performance_table

DATA = Path(__file__).resolve().parents[3] / "mbsym" / "wind" / "deck"
SOURCE = {
    "definition": ("J. Jonkman, S. Butterfield, W. Musial, G. Scott, 'Definition of a 5-MW "
                   "Reference Wind Turbine for Offshore System Development', NREL/TP-500-38060, "
                   "National Renewable Energy Laboratory, 2009 (Table 2-1: blade aerodynamic "
                   "properties; DU/NACA64 polars with AirfoilPrep rotational and Viterna "
                   "corrections)"),
    "deck": ("AeroDyn 15 files of the NREL 5 MW deck of ROSCO 2.10.6 Examples/Test_Cases/"
             "NREL-5MW (the OpenFAST r-test 5MW_Baseline aerodynamics), as used for the shared "
             "OpenFAST v5 reference runs"),
    "files": ["NRELOffshrBsline5MW_Onshore_AeroDyn15.dat", "NRELOffshrBsline5MW_AeroDyn_blade.dat",
              "Airfoils/Cylinder1.dat", "Airfoils/Cylinder2.dat", "Airfoils/DU40_A17.dat",
              "Airfoils/DU35_A17.dat", "Airfoils/DU30_A17.dat", "Airfoils/DU25_A17.dat",
              "Airfoils/DU21_A17.dat", "Airfoils/NACA64_A17.dat"],
    "generated_by": "tests/wind/aero/test_aero_nrel5mw_data.py",
    "units": "SI: m, rad; airfoil polars: AoA in rad, Reynolds number absolute",
}
DECIMALS = 10  # of the packaged Cp/Ct/Cq values


def generate_aerodyn(main: Path) -> dict:
    """The JSON document of the AeroDyn input of ``main`` (file names relative)."""
    aerodyn = read_aerodyn(main)
    data = aerodyn.to_dict()
    data["source"] = Path(main).name
    for blade in data["blades"]:
        blade["source"] = Path(blade["source"]).name
    for polar in data["airfoils"]:
        polar["source"] = "Airfoils/" + Path(polar["source"]).name
    return json.loads(json.dumps({"_source": SOURCE, "aerodyn": data}))


def generate_rotor(main: Path) -> BEMRotor:
    params = nrel5mw()
    return BEMRotor.from_aerodyn(read_aerodyn(main), hub_radius=params.hub_radius,
                                 precone=params.precone[0], n_blades=params.number_of_blades,
                                 shaft_tilt=params.shaft_tilt)


def write(main: Path) -> None:
    (DATA / AERODYN_DATA).write_text(json.dumps(generate_aerodyn(main), indent=1) + "\n",
                                     encoding="utf-8")
    table = performance_surface(generate_rotor(main))
    write_performance_table(table, DATA / PERFORMANCE_DATA, turbine_name="NREL-5MW (mbsym BEM)",
                            decimals=DECIMALS)


@pytest.fixture(scope="module")
def main_file() -> Path:
    return need(AERODYN_MAIN)


def test_packaged_aerodyn_json_matches_the_deck(main_file):
    # Reference: the shared AeroDyn deck itself; exact equality (JSON floats round-trip).
    packaged = json.loads((DATA / AERODYN_DATA).read_text(encoding="utf-8"))
    assert packaged == generate_aerodyn(main_file), (
        f"{AERODYN_DATA} is stale; regenerate with "
        "'PYTHONPATH=. python tests/wind/aero/test_aero_nrel5mw_data.py --write'")


def test_nrel5mw_aerodyn_equals_reading_the_deck(main_file):
    assert nrel5mw_aerodyn() == read_aerodyn(main_file)
    assert isinstance(nrel5mw_aerodyn(), AeroDynInput)


@pytest.mark.slow
def test_packaged_surface_matches_a_fresh_bem_run(main_file, tmp_path):
    # Reference: mbsym's BEM on the shared deck, written with the same 10 decimals; the
    # packaged file must match to the last written digit (5e-11).
    fresh = performance_surface(generate_rotor(main_file))
    path = write_performance_table(fresh, tmp_path / "fresh.txt", decimals=DECIMALS)
    packaged = nrel5mw_performance_table()
    again = read_performance_table(path)
    for name in ("cp", "ct", "cq"):
        np.testing.assert_allclose(getattr(packaged, name), getattr(again, name), rtol=0,
                                   atol=2e-10)


def test_packaged_surface_spot_check_against_bem(main_file):
    # A cheap version of the check above, for the default run: 3 grid nodes recomputed.
    packaged = nrel5mw_performance_table()
    rotor = generate_rotor(main_file)
    picks = [(24, 5), (26, 13), (10, 30)]  # (tsr index, pitch index)
    from mbsym.wind.aero import solve_bem
    sol = solve_bem(rotor, [packaged.tsr[i] for i, _ in picks], [packaged.pitch[j] for _, j in picks])
    for k, (i, j) in enumerate(picks):
        assert abs(sol.cp[k] - packaged.cp[i, j]) < 1e-9
        assert abs(sol.ct[k] - packaged.ct[i, j]) < 1e-9


def test_builtin_rotor_needs_no_deck():
    # Works without ../shared: package data only. Published NREL 5 MW facts (Jonkman et al.
    # 2009): 63 m tip radius, 2.5 deg precone -> in-plane radius 63 cos(2.5 deg) = 62.94 m;
    # peak Cp of the aerodynamic rotor about 0.48-0.49 near TSR 7.5 (AeroDyn 0.487 here).
    bem = nrel5mw_bem_rotor()
    assert abs(bem.radius - 63.0 * np.cos(np.radians(2.5))) < 1e-3
    rotor = nrel5mw_rotor()
    table = rotor.table
    assert table.tsr[0] == 1.0 and table.tsr[-1] == 16.0
    assert 0.48 < table.cp.max() < 0.50
    np.testing.assert_allclose(table.cq, table.cp / table.tsr[:, None], rtol=1e-9, atol=1e-10)


def test_source_entry_names_definition_and_files():
    source = json.loads((DATA / AERODYN_DATA).read_text(encoding="utf-8"))["_source"]
    assert "NREL/TP-500-38060" in source["definition"]
    assert "NRELOffshrBsline5MW_AeroDyn_blade.dat" in source["files"]
    text = (DATA / PERFORMANCE_DATA).read_text().splitlines()[0]
    assert "NREL-5MW" in text


if __name__ == "__main__":
    if "--write" not in sys.argv:
        raise SystemExit("usage: PYTHONPATH=. python tests/wind/aero/test_aero_nrel5mw_data.py "
                         "--write")
    write(need(AERODYN_MAIN) if AERODYN_MAIN.exists() else AERODYN_MAIN)
    print(f"wrote {DATA / AERODYN_DATA} and {DATA / PERFORMANCE_DATA}")
