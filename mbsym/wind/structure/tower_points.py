"""Points along the tower of the ElastoDyn-equivalent structure: their shapes, for loads along the tower.

AeroDyn's tower drag (``TwrAero``) acts at AeroDyn's own tower nodes (``TwrElev``), which are not
ElastoDyn's. OpenFAST maps ElastoDyn's tower line mesh onto them (displacements interpolated linearly
between the structural nodes); :func:`tower_point_shapes` does the same with ElastoDyn's tower mode
shapes, so the blade machinery of :mod:`.blade_points` (``blade_point_kinematics``, ``blade_point_loads``)
applies to the tower unchanged: its body frame is the tower base (``point_kinematics("tower")``), its
loads the structure's tower-load inputs (:data:`~.turbine.TOWER_LOAD_INPUTS` at the base, tower axes,
and ``{c}AeroQ`` per tower coordinate).
"""

from __future__ import annotations

from .blade_points import BladePointShapes, check_points, point_shapes
from .dof_tables import STATE_ORDER, TOWER_FLAGS
from .elastodyn_bodies import TOWER_DOFS, tower_elastodyn_data

__all__ = ["tower_point_shapes", "tower_coordinates"]


def tower_coordinates(structure) -> tuple[str, ...]:
    """The tower's elastic coordinates of ``structure`` (TurbineModel), in the tower body's shape order."""
    return tuple(STATE_ORDER[f] for f in TOWER_FLAGS if structure.dofs.get(f))


def tower_point_shapes(structure, height) -> BladePointShapes:
    """ElastoDyn's tower shapes at ``height`` [m above the tower base] (body axes of the tower base).

    Parameters
    ----------
    structure : TurbineModel
    height : array_like
        Points along the tower, within ``[0, TwrFlexL]`` (1 mm tolerance) [m].

    Raises
    ------
    ParameterError
        A point off the tower.
    """
    data = tower_elastodyn_data(structure.turbine)
    length = float(data.length)
    z = check_points(height, length, "tower points must lie on the tower, 0 m above its base to TwrFlexL",
                     "Check that AeroDyn's TwrElev lie between ElastoDyn's TowerBsHt and TowerHt.")
    idx = [TOWER_DOFS.index(f) for f in TOWER_FLAGS if structure.dofs.get(f)]
    return point_shapes(data.height, length, data, idx, z, tower_coordinates(structure))
