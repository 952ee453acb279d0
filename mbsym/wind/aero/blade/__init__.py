"""Blade-element aerodynamics of every blade node as CasADi SX expressions (AeroDyn 15 BEMT/DBEMT).

* :mod:`.rotor` -- :class:`BladeElementRotor`: the contract with the structure (per-node relative
  velocities in, loads per unit length and dynamic-wake state derivatives out);
* :mod:`.induction` -- Ning's residual and the fixed-count Newton solve in the graph;
* :mod:`.polars` -- smooth (C² spline) or AeroDyn-linear airfoil polars as SX;
* :mod:`.dbemt` -- AeroDyn's DBEMT as a continuous ODE per node;
* :mod:`.corrections` -- Pitt/Peters skewed wake, low-TSR blend.

See docs/blade_aero.md.
"""

from .rotor import BladeElementRotor

__all__ = ["BladeElementRotor"]
