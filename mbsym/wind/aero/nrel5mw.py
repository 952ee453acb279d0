"""The built-in NREL 5 MW rotor aerodynamics (package data, no deck needed)."""

from __future__ import annotations

import functools

from ..deck.nrel5mw import nrel5mw
from ..deck.nrel5mw_aero import nrel5mw_aerodyn, nrel5mw_performance_table
from .bem import BEMRotor
from .rotor import RotorAero

__all__ = ["nrel5mw_bem_rotor", "nrel5mw_rotor"]


def nrel5mw_bem_rotor() -> BEMRotor:
    """The NREL 5 MW rotor for mbsym's BEM: AeroDyn blade/airfoils and ElastoDyn geometry.

    Hub radius 1.5 m, precone -2.5 deg, shaft tilt -5 deg, 3 blades (ElastoDyn deck of
    :func:`mbsym.wind.nrel5mw`); blade, airfoils and BEM options from
    :func:`mbsym.wind.deck.nrel5mw_aero.nrel5mw_aerodyn`.

    Examples
    --------
    >>> from mbsym.wind.aero import nrel5mw_bem_rotor
    >>> round(nrel5mw_bem_rotor().radius, 3)
    62.94
    """
    params = nrel5mw()
    return BEMRotor.from_aerodyn(nrel5mw_aerodyn(), hub_radius=params.hub_radius,
                                 precone=params.precone[0], n_blades=params.number_of_blades,
                                 shaft_tilt=params.shaft_tilt)


@functools.lru_cache(maxsize=4)
def nrel5mw_rotor(*, degree: int = 3) -> RotorAero:
    """The NREL 5 MW rotor loads from the packaged BEM surfaces (immutable, cached).

    Parameters
    ----------
    degree : int, optional, keyword-only
        Spline degree of the ct and cq interpolants (3: C², 5: C⁴).

    Returns
    -------
    RotorAero
        Radius 62.94 m (in-plane tip radius), air density 1.225 kg/m^3; the surfaces
        agree with AeroDyn's RtAeroCp/RtAeroCt within 1 % (benchmarks/README.md).

    Examples
    --------
    >>> from mbsym.wind.aero import nrel5mw_rotor
    >>> rotor = nrel5mw_rotor()
    >>> loads = rotor.steady(8.0, 0.9622, 0.0)   # 8 m/s along the shaft, 9.19 rpm
    >>> round(float(loads["cp"]), 3)
    0.484
    """
    bem = nrel5mw_bem_rotor()
    aerodyn = nrel5mw_aerodyn()
    return RotorAero(nrel5mw_performance_table(), radius=bem.radius,
                     air_density=aerodyn.air_density or 1.225, precone=bem.precone,
                     shaft_tilt=bem.shaft_tilt, degree=degree,
                     source="mbsym package data: NREL 5 MW BEM surfaces")
