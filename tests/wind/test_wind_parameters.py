"""Behaviour of the parameter dataclasses (independent of any deck)."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from mbsym.exceptions import ParameterError
from mbsym.wind import DOF_NAMES, KEY_MAP, TurbineParameters, nrel5mw


def test_json_round_trip_is_exact():
    p = nrel5mw()
    again = TurbineParameters.from_dict(json.loads(json.dumps(p.to_dict())))
    assert again == p
    assert again.tower.fa_mode_shapes.shape == (2, 5)
    assert again.blades[0].edge_mode_shapes.shape == (1, 5)


def test_equality_ignores_source_files_only():
    p = nrel5mw()
    assert dataclasses.replace(p, source_files={"fst": "elsewhere.fst"}) == p
    tower = dataclasses.replace(p.tower, mass_density=p.tower.mass_density * (1 + 1e-15))
    assert dataclasses.replace(p, tower=tower) != p


def test_from_dict_names_missing_and_unknown_fields():
    data = nrel5mw().to_dict()
    data.pop("hub_mass")
    data["hub_mas"] = 1.0
    with pytest.raises(ParameterError, match=r"missing fields \['hub_mass'\], unknown fields "
                       r"\['hub_mas'\]"):
        TurbineParameters.from_dict(data)


def test_dofs_must_use_elastodyn_names():
    p = nrel5mw()
    dofs = dict(p.dofs)
    dofs["TowerFA1"] = dofs.pop("TwFADOF1")
    with pytest.raises(ParameterError, match="`dofs` must map exactly"):
        dataclasses.replace(p, dofs=dofs)
    assert list(p.dofs) == list(DOF_NAMES)


def test_per_blade_lengths_are_checked():
    with pytest.raises(ParameterError, match=r"`precone` has 2 entries; expected "
                       r"number_of_blades = 3"):
        dataclasses.replace(nrel5mw(), precone=(0.0, 0.0))


def test_array_shapes_and_finiteness_are_checked():
    tower = nrel5mw().tower
    with pytest.raises(ParameterError, match=r"`TowerParameters.mass_density` has 3 rows; "
                       r"expected 11"):
        dataclasses.replace(tower, mass_density=[1.0, 2.0, 3.0])
    with pytest.raises(ParameterError, match="must be finite"):
        dataclasses.replace(tower, fa_stiffness=np.full(11, np.nan))
    with pytest.raises(ParameterError, match=r"shape \(2, 4\); expected \(5,\)"):
        dataclasses.replace(tower, fa_mode_shapes=np.zeros((2, 4)))


def test_scalar_finiteness_is_checked():
    with pytest.raises(ParameterError, match="`hub_mass` must be finite"):
        dataclasses.replace(nrel5mw(), hub_mass=float("inf"))


def test_adjusted_properties():
    blade = nrel5mw().blades[0]
    np.testing.assert_array_equal(blade.adjusted_mass_density, blade.mass_density * 1.04536)


def test_key_map_documents_every_attribute():
    # Every TurbineParameters field read from the ElastoDyn file appears in KEY_MAP.
    mapped = {attr.split(".")[0].split("[")[0] for attr in KEY_MAP["ElastoDyn"].values()}
    skip = {"simulation", "tower", "blades", "output_channels", "node_output_channels",
            "extra", "source_files"}
    fields = {f.name for f in dataclasses.fields(TurbineParameters)} - skip
    assert fields <= mapped
    assert KEY_MAP["ElastoDyn"]["TowerHt"] == "tower_height"
    assert KEY_MAP["blade"]["StrcTwst"].startswith("structural_twist")
