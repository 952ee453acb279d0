"""Offshore platforms: the water's loads and the mooring of floating ones (issue 20), bottom-fixed substructures.

A wind room importing only :mod:`mbsym.wind.deck` (and the general layers):

- :mod:`.hydrostatics`: hydrostatics and buoyancy as HydroDyn applies them, HydroDyn's additional
  preload, stiffness and damping;
- :mod:`.platform`: the still-water hydrodynamics of a deck, with the infinite-frequency added mass;
- :mod:`.radiation`, :mod:`.radiation_fit`: the radiation memory as a state-space block, read from a
  ``.ss`` file or fitted to the ``.1`` data;
- :mod:`.catenary`, :mod:`.mooring`: the quasi-static elastic catenary mooring;
- :mod:`.line_dynamics`: the lines' drag and inertia on their quasi-static shape (MoorDyn decks);
- :mod:`.modes`: natural periods from the generalized eigenproblem;
- :mod:`.floating`: a first floating structure (a structural model + water + mooring; no rotor
  loads, no controller);
- :mod:`.operating`: :class:`FloatingPlatform`, the platform loads the operating turbine composes
  (``OperatingTurbine(..., platform=floating_platform(turbine))``; ``operating_deck`` does it for a
  deck with HydroDyn and a mooring);
- :mod:`.frame_fem`, :mod:`.substructure`, :mod:`.bottom_fixed`: SubDyn's bottom-fixed substructures (the frame's
  finite elements, Guyan and Craig-Bampton reduction, :class:`~.bottom_fixed.BottomFixedPlatform` as the platform
  loads of a deck with ``CompSub = 1``); :mod:`.substructure_water`: HydroDyn's Morison loads on their nodes.

Loads are numbers or CasADi expressions of the six platform DOFs (surge, sway, heave, roll, pitch,
yaw). See docs/offshore.md.
"""

from .bottom_fixed import BottomFixedPlatform, bottom_fixed_platform
from .catenary import CatenaryLine, wet_weight
from .hydrostatics import AdditionalLoads, PlatformHydrostatics
from .line_dynamics import LineHydrodynamics
from .lumped_line import LumpedLine
from .modes import PlatformModes, natural_periods, periods_with_frequency_dependent_added_mass
from .mooring import MooringSystem, mooring_from_map, mooring_from_moordyn
from .operating import FloatingPlatform, deck_radiation, floating_platform
from .platform import PlatformHydrodynamics, platform_hydrodynamics
from .radiation import RadiationStateSpace, radiation_reference
from .radiation_fit import fit_radiation, fit_radiation_cached, vector_fit
from .substructure import ReducedSubstructure, Substructure
from .substructure_water import SubstructureWater, substructure_hydrodynamics

__all__ = ["PlatformHydrostatics", "AdditionalLoads", "PlatformHydrodynamics", "platform_hydrodynamics",
           "natural_periods", "periods_with_frequency_dependent_added_mass", "PlatformModes",
           "CatenaryLine", "wet_weight", "LineHydrodynamics", "LumpedLine", "MooringSystem", "mooring_from_moordyn",
           "mooring_from_map",
           "RadiationStateSpace", "radiation_reference", "fit_radiation", "fit_radiation_cached", "vector_fit",
           "FloatingPlatform", "floating_platform", "deck_radiation", "Substructure", "ReducedSubstructure",
           "BottomFixedPlatform", "bottom_fixed_platform", "SubstructureWater", "substructure_hydrodynamics"]
