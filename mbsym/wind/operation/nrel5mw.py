"""The built-in NREL 5 MW controller settings (package data, no deck needed).

``data/nrel5mw_baseline.json`` holds every number of :class:`~mbsym.wind.control.BaselineSettings`
for the NREL 5 MW as ROSCO 2.10.6 configures it: the wheel's ``Examples/Test_Cases/NREL-5MW/DISCON.IN``
(VS_ControlMode 2 with the EKF wind-speed estimator, constant power, set-point smoothing, peak
shaving, the 30-point pitch gain schedule) and the power-coefficient table its estimator uses
(``Cp_Ct_Cq.NREL5MW.txt`` of the same wheel). ``tests/wind/operation/test_operation_components.py``
regenerates the file from the DISCON.IN of the shared OpenFAST runs (the wheel's file with
LoggingLevel 0) and compares.

``data/nrel5mw_discon.json`` holds the rest of that DISCON.IN (the keys the settings do not map: modes
the baseline does not implement, their parameters, logging) and the thrust and torque tables of the
performance file, so that :func:`write_nrel5mw_discon` writes a complete DISCON.IN for ROSCO's own
library (``tests/wind/operation/test_discon_write.py`` regenerates it and runs the library on both).
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path

from ...exceptions import ControllerError, ParameterError
from ..control.settings import BaselineSettings

__all__ = ["nrel5mw_baseline_settings", "write_nrel5mw_discon", "BASELINE_DATA", "DISCON_DATA",
           "NREL5MW_CONTROLLER_DT", "NREL5MW_DISCON_FOLDER"]

BASELINE_DATA = "data/nrel5mw_baseline.json"
DISCON_DATA = "data/nrel5mw_discon.json"
#: Sub-folder of a run's output folder where the CLI writes the built-in DISCON.IN for a DISCON library.
NREL5MW_DISCON_FOLDER = "nrel5mw_rosco"
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
    data = _package_data(BASELINE_DATA, ("_source", "settings"))
    values = dict(data["settings"])
    values["cp"] = tuple(tuple(row) for row in values["cp"])
    return BaselineSettings(dt=dt, **values, source="mbsym package data: ROSCO 2.10.6 NREL-5MW DISCON.IN")


def write_nrel5mw_discon(folder, *, dt: float = NREL5MW_CONTROLLER_DT) -> Path:
    """Write ROSCO 2.10.6's NREL 5 MW ``DISCON.IN`` and its ``Cp_Ct_Cq.txt`` into ``folder`` (created).

    Every key ROSCO 2.10.6 reads, from the package data (:func:`nrel5mw_baseline_settings` and
    :data:`DISCON_DATA`; debug files off, ``LoggingLevel 0``), for ROSCO's ``libdiscon.so`` on the
    built-in turbine: ``DisconController(lib, write_nrel5mw_discon("run"), dt=0.01)``. The same
    file as the rosco wheel's ``Examples/Test_Cases/NREL-5MW/DISCON.IN`` key by key (numbers as
    stored). A DISCON.IN already in ``folder`` is replaced only if mbsym wrote it.

    Parameters
    ----------
    folder : str or Path
    dt : float, optional, keyword-only
        Controller sample time [s] the file is checked with (ROSCO takes it from the caller).

    Returns
    -------
    Path
        ``folder/DISCON.IN``.

    Raises
    ------
    ControllerError
        ``folder/DISCON.IN`` exists and is not one mbsym wrote (names it and the way out).
    """
    from ..control.discon_write import HEADER, write_discon_in
    from ..deck.performance import PerformanceTable

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "DISCON.IN"
    if path.exists() and not path.read_text(encoding="utf-8", errors="replace").startswith(HEADER):
        raise ControllerError(f"{path.absolute()} exists and was not written by mbsym; not replacing it. Move it, "
                              "pass it with --discon-input, or choose another output folder.")
    settings = nrel5mw_baseline_settings(dt)
    data = _package_data(DISCON_DATA, ("_source", "other", "ct", "cq"))
    table = PerformanceTable(settings.cp_tsr, settings.cp_pitch, settings.cp, data["ct"], data["cq"],
                             source="mbsym package data: ROSCO 2.10.6 Cp_Ct_Cq.NREL5MW.txt")
    return write_discon_in(settings, path, performance=table, other=data["other"],
                           title="NREL 5 MW, ROSCO 2.10.6 settings (mbsym package data)")


def _package_data(name: str, keys: tuple[str, ...]) -> dict:
    data = json.loads(resources.files("mbsym.wind.operation").joinpath(name).read_text(encoding="utf-8"))
    missing = [k for k in keys if k not in data]
    if missing:
        raise ParameterError(f"Package data {name} is malformed (no {missing}); reinstall mbsym.")
    return data
