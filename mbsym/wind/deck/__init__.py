"""Reading turbine descriptions: OpenFAST decks and the built-in NREL 5 MW.

The strict, line-numbered OpenFAST format parser (``_format``), the typed parameter
records (:mod:`.parameters`), the ElastoDyn deck reader (:mod:`.openfast`), the AeroDyn 15
readers (:mod:`.aerodyn`, :mod:`.airfoils`), ROSCO performance tables (:mod:`.performance`), the
floating-platform readers (:mod:`.hydrodyn`, :mod:`.seastate`, :mod:`.wamit`, :mod:`.moordyn`,
:mod:`.mapplusplus`; positional files through ``_lines``, sectioned ones through ``_sections``)
the package data of the NREL 5 MW (:mod:`.nrel5mw`, :mod:`.nrel5mw_aero`) and the memory a deck
implies (:mod:`.budget`). Imports
nothing else of ``mbsym.wind``.
"""

from .aerodyn import AeroDynBlade, AeroDynInput, read_aerodyn, read_aerodyn_blade
from .airfoils import AirfoilPolar, read_airfoil
from .budget import MemoryEstimate, MemoryItem, check_deck_memory, deck_memory_estimate
from .hydrodyn import HydroDynInput, read_hydrodyn
from .mapplusplus import MapInput, read_map
from .moordyn import MoorDynInput, read_moordyn
from .nrel5mw import nrel5mw
from .nrel5mw_aero import nrel5mw_aerodyn, nrel5mw_performance_table
from .openfast import KEY_MAP, read_openfast
from .seastate import SeaStateInput, read_seastate
from .wamit import WamitData, WamitHydrodynamics, read_wamit
from .performance import PerformanceTable, read_performance_table, write_performance_table
from .parameters import (DOF_NAMES, BladeParameters, InitialConditions, SimulationSettings, TowerParameters,
                         TurbineParameters)

__all__ = ["read_openfast", "nrel5mw", "KEY_MAP", "DOF_NAMES", "TurbineParameters", "SimulationSettings",
           "InitialConditions", "TowerParameters", "BladeParameters",
           # rotor aerodynamics input (AeroDyn 15, ROSCO performance tables)
           "read_aerodyn", "read_aerodyn_blade", "AeroDynInput", "AeroDynBlade", "read_airfoil",
           "AirfoilPolar", "PerformanceTable", "read_performance_table", "write_performance_table",
           "nrel5mw_aerodyn", "nrel5mw_performance_table",
           # floating platforms (HydroDyn, SeaState, WAMIT output, MoorDyn, MAP++)
           "read_hydrodyn", "HydroDynInput", "read_seastate", "SeaStateInput", "read_wamit", "WamitData",
           "WamitHydrodynamics", "read_moordyn", "MoorDynInput", "read_map", "MapInput",
           # the memory a deck implies
           "deck_memory_estimate", "check_deck_memory", "MemoryEstimate", "MemoryItem"]
