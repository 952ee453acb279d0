"""Floating platforms: the water's loads and the mooring (issue 20).

A wind room importing only :mod:`mbsym.wind.deck` (and the general layers): the platform's
hydrostatics and buoyancy as HydroDyn applies them, HydroDyn's additional preload, stiffness
and damping (:mod:`.hydrostatics`), the still-water hydrodynamics of a deck with the
infinite-frequency added mass (:mod:`.platform`), natural periods from the generalized
eigenproblem (:mod:`.modes`), the quasi-static catenary mooring (:mod:`.catenary`,
:mod:`.mooring`), and the radiation memory as a state-space block (:mod:`.radiation`), read from a
``.ss`` file or fitted to the ``.1`` data (:mod:`.radiation_fit`). Loads are numbers or CasADi expressions of the six
platform DOFs (surge, sway, heave, roll, pitch, yaw). Nothing here is wired into the operating
turbine yet. See docs/offshore.md.
"""

from .catenary import CatenaryLine, wet_weight
from .hydrostatics import AdditionalLoads, PlatformHydrostatics
from .modes import PlatformModes, natural_periods, periods_with_frequency_dependent_added_mass
from .mooring import MooringSystem, mooring_from_map, mooring_from_moordyn
from .platform import PlatformHydrodynamics, platform_hydrodynamics
from .radiation import RadiationStateSpace, radiation_reference
from .radiation_fit import fit_radiation, vector_fit

__all__ = ["PlatformHydrostatics", "AdditionalLoads", "PlatformHydrodynamics", "platform_hydrodynamics",
           "natural_periods", "periods_with_frequency_dependent_added_mass", "PlatformModes",
           "CatenaryLine", "wet_weight", "MooringSystem", "mooring_from_moordyn", "mooring_from_map",
           "RadiationStateSpace", "radiation_reference", "fit_radiation", "vector_fit"]
