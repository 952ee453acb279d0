"""Wind-turbine parameters: OpenFAST/ElastoDyn decks and the built-in NREL 5 MW.

:func:`read_openfast` reads a deck into :class:`TurbineParameters` (SI units,
descriptive names); :func:`nrel5mw` returns the NREL 5 MW onshore turbine from
package data; :mod:`mbsym.wind.structure.elastodyn_nodes` integrates the distributed tower
and blade properties the way ElastoDyn does, and :mod:`mbsym.wind.structure.elastodyn_bodies`
turns them into ElastoDyn-equivalent shape integrals for flexible bodies.

Public names are imported on first use (:mod:`mbsym._lazy`): ``import mbsym.wind`` or reading
a deck does not import the Campbell/MBC analysis (scipy) it does not need. To export a new name,
add it to ``_LAZY`` (name -> modules to look in) and to ``__all__``.
"""

from .._lazy import lazy_attributes

#: Public name -> module(s) defining it (relative to mbsym.wind; the first that has it wins).
_LAZY = {
    **dict.fromkeys(
        ("BladeModalProperties", "BladeNodes", "RotorMassProperties", "TowerModalProperties", "TowerNodes",
         "blade_modal_properties", "blade_nodes", "mode_shape", "rotor_mass_properties", "tower_mass",
         "tower_modal_properties", "tower_nodes", "tower_top_mass"),
        ("structure.elastodyn_nodes",)),
    **dict.fromkeys(
        ("BLADE_DOFS", "TOWER_DOFS", "ElastoDynBladeData", "ElastoDynTowerData", "blade_elastodyn_data",
         "blade_shape_integrals", "tower_elastodyn_data", "tower_shape_integrals"),
        ("structure.elastodyn_bodies",)),
    **dict.fromkeys(
        ("CampbellDiagram", "CampbellMode", "campbell", "fixed_frame_modes"),
        ("analysis.campbell_diagram",)),
    **dict.fromkeys(
        ("coleman_matrices", "mbc_second_order", "mbc_transform"),
        ("structure.mbc",)),
    **dict.fromkeys(
        ("DEFAULT_LADDER", "FidelityLadder", "fidelity_ladder"),
        ("analysis.fidelity",)),
    **dict.fromkeys(
        ("TurbineModel",),
        ("structure.turbine",)),
    **dict.fromkeys(
        ("OperatingTurbine",),
        ("operation.model",)),
    **dict.fromkeys(
        ("BladeElementRotor",),
        ("aero.blade",)),
    **dict.fromkeys(
        ("FullFieldWind", "UniformFieldWind", "read_turbsim_bts", "rotor_effective_wind"),
        ("inflow",)),
    **dict.fromkeys(
        ("nrel5mw",),
        ("deck.nrel5mw",)),
    **dict.fromkeys(
        ("KEY_MAP", "read_openfast"),
        ("deck.openfast",)),
    **dict.fromkeys(
        ("DOF_NAMES", "BladeParameters", "InitialConditions", "SimulationSettings", "TowerParameters",
         "TurbineParameters"),
        ("deck.parameters",)),
}
__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, globals())

__all__ = [
    "TurbineModel",
    "read_openfast",
    "nrel5mw",
    "KEY_MAP",
    "DOF_NAMES",
    "TurbineParameters",
    "SimulationSettings",
    "InitialConditions",
    "TowerParameters",
    "BladeParameters",
    "TowerNodes",
    "BladeNodes",
    "tower_nodes",
    "blade_nodes",
    "RotorMassProperties",
    "rotor_mass_properties",
    "tower_mass",
    "tower_top_mass",
    "TowerModalProperties",
    "tower_modal_properties",
    "BladeModalProperties",
    "blade_modal_properties",
    "mode_shape",
    "BLADE_DOFS",
    "TOWER_DOFS",
    "blade_shape_integrals",
    "tower_shape_integrals",
    "ElastoDynBladeData",
    "ElastoDynTowerData",
    "blade_elastodyn_data",
    "tower_elastodyn_data",
    "campbell",
    "CampbellDiagram",
    "CampbellMode",
    "fixed_frame_modes",
    "coleman_matrices",
    "mbc_transform",
    "mbc_second_order",
    "fidelity_ladder",
    "FidelityLadder",
    "DEFAULT_LADDER",
    "OperatingTurbine",
    "BladeElementRotor",
    "FullFieldWind",
    "UniformFieldWind",
    "read_turbsim_bts",
    "rotor_effective_wind",
]
