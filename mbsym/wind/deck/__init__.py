"""Reading turbine descriptions: OpenFAST decks and the built-in NREL 5 MW.

The strict, line-numbered OpenFAST format parser (``_format``), the typed parameter
records (:mod:`.parameters`), the ElastoDyn deck reader (:mod:`.openfast`) and the
package data of the NREL 5 MW (:mod:`.nrel5mw`). Imports nothing else of ``mbsym.wind``.
"""

from .nrel5mw import nrel5mw
from .openfast import KEY_MAP, read_openfast
from .parameters import (DOF_NAMES, BladeParameters, InitialConditions, SimulationSettings, TowerParameters,
                         TurbineParameters)

__all__ = ["read_openfast", "nrel5mw", "KEY_MAP", "DOF_NAMES", "TurbineParameters", "SimulationSettings",
           "InitialConditions", "TowerParameters", "BladeParameters"]
