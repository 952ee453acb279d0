"""Wind-turbine parameters: OpenFAST/ElastoDyn decks and the built-in NREL 5 MW.

:func:`read_openfast` reads a deck into :class:`TurbineParameters` (SI units,
descriptive names); :func:`nrel5mw` returns the NREL 5 MW onshore turbine from
package data; :mod:`mbsym.wind.structure.elastodyn_nodes` integrates the distributed tower
and blade properties the way ElastoDyn does, and :mod:`mbsym.wind.structure.elastodyn_bodies`
turns them into ElastoDyn-equivalent shape integrals for flexible bodies.
"""

from .structure.elastodyn_nodes import (
    BladeModalProperties,
    BladeNodes,
    RotorMassProperties,
    TowerModalProperties,
    TowerNodes,
    blade_modal_properties,
    blade_nodes,
    mode_shape,
    rotor_mass_properties,
    tower_mass,
    tower_modal_properties,
    tower_nodes,
    tower_top_mass,
)
from .structure.elastodyn_bodies import (
    BLADE_DOFS,
    TOWER_DOFS,
    ElastoDynBladeData,
    ElastoDynTowerData,
    blade_elastodyn_data,
    blade_shape_integrals,
    tower_elastodyn_data,
    tower_shape_integrals,
)
from .analysis.campbell_diagram import CampbellDiagram, CampbellMode, campbell, fixed_frame_modes
from .structure.mbc import coleman_matrices, mbc_second_order, mbc_transform
from .analysis.fidelity import DEFAULT_LADDER, FidelityLadder, fidelity_ladder
from .structure.turbine import TurbineModel
from .deck.nrel5mw import nrel5mw
from .deck.openfast import KEY_MAP, read_openfast
from .deck.parameters import (
    DOF_NAMES,
    BladeParameters,
    InitialConditions,
    SimulationSettings,
    TowerParameters,
    TurbineParameters,
)

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
]
