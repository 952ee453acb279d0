"""The NREL 5 MW rotor aerodynamics as package data (no deck needed).

* ``data/nrel5mw_aerodyn.json``: the AeroDyn 15 blade and airfoil data of the NREL
  5 MW reference turbine -- blade geometry of Jonkman et al. 2009 (NREL/TP-500-38060,
  Table 2-1: chord, twist, airfoil stations) and its DU/NACA64 polars with
  AirfoilPrep rotational and Viterna corrections, as distributed with the OpenFAST
  r-test 5MW_Baseline deck and ROSCO 2.10.6's ``Examples/Test_Cases/NREL-5MW`` deck
  (files ``NRELOffshrBsline5MW_Onshore_AeroDyn15.dat``,
  ``NRELOffshrBsline5MW_AeroDyn_blade.dat``, ``Airfoils/*.dat``).
* ``data/Cp_Ct_Cq.NREL5MW_mbsym.txt``: Cp, Ct, Cq over TSR 1..16 × pitch -5..40 deg
  computed from those files by mbsym's steady BEM (:mod:`mbsym.wind.aero.bem`), in
  ROSCO's format, so start-up needs no BEM run.

``tests/wind/aero/test_aero_nrel5mw_data.py`` regenerates both from the shared
OpenFAST deck and compares them with the packaged files.
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path

from ...exceptions import ParameterError
from .aerodyn import AeroDynInput
from .performance import PerformanceTable, read_performance_table

__all__ = ["nrel5mw_aerodyn", "nrel5mw_performance_table", "AERODYN_DATA", "PERFORMANCE_DATA"]

AERODYN_DATA = "data/nrel5mw_aerodyn.json"
PERFORMANCE_DATA = "data/Cp_Ct_Cq.NREL5MW_mbsym.txt"


def nrel5mw_aerodyn() -> AeroDynInput:
    """The NREL 5 MW AeroDyn 15 input (options, blades, airfoil polars) from package data.

    Returns
    -------
    AeroDynInput
        Equal to ``read_aerodyn`` of the NREL 5 MW AeroDyn deck (see the module docstring).
    """
    text = resources.files("mbsym.wind.deck").joinpath(AERODYN_DATA).read_text(encoding="utf-8")
    data = json.loads(text)
    if "_source" not in data or "aerodyn" not in data:
        raise ParameterError(f"Package data {AERODYN_DATA} is malformed (no '_source' or "
                             "'aerodyn' entry); reinstall mbsym.")
    return AeroDynInput.from_dict(data["aerodyn"])


def nrel5mw_performance_table() -> PerformanceTable:
    """The NREL 5 MW Cp/Ct/Cq surfaces computed by mbsym's BEM (package data).

    Returns
    -------
    PerformanceTable
        TSR 1..16 (step 0.25) × pitch -5..40 deg (step 1 deg); radius convention:
        the in-plane tip radius 62.94 m, wind along the shaft (AeroDyn's RtAeroCp).
    """
    with resources.as_file(resources.files("mbsym.wind.deck").joinpath(PERFORMANCE_DATA)) as path:
        table = read_performance_table(Path(path))
    return table
