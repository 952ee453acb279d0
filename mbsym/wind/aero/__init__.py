"""Rotor aerodynamics: steady BEM, performance surfaces, smooth CasADi rotor loads.

* :mod:`.bem` -- steady blade-element momentum theory with AeroDyn 15's options
  (:class:`BEMRotor`, :func:`solve_bem`);
* :mod:`.surfaces` -- Cp/Ct/Cq over TSR × pitch (:func:`performance_surface`) and the disk's steady moment in a
  skewed flow (:func:`disk_moment_surface`);
* :mod:`.interpolant` -- C² spline interpolants as SX expressions (:class:`SurfaceSpline`);
* :mod:`.rotor` -- rotor thrust/torque from the surfaces (:class:`RotorAero`);
* :mod:`.nrel5mw` -- the built-in NREL 5 MW rotor (:func:`nrel5mw_rotor`);
* :mod:`.tower` -- AeroDyn's tower: drag, potential flow and shadow (:class:`TowerAero`).

See docs/aero.md for the model and its assumptions.
"""

from .bem import BEMRotor, BEMSolution, rotor_coefficients, solve_bem
from .interpolant import SurfaceSpline
from .nrel5mw import nrel5mw_bem_rotor, nrel5mw_rotor
from .rotor import RotorAero
from .surfaces import DEFAULT_PITCH, DEFAULT_TSR, DiskMomentTable, disk_moment_surface, performance_surface
from .tower import TowerAero

__all__ = ["BEMRotor", "BEMSolution", "solve_bem", "rotor_coefficients", "SurfaceSpline",
           "RotorAero", "performance_surface", "disk_moment_surface", "DiskMomentTable", "TowerAero", "DEFAULT_TSR",
           "DEFAULT_PITCH",
           "nrel5mw_bem_rotor", "nrel5mw_rotor"]
