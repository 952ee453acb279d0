"""ElastoDyn's own summary of the base deck vs our reading and integration.

Reference: ``../shared/openfast/NREL5MW/NREL5MW_Onshore_ElastoDynOnly.ED.sum``,
printed by OpenFAST v5.0.0 ElastoDyn (double precision) for the shared base deck,
and the same values published in ``../shared/guide/REFERENCE_NUMBERS.md``.

Tolerance: half a unit of the last printed digit (ElastoDyn rounds when it
prints), plus 1e-9 for floating-point noise.  For the mass totals (3 decimals on
1e4..4e7) that is a relative error below 3e-8; for the node tables it is 5e-4
absolute (F format) or 5e-4 relative (4-digit E format).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from mbsym.wind import (
    blade_nodes, rotor_mass_properties, tower_mass, tower_nodes, tower_top_mass,
)


# Published in REFERENCE_NUMBERS.md (ElastoDyn, NREL 5 MW onshore).
PUBLISHED = {"Rotor Mass": 109389.842, "Rotor Inertia": 38677040.613, "Mass": 17536.614,
             "Second Mass Moment": 11752352.265, "First Mass Moment": 362132.653,
             "Center of Mass": 20.650}


def _half_unit(text: str) -> float:
    """Half a unit of the last digit printed in ``text`` (F or E format)."""
    mantissa, _, exponent = text.upper().partition("E")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 0.5 * 10.0 ** (-decimals + (int(exponent) if exponent else 0)) + 1e-9


@pytest.fixture(scope="module")
def summary(base_fst) -> dict:
    ed_sum = base_fst.with_suffix(".ED.sum")
    if not ed_sum.is_file():
        pytest.skip(f"ElastoDyn summary not found at {ed_sum}")
    text = ed_sum.read_text()
    values = {}
    for label in ("Hub-Height", "Flexible Tower Length", "Flexible Blade Length", "Rotor Mass",
                  "Rotor Inertia", "Tower-top Mass", "Tower Mass", "Platform Mass",
                  "Mass Incl. Platform", "Mass", "Second Mass Moment", "First Mass Moment",
                  "Center of Mass"):
        match = re.search(rf"^\s+{re.escape(label)}\s+\([^)]*\)\s+(.+)$", text, re.M)
        values[label] = match.group(1).split()
    tables = {}
    for name, pattern in (("tower", r"Interpolated tower properties:"),
                          ("blade1", r"Interpolated blade 1 properties:"),
                          ("blade2", r"Interpolated blade 2 properties:"),
                          ("blade3", r"Interpolated blade 3 properties:")):
        block = text[re.search(pattern, text).end():].split("\n\n\n")[0]
        rows = [line.split() for line in block.splitlines() if re.match(r"^\s*\d+\s", line)]
        tables[name] = rows
    return {"values": values, "tables": tables}


def _close(ours: float, printed: str) -> bool:
    return abs(ours - float(printed)) <= _half_unit(printed)


def test_rotor_and_blade_mass_properties(base_params, summary):
    rotor = rotor_mass_properties(base_params)
    printed = summary["values"]
    assert _close(rotor.rotor_mass, printed["Rotor Mass"][0])
    assert _close(rotor.rotor_inertia, printed["Rotor Inertia"][0])
    for k in range(3):
        assert _close(rotor.blade_mass[k], printed["Mass"][k])
        assert _close(rotor.second_mass_moment[k], printed["Second Mass Moment"][k])
        assert _close(rotor.first_mass_moment[k], printed["First Mass Moment"][k])
        assert _close(rotor.blade_cg[k], printed["Center of Mass"][k])


def test_published_reference_numbers(base_params):
    rotor = rotor_mass_properties(base_params)
    ours = {"Rotor Mass": rotor.rotor_mass, "Rotor Inertia": rotor.rotor_inertia,
            "Mass": rotor.blade_mass[0], "Second Mass Moment": rotor.second_mass_moment[0],
            "First Mass Moment": rotor.first_mass_moment[0], "Center of Mass": rotor.blade_cg[0]}
    for label, value in PUBLISHED.items():
        assert abs(ours[label] - value) <= 0.5e-3 + 1e-9, label


def test_tower_and_turbine_masses(base_params, summary):
    printed = summary["values"]
    assert _close(tower_top_mass(base_params), printed["Tower-top Mass"][0])
    assert _close(tower_mass(base_params), printed["Tower Mass"][0])
    assert _close(base_params.platform_mass, printed["Platform Mass"][0])
    total = tower_top_mass(base_params) + tower_mass(base_params) + base_params.platform_mass
    assert _close(total, printed["Mass Incl. Platform"][0])


def test_geometry(base_params, summary):
    printed = summary["values"]
    assert _close(base_params.hub_height, printed["Hub-Height"][0])
    assert _close(base_params.tower_flexible_length, printed["Flexible Tower Length"][0])
    assert _close(base_params.blade_flexible_length, printed["Flexible Blade Length"][0])


def test_interpolated_tower_nodes(base_params, summary):
    nodes = tower_nodes(base_params)
    rows = summary["tables"]["tower"]
    assert len(rows) == base_params.n_tower_nodes == nodes.height.size
    columns = (nodes.fraction, nodes.height, nodes.length, nodes.mass_density,
               nodes.fa_stiffness, nodes.ss_stiffness)
    for j, row in enumerate(rows):
        assert int(row[0]) == j + 1
        for ours, printed in zip(columns, row[1:]):
            assert _close(float(ours[j]), printed), (j + 1, printed, ours[j])


@pytest.mark.parametrize("blade", [0, 1, 2])
def test_interpolated_blade_nodes(base_params, summary, blade):
    nodes = blade_nodes(base_params, blade)
    rows = summary["tables"][f"blade{blade + 1}"]
    assert len(rows) == base_params.n_blade_nodes == nodes.span.size
    columns = (nodes.fraction, nodes.radius, nodes.length, np.rad2deg(nodes.structural_twist),
               nodes.mass_density, nodes.flap_stiffness, nodes.edge_stiffness)
    for j, row in enumerate(rows):
        for ours, printed in zip(columns, row[1:]):
            assert _close(float(ours[j]), printed), (j + 1, printed, ours[j])


def test_summary_parser_reads_what_it_should(summary):
    # Guard against a parser that silently reads nothing (a test that cannot fail).
    assert summary["values"]["Rotor Mass"] == ["109389.842"]
    assert len(summary["tables"]["tower"]) == 20 and len(summary["tables"]["blade3"]) == 17
    assert math.isclose(float(summary["tables"]["blade1"][0][5]), 787.554)
