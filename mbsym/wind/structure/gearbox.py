"""Gearbox losses (ElastoDyn's ``GBoxEff`` < 100 %) in the generator-azimuth equation.

ElastoDyn (``FillAugMat``, its "GBFric" terms; OpenFAST v5.0.0) multiplies the generator's side of the
generator-azimuth equation, the torque the generator asks of the low-speed shaft

    tau_G = N (J_g alpha_G + T_g)        (N gearbox ratio, J_g generator inertia [kg m^2] about the HSS,
                                           alpha_G its angular acceleration about the shaft, T_g HSS torque),

by ``k = eta^(-s)``: ``eta`` = GBoxEff / 100 and ``s`` the sign of the low-speed-shaft torque (from the previous
time step). Power flowing to the generator (``s = +1``) costs the rotor ``tau_G / eta``; flowing back
(``s = -1``), ``eta tau_G``. The extra term enters the generator-azimuth equation only. Here:

- **with DrTrDOF: exact, no change of the mass matrix.** The generator-azimuth and drivetrain-torsion equations
  differ only by the generator's side and the torsion spring and damper (the rotor turns with ``GeAz + DrTr``,
  the generator with ``N GeAz``): ``k tau_G = T_s = K DrTr + C DrTr_d``. So the losses are the generalized force
  ``-(1 - 1/k) T_s`` on ``GeAz``, with ``s = sign(T_s)``, the shaft torque itself (ElastoDyn: a step late).
- **rigid drivetrain**: the generator's inertia about the shaft is ``J_g / eta`` (power to the generator) and
  its torque ``T_g / eta`` for ``T_g >= 0``, ``eta T_g`` for ``T_g < 0`` (the torque's sign stands for the
  shaft torque's: they differ only while the generator torque is smaller than the generator's own inertia
  torque, e.g. an idling rotor slowing down, where ElastoDyn would take ``eta J_g``). The inertia so referred
  also enters the equations of the DOFs that turn the shaft about its axis (tower side-side, yaw, platform roll)
  as ElastoDyn's does not: there ``J_g (1/eta - 1)`` times the small share of those DOFs in the generator's spin,
  for the NREL 5 MW at 95 % about 1e-7 of their own inertia and 1e-5 of their coupling to the rotor.

:func:`add_gearbox_losses` adds them to a :class:`~.turbine.TurbineModel` being built; the helpers convert
between the generator torque and the low-speed-shaft torque for trims and channels.
"""

from __future__ import annotations

from typing import Any

import casadi as ca

__all__ = ["add_gearbox_losses", "generator_inertia", "generator_torque_at_shaft", "hss_torque_for", "has_losses"]


def has_losses(model) -> bool:
    """Whether the gearbox losses act in ``model`` (a TurbineModel): GBoxEff < 100 % and a generator DOF."""
    return float(model.turbine.gearbox_efficiency) < 1.0 and "GeAz" in model.coords


def generator_inertia(model) -> Any:
    """The generator's inertia about the HSS [kg m^2] in the model: ``J_g`` or, rigid drivetrain with losses,
    ``J_g / eta`` (module docstring)."""
    j = model.p["generator_inertia"]
    if has_losses(model) and "DrTr" not in model.coords:
        return j / float(model.turbine.gearbox_efficiency)
    return j


def generator_torque_at_shaft(torque: Any, efficiency: float) -> Any:
    """The HSS generator torque ``T_g`` [N m] as the rotor sees it through a lossy gearbox (before the gearbox
    ratio): ``T_g / eta`` for ``T_g >= 0``, ``eta T_g`` below (continuous in ``T_g``)."""
    eta = float(efficiency)
    if eta >= 1.0:
        return torque
    if isinstance(torque, (ca.SX, ca.MX, ca.DM)):
        return ca.fmax(torque, 0.0) / eta + ca.fmin(torque, 0.0) * eta
    return max(torque, 0.0) / eta + min(torque, 0.0) * eta


def hss_torque_for(shaft_torque: float, ratio: float, efficiency: float) -> float:
    """The generator torque [N m] that balances a low-speed-shaft torque [N m] through the gearbox (ratio ``N``,
    efficiency ``eta``): the inverse of ``N * generator_torque_at_shaft``."""
    q = float(shaft_torque) / float(ratio)
    eta = float(efficiency)
    return q * eta if q >= 0.0 else q / eta


def add_gearbox_losses(model) -> None:
    """Add the losses of the module docstring to ``model.system`` (a TurbineModel being built), after its
    generator torque (:func:`~.load_inputs.add_load_inputs`). Nothing without losses or with the rigid
    drivetrain (there :func:`generator_inertia` and :func:`generator_torque_at_shaft` carry them)."""
    if not has_losses(model) or "DrTr" not in model.coords:
        return
    eta, p, sys = float(model.turbine.gearbox_efficiency), model.p, model.system
    twist = model.coords["DrTr"]
    rate = sys.speed(twist)
    t_s = p["drivetrain_stiffness"] * twist + p["drivetrain_damping"] * rate
    # -(1 - 1/k) T_s: k = 1/eta for T_s >= 0, eta below
    sys.add_generalized_force(model.coords["GeAz"], -(1.0 - eta) * ca.fmax(t_s, 0.0)
                              - (1.0 - 1.0 / eta) * ca.fmin(t_s, 0.0))
