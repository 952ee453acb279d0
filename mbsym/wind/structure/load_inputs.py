"""The loads a :class:`~.turbine.TurbineModel` exposes as inputs, only where they can move an enabled DOF.

- ``GenTq`` (on the generator, reacted on the nacelle; through a lossy gearbox as :mod:`.gearbox` says) and
  ``RotTorq`` (on the rotor), with GenDOF or DrTrDOF;
- ``RotThrust`` along the shaft at the hub, and with ``hub_moments`` ``RotMomY``, ``RotMomZ``, ``RotFrcY``,
  ``RotFrcZ`` across it (shaft axes);
- with ``blade_loads``, per blade ``k`` the root force ``B{k}AeroFx/Fy/Fz`` and moment ``B{k}AeroMx/My/Mz`` (blade
  axes, :data:`BLADE_LOAD_INPUTS`) and ``{c}AeroQ`` per elastic blade coordinate;
- with ``tower_loads``, the force ``TwrAeroFx/Fy/Fz`` at the tower base and moment ``TwrAeroMx/My/Mz`` about it
  (tower-base axes, :data:`TOWER_LOAD_INPUTS`) and ``{c}AeroQ`` per tower coordinate (:mod:`.tower_points`);
- with ``nacelle_loads``, the force ``NacAeroFx/Fy/Fz`` at the yaw bearing (the nacelle's origin, the tower top) and
  moment ``NacAeroMx/My/Mz`` about it, nacelle axes (:data:`NACELLE_LOAD_INPUTS`; AeroDyn's nacelle drag);
- with a platform DOF, ``PtfmFx`` … ``PtfmMz`` on the platform (ground axes).
"""

from __future__ import annotations

from .dof_tables import PLATFORM_FLAGS
from .gearbox import add_gearbox_losses, generator_torque_at_shaft, has_losses
from .tower_points import tower_coordinates

__all__ = ["add_load_inputs", "BLADE_LOAD_INPUTS", "TOWER_LOAD_INPUTS", "NACELLE_LOAD_INPUTS"]

#: Per-blade load inputs with ``blade_loads=True``: ``B{k}Aero`` + these (root force [N], moment [N m], blade axes).
BLADE_LOAD_INPUTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: Tower load inputs with ``tower_loads=True``: ``TwrAero`` + these (base force [N], moment [N m], tower axes).
TOWER_LOAD_INPUTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
#: Nacelle load inputs with ``nacelle_loads=True``: ``NacAero`` + these (force [N] at the yaw bearing, moment [N m]
#: about it, nacelle axes).
NACELLE_LOAD_INPUTS = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")


def add_load_inputs(model, platform, shaft, hub) -> None:
    """Add the inputs of the module docstring to ``model.system`` (a TurbineModel being built)."""
    sys = model.system
    if "GeAz" in model.coords or "DrTr" in model.coords:
        tq_gen, tq_aero = sys.inputs("GenTq RotTorq")
        gen = model.bodies["generator"]
        if has_losses(model) and "DrTr" not in model.coords:       # GBoxEff, rigid drivetrain (.gearbox)
            tq_gen = generator_torque_at_shaft(tq_gen, model.turbine.gearbox_efficiency)
        sys.add_torque(gen, [-tq_gen, 0.0, 0.0], frame=shaft)       # HSS torque on the generator
        sys.add_torque(shaft, [tq_gen, 0.0, 0.0], frame=shaft)      # its reaction on the nacelle
        sys.add_torque(hub, [tq_aero, 0.0, 0.0], frame=shaft)       # aerodynamic torque on the rotor
        add_gearbox_losses(model)                                   # GBoxEff with DrTrDOF (.gearbox)
    thrust = sys.inputs("RotThrust")
    if model.hub_moments:                                           # rotor moments and forces across the shaft
        my, mz, fy, fz = sys.inputs("RotMomY RotMomZ RotFrcY RotFrcZ")
        sys.add_torque(hub, [0.0, my, mz], frame=shaft)
        sys.add_force(hub, [thrust, fy, fz], frame=shaft)
    else:
        sys.add_force(hub, [thrust, 0.0, 0.0], frame=shaft)
    if model.blade_loads:
        for k in range(model.turbine.number_of_blades):
            _body_loads(model, model.bodies[f"blade{k + 1}"], f"B{k + 1}Aero", BLADE_LOAD_INPUTS,
                        model.blade_coordinates(k))
    if model.tower_loads:
        _body_loads(model, model.bodies["tower"], "TwrAero", TOWER_LOAD_INPUTS, tower_coordinates(model))
    if getattr(model, "nacelle_loads", False):
        _body_loads(model, model.bodies["nacelle"], "NacAero", NACELLE_LOAD_INPUTS, ())
    if any(model.dofs.get(f) for f in PLATFORM_FLAGS):
        fx, fy, fz, mx, my, mz = sys.inputs("PtfmFx PtfmFy PtfmFz PtfmMx PtfmMy PtfmMz")
        sys.add_force(platform, [fx, fy, fz])
        sys.add_torque(platform, [mx, my, mz])


def _body_loads(model, body, prefix: str, components, coordinates) -> None:
    """A force and moment on ``body`` in its own axes, and a generalized force per elastic coordinate."""
    sys = model.system
    fx, fy, fz, mx, my, mz = sys.inputs([f"{prefix}{c}" for c in components])
    sys.add_force(body, [fx, fy, fz], frame=body)
    sys.add_torque(body, [mx, my, mz], frame=body)
    for c in coordinates:
        sys.add_generalized_force(model.coords[c], sys.inputs(f"{c}AeroQ"))
