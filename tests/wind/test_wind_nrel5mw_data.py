"""The packaged NREL 5 MW data must be exactly what the shared base deck gives.

This module is also the generator of ``mbsym/wind/deck/data/nrel5mw.json``::

    PYTHONPATH=. python tests/wind/test_wind_nrel5mw_data.py --write

The deck (``../shared/openfast/NREL5MW``, OpenFAST v5 ElastoDyn-only NREL 5 MW
onshore) is the fact source; the test regenerates the JSON from it and compares
it with the packaged file, so the data stays honest.
"""

from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from mbsym.wind import TurbineParameters, nrel5mw, read_openfast

PACKAGED = Path(__file__).resolve().parents[2] / "mbsym" / "wind" / "deck" / "data" / "nrel5mw.json"

SOURCE = {
    "definition": ("J. Jonkman, S. Butterfield, W. Musial, G. Scott, 'Definition of a 5-MW "
                   "Reference Wind Turbine for Offshore System Development', NREL/TP-500-38060, "
                   "National Renewable Energy Laboratory, 2009 (onshore variant)"),
    "deck": ("OpenFAST v5 ElastoDyn-only base deck (values from welib "
             "data/NREL5MW/onshore/NREL5MW_ED_Onshore.dat, rewritten in the v5 layout)"),
    "files": ["NREL5MW_Onshore_ElastoDynOnly.fst", "NREL5MW_ElastoDyn_Onshore.dat",
              "NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat", "NRELOffshrBsline5MW_Blade.dat"],
    "generated_by": "tests/wind/test_wind_nrel5mw_data.py",
    "units": ("SI: m, kg, s, N; angles in rad, rotational speeds in rad/s, damping ratios and "
              "gearbox efficiency as fractions; distributed properties unadjusted, adjustment "
              "factors kept separately"),
    "initial_conditions": "as in the deck: RotSpeed 10 rpm, all other initial values 0",
}


def generate(fst: Path) -> dict:
    """Return the JSON document for the turbine of deck ``fst``."""
    params = read_openfast(fst)
    data = params.to_dict()
    data["source_files"] = {role: Path(p).name for role, p in params.source_files.items()}
    return json.loads(json.dumps({"_source": SOURCE, "parameters": data}))


def test_packaged_json_matches_the_deck(base_fst):
    # Reference: the shared deck itself; exact equality (JSON floats round-trip exactly).
    packaged = json.loads(PACKAGED.read_text(encoding="utf-8"))
    assert packaged == generate(base_fst), (
        "mbsym/wind/deck/data/nrel5mw.json is stale; regenerate it with "
        "'PYTHONPATH=. python tests/wind/test_wind_nrel5mw_data.py --write'")


def test_nrel5mw_equals_reading_the_base_deck(base_params):
    assert nrel5mw() == base_params


def test_nrel5mw_needs_no_deck():
    # Works without ../shared: values straight from package data (published NREL 5 MW data,
    # Jonkman et al. 2009, Table 1-1 and Sect. 2-5).
    p = nrel5mw()
    assert p.number_of_blades == 3
    assert p.tip_radius == 63.0 and p.hub_radius == 1.5
    assert p.tower_height == 87.6
    assert p.hub_mass == 56780.0 and p.nacelle_mass == 240000.0
    assert p.gearbox_ratio == 97.0
    assert abs(p.hub_height - 90.0) < 1e-5
    assert abs(p.shaft_tilt - np.deg2rad(-5.0)) < 1e-15
    assert abs(p.initial_conditions.rotor_speed - 10 * np.pi / 30) < 1e-15


def test_source_entry_names_definition_and_files():
    source = json.loads(PACKAGED.read_text(encoding="utf-8"))["_source"]
    assert "NREL/TP-500-38060" in source["definition"]
    assert "NREL5MW_ElastoDyn_Onshore.dat" in source["files"]


def test_nrel5mw_returns_fresh_immutable_objects():
    a, b = nrel5mw(), nrel5mw()
    assert a == b and a is not b
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.hub_mass = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        a.tower.mass_density[0] = 1.0
    heavier = dataclasses.replace(a, hub_mass=60000.0)
    assert heavier != a and isinstance(heavier, TurbineParameters)


if __name__ == "__main__":
    if sys.argv[1:] != ["--write"]:
        sys.exit("usage: PYTHONPATH=. python tests/wind/test_wind_nrel5mw_data.py --write")
    base = (Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "NREL5MW"
            / "NREL5MW_Onshore_ElastoDynOnly.fst")
    PACKAGED.write_text(json.dumps(generate(base), indent=1) + "\n", encoding="utf-8")
    print(f"wrote {PACKAGED}")
