"""The built-in NREL 5 MW controller settings (package data, no deck needed).

``data/nrel5mw_baseline.json`` holds every number of :class:`~mbsym.wind.control.BaselineSettings`
for the NREL 5 MW as ROSCO 2.10.6 configures it: the wheel's ``Examples/Test_Cases/NREL-5MW/DISCON.IN``
(VS_ControlMode 2 with the EKF wind-speed estimator, constant power, set-point smoothing, peak
shaving, the 30-point pitch gain schedule) and the power-coefficient table its estimator uses
(``Cp_Ct_Cq.NREL5MW.txt`` of the same wheel). ``tests/wind/operation/test_operation_data.py``
regenerates the file from the DISCON.IN of the shared OpenFAST runs (the wheel's file with
LoggingLevel 0) and compares.
"""

from __future__ import annotations

import json
from importlib import resources

from ...exceptions import ParameterError
from ..control.settings import BaselineSettings

__all__ = ["nrel5mw_baseline_settings", "BASELINE_DATA", "NREL5MW_CONTROLLER_DT"]

BASELINE_DATA = "data/nrel5mw_baseline.json"
#: Controller sample time of the built-in NREL 5 MW [s]: the built-in deck's glue time step DT
#: (ServoDyn's "default" communication interval).
NREL5MW_CONTROLLER_DT = 0.01


def nrel5mw_baseline_settings(dt: float = NREL5MW_CONTROLLER_DT) -> BaselineSettings:
    """ROSCO 2.10.6's NREL 5 MW settings for :class:`~mbsym.wind.control.BaselineController`.

    Parameters
    ----------
    dt : float, optional
        Sample time [s] (default :data:`NREL5MW_CONTROLLER_DT`).

    Examples
    --------
    >>> s = nrel5mw_baseline_settings()
    >>> s.rated_power, s.optimal_tsr, len(s.schedule_pitch)
    (5000000.0, 7.5, 30)
    """
    text = resources.files("mbsym.wind.operation").joinpath(BASELINE_DATA).read_text(encoding="utf-8")
    data = json.loads(text)
    if "_source" not in data or "settings" not in data:
        raise ParameterError(f"Package data {BASELINE_DATA} is malformed (no '_source' or 'settings'); "
                             "reinstall mbsym.")
    values = dict(data["settings"])
    values["cp"] = tuple(tuple(row) for row in values["cp"])
    return BaselineSettings(dt=dt, **values, source="mbsym package data: ROSCO 2.10.6 NREL-5MW DISCON.IN")
