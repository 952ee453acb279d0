"""The built-in NREL 5 MW onshore reference turbine (no deck needed).

The values come from package data ``mbsym/wind/deck/data/nrel5mw.json``, generated
once from the OpenFAST v5 ElastoDyn-only base deck of the NREL 5 MW onshore
turbine (Jonkman et al. 2009, NREL/TP-500-38060; ElastoDyn files
``NREL5MW_ElastoDyn_Onshore.dat``, ``NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat``
and ``NRELOffshrBsline5MW_Blade.dat``).  The test
``tests/wind/test_wind_nrel5mw_data.py`` regenerates it from that deck and checks
that the packaged file is unchanged.
"""

from __future__ import annotations

import json
from importlib import resources
from typing import Any

from ...exceptions import ParameterError
from .parameters import TurbineParameters

__all__ = ["nrel5mw", "NREL5MW_YAW_SPRING", "NREL5MW_YAW_DAMPING"]

#: NREL 5 MW baseline ServoDyn yaw spring [N m/rad] and damper [N m s/rad] (YawSpr, YawDamp of the
#: NREL 5 MW ServoDyn input file, OpenFAST regression tests): the built-in scenes hold the nacelle
#: with them, since ElastoDyn alone leaves the yaw DOF free.
NREL5MW_YAW_SPRING, NREL5MW_YAW_DAMPING = 9.02832e9, 1.916e7

_DATA = "data/nrel5mw.json"


def _load() -> dict[str, Any]:
    text = resources.files("mbsym.wind.deck").joinpath(_DATA).read_text(encoding="utf-8")
    data = json.loads(text)
    if "_source" not in data or "parameters" not in data:
        raise ParameterError(f"Package data {_DATA} is malformed (no '_source' or "
                             "'parameters' entry); reinstall mbsym.")
    return data


def nrel5mw() -> TurbineParameters:
    """Return the NREL 5 MW onshore turbine as ElastoDyn describes it.

    All degrees of freedom of the base deck are enabled (blade flap 1 and 2,
    edge, drivetrain, generator, yaw, tower fore-aft and side-to-side 1 and 2;
    platform and pitch off).  The initial conditions are the deck's: rotor speed
    10 rpm, everything else 0 (a free-decay start from rest except the rotor).
    Change them with :func:`dataclasses.replace`.

    Returns
    -------
    TurbineParameters
        A fresh object on every call; equal to ``read_openfast`` of the base deck.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> p = nrel5mw()
    >>> p.number_of_blades, p.tower_height, round(p.hub_height, 3)
    (3, 87.6, 90.0)
    """
    return TurbineParameters.from_dict(_load()["parameters"])
