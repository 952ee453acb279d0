"""The tower's aerodynamics in the operating turbine's graph: its drag on the structure, its line for the blades.

:class:`~mbsym.wind.aero.tower.TowerAero` holds AeroDyn's physics; this module places it on the
structure. AeroDyn's tower nodes (``TwrElev``) move with ElastoDyn's tower shapes
(:func:`~mbsym.wind.structure.tower_points.tower_point_shapes`, heights above ``TowerBsHt``):

- :func:`tower_drag_loads`: the drag per unit length at the nodes (wind minus the node's velocity, across
  the deflected tower axis), integrated with the nodes' trapezoidal weights into the structure's tower-load
  inputs (:data:`~mbsym.wind.structure.turbine.TOWER_LOAD_INPUTS` and ``{c}AeroQ``, the virtual work of the
  distributed load, exact as for the blades);
- :func:`tower_line`: the lowest and highest nodes with their velocities, the straight line along which the
  blade-element rotor evaluates the tower's disturbance of its inflow;
- :func:`nacelle_drag_loads`: AeroDyn's nacelle drag (:class:`~mbsym.wind.aero.nacelle.NacelleDrag`) from the wind
  at the yaw bearing minus its velocity, the structure's nacelle-load inputs (force at the yaw bearing and moment
  about it, nacelle axes: ElastoDyn's ``NacelleLoads``, which OpenFAST fills from AeroDyn's ``NacelleLoad``).
"""

from __future__ import annotations

from typing import Any, Callable

import casadi as ca
import numpy as np

from ..structure.blade_points import blade_point_kinematics, blade_point_loads
from ..structure.tower_points import tower_coordinates, tower_point_shapes
from ..structure.load_inputs import NACELLE_LOAD_INPUTS
from ..structure.turbine import TOWER_LOAD_INPUTS

__all__ = ["tower_load_inputs", "tower_drag_loads", "tower_line", "tower_moves", "nacelle_load_inputs",
           "nacelle_drag_loads"]


def tower_load_inputs(structure) -> tuple[str, ...]:
    """The structure's tower-load inputs (empty without ``tower_loads``)."""
    if not getattr(structure, "tower_loads", False):
        return ()
    return tuple(f"TwrAero{c}" for c in TOWER_LOAD_INPUTS) + tuple(f"{c}AeroQ" for c in tower_coordinates(structure))


def nacelle_load_inputs(structure) -> tuple[str, ...]:
    """The structure's nacelle-load inputs (empty without ``nacelle_loads``)."""
    if not getattr(structure, "nacelle_loads", False):
        return ()
    return tuple(f"NacAero{c}" for c in NACELLE_LOAD_INPUTS)


def tower_moves(structure) -> bool:
    """Whether a load on the tower can move an enabled DOF (tower or platform DOFs)."""
    flags = ("TwFADOF1", "TwFADOF2", "TwSSDOF1", "TwSSDOF2", "PtfmSgDOF", "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF",
             "PtfmPDOF", "PtfmYDOF")
    return any(structure.dofs.get(f) for f in flags)


def _points(model, heights: np.ndarray, q: Any, qd: Any, frame: dict[str, Any]) -> dict[str, Any]:
    """Kinematics of the tower points at ``heights`` [m above the tower base] (shapes cached on the model)."""
    key = ("tower_points", tuple(np.round(heights, 9)))
    shapes = model._parts.get(key)
    if shapes is None:
        shapes = model._parts[key] = tower_point_shapes(model.structure, heights)
    coords = model.structure.eom.coordinates
    idx = [coords.index(c) for c in shapes.coordinates]
    kind = ca.MX if isinstance(q, ca.MX) else ca.SX
    qe, qde = (q[idx], qd[idx]) if idx else (kind(0, 1), kind(0, 1))
    return blade_point_kinematics(shapes, frame, qe, qde)


def _heights(model, elevation: np.ndarray) -> np.ndarray:
    return np.asarray(elevation, dtype=float) - float(model.turbine.tower_base_height)


def tower_drag_loads(model, frame: dict[str, Any], q: Any, qd: Any, wind: Callable[[Any], Any],
                     rho: Any) -> dict[str, Any]:
    """The tower-load inputs of AeroDyn's tower drag (module docstring).

    Parameters
    ----------
    model : OperatingTurbine
        With ``tower_aero`` (drag on) and a structure built with ``tower_loads``.
    frame : dict
        The tower body frame at its base (``point_kinematics("tower")``: ``r``, ``R``, ``v``, ``w``).
    q, qd : SX or MX
        The structure's coordinates and speeds.
    wind : callable
        ``wind(points (3, N)) -> (3, N)`` wind velocity [m/s] at ground positions [m].
    rho : SX or float
        Air density [kg/m³].

    Returns
    -------
    dict
        Input name -> load (``TwrAeroFx`` … ``TwrAeroMz``, ``{c}AeroQ``).
    """
    from ..aero.tower import drag_per_length

    tower = model.tower_aero
    weights, elevation = tower.nodes()
    kin = _points(model, _heights(model, elevation), q, qd, frame)
    force = drag_per_length(wind(kin["r"]) - kin["v"], kin["tangent"], tower.diameter, tower.drag_coefficient, rho)
    n = force.size2()
    loads = blade_point_loads(kin, frame["R"], force, type(force).zeros(3, n), weights)
    names = tower_load_inputs(model.structure)
    values = list(ca.vertsplit(loads["F"])) + list(ca.vertsplit(loads["M"])) + list(loads["Q"])
    return dict(zip(names, values))


def tower_line(model, frame: dict[str, Any], q: Any, qd: Any) -> dict[str, Any]:
    """The tower's lowest and highest AeroDyn nodes, ground axes: ``start``, ``end`` [m] and their velocities
    ``start_velocity``, ``end_velocity`` [m/s] (arguments as :func:`tower_drag_loads`)."""
    elevation = model.tower_aero.elevation
    kin = _points(model, _heights(model, elevation[[0, -1]]), q, qd, frame)
    return {"start": kin["r"][:, 0], "end": kin["r"][:, 1], "start_velocity": kin["v"][:, 0],
            "end_velocity": kin["v"][:, 1]}


def nacelle_drag_loads(model, frame: dict[str, Any], wind: Callable[[Any], Any], rho: Any) -> dict[str, Any]:
    """The nacelle-load inputs of AeroDyn's nacelle drag and its force and moment (module docstring).

    Parameters
    ----------
    model : OperatingTurbine
        With ``nacelle_drag`` and a structure built with ``nacelle_loads``.
    frame : dict
        The nacelle body frame at the yaw bearing (``point_kinematics("nacelle")``: ``r``, ``R``, ``v``).
    wind : callable
        ``wind(points (3, N)) -> (3, N)`` wind velocity [m/s] at ground positions [m].
    rho : SX or float
        Air density [kg/m³].

    Returns
    -------
    dict
        ``NacAeroFx`` … ``NacAeroMz`` (nacelle axes), and ``force``, ``moment`` (3, 1) the same in nacelle axes.
    """
    force, moment = model.nacelle_drag.loads(wind(frame["r"]) - frame["v"], frame["R"], rho)
    out = dict(zip(nacelle_load_inputs(model.structure), list(ca.vertsplit(force)) + list(ca.vertsplit(moment))))
    out.update(force=force, moment=moment)
    return out
