"""The rotor-effective model the turbine NMPC and its estimators predict with, for any deck.

Shared by ``mbsym export-discon`` and ``mbsym simulate --controller nmpc`` / ``--estimator`` so that a
deck configures the controller the same way in both (issue 21's contract):

* :func:`controller_model`: the deck's own model when it is rotor-effective; for a deck whose plant is
  blade-element (a full-field wind, shear, blade or yaw DOFs) the deck's rotor-effective model with the
  DOFs the controller models (:data:`~mbsym.wind.mpc.PREDICTION_DOFS` and
  :data:`~mbsym.wind.mpc.ESTIMATOR_DOFS` the deck switches on). The controller never sees the field:
  its estimator reads the turbine's sensors.
* :func:`full_field_wind`: whether the deck's wind is a full field; :func:`blade_element_plant`: whether the
  deck's plant is blade-element (a full field, flexible blades, shear, AeroDyn's tower or unsteady airfoils):
  then the NMPC and the EKF take their tunings for such a plant, :meth:`~mbsym.wind.mpc.NMPCTuning.full_field`,
  :meth:`~mbsym.wind.mpc.EstimatorTuning.full_field` (tuned in OpenFAST on the flexible-blade ff14_flex; with the
  rotor-effective tunings the EKF's wind on the ROSCO wheel's NREL 5 MW deck at a steady 16 m/s ran to −1.7 m/s
  and the rotor to 24 rpm; with these it holds 12.1 rpm and 5.0 MW);
* :func:`nmpc_tuning`, :func:`estimator_tuning`: the NMPC's and its estimator's tunings for the deck (full field,
  floating platform, preview, a nacelle moving in modes the estimator does not hold: :func:`flexible_nacelle`).
"""

from __future__ import annotations

import dataclasses
from typing import Callable

__all__ = ["controller_model", "full_field_wind", "blade_element_plant", "nmpc_tuning", "estimator_tuning",
           "flexible_nacelle"]


def full_field_wind(deck) -> bool:
    """Whether the deck's InflowWind is a full field (TurbSim, Bladed or HAWC boxes: WindType 3, 4, 5, 7)."""
    return deck.inflow is not None and deck.inflow.wind_type in (3, 4, 5, 7)


def blade_element_plant(deck) -> bool:
    """Whether the deck's plant is blade-element (:meth:`OperatingDeck.default_aero`), a full field included: the
    NMPC and its EKF then take the tunings made for it (``field=True`` of :func:`nmpc_tuning`,
    :func:`estimator_tuning`; module docstring)."""
    return full_field_wind(deck) or deck.default_aero() == "blade"


def nmpc_tuning(prediction, *, field: bool, preview: float | None = None, lidar: bool = False):
    """The :class:`~mbsym.wind.mpc.NMPCTuning` a deck's NMPC gets, before ``for_turbine``.

    Parameters
    ----------
    prediction : PredictionModel
        The NMPC's model (a platform DOF in it makes the tuning the floating one).
    field : bool, keyword-only
        The deck's plant is blade-element (:func:`blade_element_plant`: a full field, flexible blades, ...):
        :meth:`~mbsym.wind.mpc.NMPCTuning.full_field` on land.
    preview : float, optional, keyword-only
        A preview of the plant's own wind [s] (``mbsym simulate --preview``): the ideal-wind tuning (with a cost
        on the platform's pitch rate when floating). Otherwise :meth:`~mbsym.wind.mpc.NMPCTuning.floating` on a
        floating platform in any wind (without its platform term the speed loop pumps the platform's pitch),
        :meth:`~mbsym.wind.mpc.NMPCTuning.full_field` or :meth:`~mbsym.wind.mpc.NMPCTuning.estimated_wind` on
        land.
    lidar : bool, optional, keyword-only
        The NMPC's stage winds come from the deck's nacelle lidar: on land with ``field``,
        :meth:`~mbsym.wind.mpc.NMPCTuning.full_field_lidar`.
    """
    from ..wind.mpc.nmpc import NMPCTuning

    floating = any(s.startswith("Ptfm") for s in prediction.dofs)
    if preview is not None:
        return NMPCTuning(platform_pitch_rate_scale=5e-4) if floating else NMPCTuning()
    if floating:
        return NMPCTuning.floating()
    if field:
        return NMPCTuning.full_field_lidar() if lidar else NMPCTuning.full_field()
    return NMPCTuning.estimated_wind()


def estimator_tuning(prediction, *, field: bool, flexible: bool = False):
    """The :class:`~mbsym.wind.mpc.EstimatorTuning` a deck's NMPC estimator gets.

    :meth:`~mbsym.wind.mpc.EstimatorTuning.full_field` for a land turbine whose plant is blade-element (``field``:
    :func:`blade_element_plant`; tuned inside OpenFAST on the NREL 5 MW with flexible blades); the default
    :class:`~mbsym.wind.mpc.EstimatorTuning` otherwise, on a floating platform in any wind: the floating NMPC was
    tuned with it, and with the full-field tuning the exported floating NMPC in OpenFAST (IEA 15 MW, 13 m/s TurbSim
    field, 4 m waves, 60-660 s) ran the rotor below rated (speed RMS error 0.83 rpm against ROSCO's 0.32) and made
    11.5 % less energy than ROSCO (with the default: 0.30 rpm, 3 % more; measured,
    benchmarks/floating_nmpc_openfast.py). A floating plant whose nacelle moves in modes the estimator does not
    hold (``flexible``: :func:`flexible_nacelle`) gets :meth:`~mbsym.wind.mpc.EstimatorTuning.flexible_floating`.
    """
    from ..wind.mpc.estimator import EstimatorTuning

    floating = any(s.startswith("Ptfm") for s in prediction.dofs)
    if floating:
        return EstimatorTuning.flexible_floating() if flexible else EstimatorTuning()
    return EstimatorTuning.full_field() if field else EstimatorTuning()


def flexible_nacelle(dofs) -> bool:
    """Whether a plant with these ElastoDyn DOF flags (names switched on, or a name -> flag mapping) moves its
    nacelle in modes the estimator's model does not hold (:data:`~mbsym.wind.mpc.estimator.NACELLE_MODES`)."""
    from ..wind.mpc.estimator import NACELLE_MODES

    on = {d for d, flag in dofs.items() if flag} if isinstance(dofs, dict) else set(dofs)
    return bool(on & set(NACELLE_MODES))


def controller_model(deck, say: Callable[[str], None] | None = None):
    """The rotor-effective :class:`~mbsym.wind.operation.OperatingTurbine` the NMPC and its estimators use.

    Parameters
    ----------
    deck : OperatingDeck
    say : callable, optional
        Told one line when the model differs from the deck's plant (blade-element decks).

    The deck's tower influence on the blade inflow (``TwrPotent``, ``TwrShadow``) enters the controller's model as
    its azimuth average and its unsteady airfoils (``UA_Mod`` 3) at their steady state (the rotor-effective
    surfaces: :mod:`mbsym.wind.aero.tower_average`, :mod:`mbsym.wind.aero.blade.ua_steady`), and ``say`` is told.
    Its prediction model keeps the plant's tower drag (:class:`~mbsym.wind.mpc.prediction.PredictionModel`).

    Raises
    ------
    OpenFASTFormatError
        The deck's AeroDyn asks for what neither rotor models: the controller's model cannot be built from it.
    """
    from ..wind.mpc import ESTIMATOR_DOFS, PREDICTION_DOFS

    if deck.default_aero() == "rotor":
        return deck.model()
    dofs = [d for d in dict.fromkeys(PREDICTION_DOFS + ESTIMATOR_DOFS) if deck.turbine.dofs.get(d, False)]
    if say is not None:
        say(f"the deck's plant is blade-element; the NMPC and its estimators use its rotor-effective model with "
            f"{', '.join(dofs)}")
    from ..exceptions import OpenFASTFormatError

    if deck.aerodyn is not None and say is not None:
        from ..wind.aero.tower import TowerAero

        tower = TowerAero.from_aerodyn(deck.aerodyn)
        held = (["the tower's influence on the blade inflow as its azimuth average"]
                if tower is not None and tower.disturbs_inflow else []) + \
            ([f"UA_Mod {deck.aerodyn.unsteady_model} at its steady state"] if deck.aerodyn.unsteady_model else [])
        if held:
            say(f"the controller's model holds {' and '.join(held)}; the plant has them blade by blade")
    try:
        return dataclasses.replace(deck, inflow=None).model(dofs=dofs, aero="rotor")
    except OpenFASTFormatError as exc:
        raise OpenFASTFormatError(f"the NMPC and its estimators predict with the deck's rotor-effective model, which "
                                  f"this deck's AeroDyn rules out: {exc}") from exc
