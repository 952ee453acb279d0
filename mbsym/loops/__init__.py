"""Closed kinematic loops: Kane's method with dependent coordinates and speeds (docs/closed_loops.md).

- :mod:`.assembly`: independent coordinates, the assembled configuration, rank checks;
- :mod:`.reduce`: the reduced equations and the dependent coordinates solved in the graph;
- :mod:`.equations`: :class:`ClosedLoopEquations`, what :meth:`mbsym.System.equations` returns for a
  System with closures;
- :mod:`.nonholonomic`: velocity constraints, as first-order dynamics.
"""

from .equations import ClosedLoopEquations, closed_equations

__all__ = ["ClosedLoopEquations", "closed_equations"]
