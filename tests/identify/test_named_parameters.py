"""Named turbine parameters: a parameter set to a value gives the equations of the deck edited to that value.

Reference: the template built from an edited deck (numeric shape integrals, ElastoDyn's stiffness and
damping computed by elastodyn_bodies.py) — independent of the symbolic expressions in
named_parameters.py. Tolerance 1e-10 relative to the largest rhs entry at a random state (the same
arithmetic up to rounding; the 9-DOF blade model solves M qdd = F numerically).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import ParameterError
from mbsym.wind import nrel5mw
from mbsym.wind.structure import named_parameters as npar
from mbsym.wind.structure.turbine import TurbineModel


def _edit(t, key: str, value: float):
    """The deck with ``key`` set to ``value`` (key units), through the dataclasses."""
    e = npar.lookup(key)
    si = value / e.factor
    tw, bl = t.tower, t.blades
    rigid = {"NacMass": "nacelle_mass", "NacYIner": "nacelle_yaw_inertia", "HubMass": "hub_mass",
             "HubIner": "hub_inertia", "GenIner": "generator_inertia", "YawBrMass": "yaw_bearing_mass",
             "DTTorSpr": "drivetrain_stiffness", "DTTorDmp": "drivetrain_damping", "PtfmMass": "platform_mass",
             "PtfmRIner": "platform_roll_inertia", "PtfmPIner": "platform_pitch_inertia",
             "PtfmYIner": "platform_yaw_inertia"}
    if e.key in rigid:
        return dataclasses.replace(t, **{rigid[e.key]: si})
    if e.key == "PtfmCMzt":
        return dataclasses.replace(t, platform_cm=(*t.platform_cm[:2], si))
    factors = {"AdjTwMa": "mass_factor", "AdjFASt": "fa_stiffness_factor", "AdjSSSt": "ss_stiffness_factor"}
    if e.key in factors:
        return dataclasses.replace(t, tower=dataclasses.replace(tw, **{factors[e.key]: si}))
    base, i = e.key[:-3], int(e.key[-2]) - 1
    tower = {"FAStTunr": "fa_stiffness_tuner", "SSStTunr": "ss_stiffness_tuner", "TwrFADmp": "fa_damping_ratio",
             "TwrSSDmp": "ss_damping_ratio"}
    if base in tower:
        a = np.array(getattr(tw, tower[base]))
        a[i] = si
        return dataclasses.replace(t, tower=dataclasses.replace(tw, **{tower[base]: a}))
    blade = {"FlStTunr": "flap_stiffness_tuner", "BldFlDmp": "flap_damping_ratio", "BldEdDmp": "edge_damping_ratio"}
    a = np.array(getattr(bl[0], blade[base]))
    a[i] = si
    return dataclasses.replace(t, blades=tuple(dataclasses.replace(b, **{blade[base]: a}) for b in bl))


def _floating():
    """NREL 5 MW with a spar-like platform (values of the shared paper46 deck, welib's Spar_ED)."""
    t = nrel5mw()
    return dataclasses.replace(t, platform_mass=7.5e6, platform_roll_inertia=4.2e9, platform_pitch_inertia=4.2e9,
                               platform_yaw_inertia=1.6e8, platform_cm=(0.0, 0.0, -90.0),
                               platform_reference=(0.0, 0.0, 20.0), tower_base_height=20.0)


GROUPS = {
    "tower": (nrel5mw, ["TwFADOF1", "TwFADOF2", "TwSSDOF1", "TwSSDOF2"],
              ["AdjTwMa", "AdjFASt", "AdjSSSt", "FAStTunr(1)", "FAStTunr(2)", "SSStTunr(1)", "SSStTunr(2)",
               "TwrFADmp(1)", "TwrFADmp(2)", "TwrSSDmp(1)", "TwrSSDmp(2)", "NacMass", "HubMass", "YawBrMass"]),
    "blades": (nrel5mw, ["FlapDOF1", "FlapDOF2", "EdgeDOF"],
               ["FlStTunr(1)", "FlStTunr(2)", "BldFlDmp(1)", "BldFlDmp(2)", "BldEdDmp(1)"]),
    "platform": (_floating, ["PtfmSgDOF", "PtfmPDOF", "PtfmRDOF", "TwFADOF1", "DrTrDOF", "GenDOF"],
                 ["PtfmMass", "PtfmRIner", "PtfmPIner", "PtfmYIner", "PtfmCMzt", "DTTorSpr", "DTTorDmp", "HubIner",
                  "GenIner", "NacYIner"]),
}


@pytest.mark.parametrize("group", list(GROUPS))
def test_parameter_equals_edited_deck(group):
    make, dofs, keys = GROUPS[group]
    t = make()
    dyn = mb.as_dynamics(TurbineModel(t, dofs=dofs).eom)
    rng = np.random.default_rng(3)
    x = 0.05 * rng.normal(size=dyn.n_x)
    x[dyn.n_x // 2:] *= 20.0                                    # speeds: damping terms matter
    u = np.zeros(dyn.n_u)
    f_default = dyn.rhs_value(x, u)
    for key in keys:
        e = npar.lookup(key)
        value = 1.3 * npar.deck_value(t, key) + (0.5 if npar.deck_value(t, key) == 0 else 0.0)
        ref = mb.as_dynamics(TurbineModel(_edit(t, key, value), dofs=dofs).eom).rhs_value(x, u)
        got = dyn.rhs_value(x, u, {e.name: value / e.factor})
        scale = np.max(np.abs(ref))
        assert np.max(np.abs(got - ref)) <= 1e-10 * scale, key
        assert np.max(np.abs(f_default - ref)) > 1e-9 * scale, f"{key} does not change the equations"


def test_defaults_are_the_deck_values():
    t = _floating()
    dyn = mb.as_dynamics(TurbineModel(t, dofs=["PtfmPDOF", "TwFADOF1", "TwSSDOF2"]).eom)
    for key in ("PtfmPIner", "PtfmCMzt", "TwrFADmp(1)", "SSStTunr(2)", "AdjTwMa", "NacMass", "Gravity"):
        e = npar.lookup(key)
        assert dyn.defaults[e.name] * e.factor == pytest.approx(npar.deck_value(t, key), rel=1e-15)
    assert "tower_fa2_damping_ratio" not in dyn.parameters          # TwFADOF2 off: not a parameter
    assert npar.deck_value(t, "TwrFADmp(1)") == pytest.approx(100 * t.tower.fa_damping_ratio[0])


@pytest.mark.parametrize("spelling", ["TwrFADmp(1)", "TwrFADmp1", "twrfadmp(1)", " TwrFADmp( 1 ) ",
                                      "tower_fa1_damping_ratio"])
def test_key_spellings(spelling):
    assert npar.lookup(spelling).key == "TwrFADmp(1)"


def test_edge_damping_without_index_and_unknown_keys():
    assert npar.lookup("BldEdDmp").key == "BldEdDmp(1)"
    with pytest.raises(ParameterError, match="unknown parameter key 'FAStTunr'"):
        npar.lookup("FAStTunr")                               # two modes: the index is required
    with pytest.raises(ParameterError, match="unknown parameter key 'TwrFADmp\\(3\\)'"):
        npar.lookup("TwrFADmp(3)")


def test_blades_that_differ_keep_numeric_values():
    t = nrel5mw()
    b = [dataclasses.replace(t.blades[0], flap_damping_ratio=np.array([0.01, 0.005]))] + list(t.blades[1:])
    model = TurbineModel(dataclasses.replace(t, blades=tuple(b)), dofs=["FlapDOF1", "EdgeDOF"])
    assert "blade_flap1_damping_ratio" not in model.eom.parameters
    assert "blade_edge_damping_ratio" in model.eom.parameters
    with pytest.raises(ParameterError, match="blades have different values"):
        model.resolve_parameter("BldFlDmp(1)")


def test_table_lists_every_key_once():
    table = npar.parameter_table()
    for key in npar.NAMED_PARAMETERS:
        assert table.count(f"| {key} |") == 1
    assert len({e.name for e in npar.NAMED_PARAMETERS.values()}) == len(npar.NAMED_PARAMETERS)


def test_other_layers_register_parameters_by_name():
    """How the aerodynamic turbine plugs in (air density, Cp/Ct scales): register, then resolve by name."""
    entry = npar.NamedParameter("TestAirDens", "test_air_density", "kg/m^3", 1.0, "air density (test entry)",
                                "rotor loads")
    npar.register(entry)
    try:
        npar.register(entry)                                    # the same entry again: accepted
        assert npar.lookup("testairdens") is entry
        assert npar.resolve(["test_air_density", "gravity"], "TestAirDens") is entry
        with pytest.raises(ParameterError, match="'TestAirDens' \\(test_air_density\\) is not a parameter"):
            npar.resolve(["gravity"], "TestAirDens")
        with pytest.raises(ParameterError, match="already registered differently"):
            npar.register(dataclasses.replace(entry, factor=2.0))
    finally:                                                    # leave the table as it was
        npar.NAMED_PARAMETERS.pop("TestAirDens")
        npar._BY_NAME.pop("test_air_density")
        npar._CANONICAL.pop("testairdens")
