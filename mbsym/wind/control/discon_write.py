"""Write ROSCO's ``DISCON.IN`` (and the performance file it names) from :class:`BaselineSettings`.

The inverse of :meth:`BaselineSettings.from_discon`: every key of
:data:`~mbsym.wind.deck.discon_in.DISCON_KEYS` (all the keys ROSCO 2.10.6 reads) is written, one per
line in ROSCO's layout ``<value(s)>   ! <Key>``. The keys of :data:`~.settings.DISCON_MAP` (and of
:data:`~.settings.IPC_MAP` / :data:`~.settings.ACTUATOR_MAP` when their mode is on) come from the
settings, converted back to ROSCO's units (``VS_GenEff`` in %); so do, when the settings have them, the
generator-speed notch filters (``F_NumNotchFilts``, ``F_Notch*``, ``F_GenSpdNotch_N``/``_Ind``), the tower
damper (:data:`~.settings.TOWER_DAMPER_MAP`), the power reference (:data:`~.settings.POWER_REFERENCE_MAP`
with ``PRC_Comm`` 0, ``PRC_n``, ``PRC_Table_n``), the shut-down (:data:`~.shutdown.SHUTDOWN_MAP`, ``SD_Stage_N``;
``SD_MaxYawError`` in deg) and the start-up (:data:`~.startup.STARTUP_MAP`, ``SU_LoadStages_N``); the lengths
of their vectors (``PC_GS_n``, ``VS_n``, ``WE_FOPoles_N``, ``PS_BldPitchMin_N``) and the performance file
(``PerfFileName``, ``PerfTableSize``) follow from them; every other key takes its value from
``other`` (the modes the baseline does not implement, their parameters, logging), else ROSCO's
default (0, or as :data:`~mbsym.wind.deck.discon_in.DISCON_KEYS` lists). The settings' power
table is written with the thrust and torque tables of ``performance`` into the file ROSCO reads
next to the ``DISCON.IN`` (ROSCO 2.10.6 reads all three; its estimator uses the power table).

The file is read back with :func:`~mbsym.wind.deck.discon_in.read_discon_in` and
:meth:`BaselineSettings.from_discon` before returning, so a file that mbsym would not run the same
way is never left behind silently.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

import numpy as np

from ...exceptions import ControllerError, ParameterError
from .settings import ACTUATOR_MAP, DISCON_MAP, IPC_MAP, POWER_REFERENCE_MAP, TOWER_DAMPER_MAP, BaselineSettings
from .shutdown import SHUTDOWN_MAP
from .startup import STARTUP_MAP

__all__ = ["write_discon_in", "discon_in_values", "HEADER"]

#: First line of every DISCON.IN this module writes (how an earlier one is recognised).
HEADER = "! ROSCO controller input file written by mbsym (mbsym.wind.control.discon_write)"


def discon_in_values(settings: BaselineSettings, *, other: Mapping[str, Any] | None = None,
                     performance_file: str = "Cp_Ct_Cq.txt") -> dict[str, Any]:
    """Every key ROSCO 2.10.6 reads with its value (ROSCO's units), in ROSCO's order.

    Parameters
    ----------
    settings : BaselineSettings
    other : mapping, optional, keyword-only
        Values of the keys the settings do not hold (unknown keys are refused).
    performance_file : str, optional, keyword-only
        ``PerfFileName`` (relative to the DISCON.IN).

    Raises
    ------
    ControllerError
        Settings with the floating feedback on (``floating_mode``): not written yet.
    ParameterError
        ``other`` names keys ROSCO does not read, or gives a key the settings hold.
    """
    from ..deck.discon_in import DISCON_KEYS

    keys = [s.key for s in DISCON_KEYS]
    other = dict(other or {})
    unknown = sorted(set(other) - set(keys))
    if unknown:
        raise ParameterError(f"other names keys ROSCO 2.10.6 does not read: {unknown}.")
    if settings.floating_mode:
        raise ControllerError("write_discon_in does not write the floating feedback (floating_mode "
                              f"{settings.floating_mode}); write that DISCON.IN by hand or with ROSCO's tuning.")
    derived = _from_settings(settings, performance_file)
    clash = sorted(set(other) & set(derived))
    if clash:
        raise ParameterError(f"other gives keys the settings hold: {clash}; change the settings instead.")
    defaults = {s.key: s.default for s in DISCON_KEYS}
    return {k: derived[k] if k in derived else other.get(k, defaults[k]) for k in keys}


def _from_settings(s: BaselineSettings, performance_file: str) -> dict[str, Any]:
    """The keys the settings give, in ROSCO's units."""
    out: dict[str, Any] = {key: getattr(s, attr) for key, attr in DISCON_MAP.items()}
    out["VS_GenEff"] = float(f"{100.0 * s.generator_efficiency:.12g}")              # fraction -> %
    out["VS_KP"], out["VS_KI"] = [s.torque_kp], [s.torque_ki]
    for key in ("VS_ConstPower", "SS_Mode", "PS_Mode"):
        out[key] = int(bool(out[key]))
    out.update(PC_GS_n=len(s.schedule_pitch), VS_n=1, WE_FOPoles_N=len(s.estimator_wind_speeds),
               PS_BldPitchMin_N=len(s.min_pitch_wind_speeds), PerfFileName=performance_file,
               PerfTableSize=[len(s.cp_pitch), len(s.cp_tsr)])
    for mode, table in (("ipc_mode", IPC_MAP), ("actuator_mode", ACTUATOR_MAP), ("tower_damper_mode", TOWER_DAMPER_MAP),
                        ("power_reference_mode", POWER_REFERENCE_MAP)):
        if getattr(s, mode):
            out.update({key: getattr(s, attr) for key, attr in table.items()})
    if s.power_reference_mode:
        out.update(PRC_Comm=0, PRC_n=len(s.power_reference_wind_speeds), PRC_Table_n=len(s.power_rating_table))
    if s.shutdown_mode:
        out.update({key: getattr(s, attr) for key, attr in SHUTDOWN_MAP.items() if getattr(s, attr) != ()})
        out.update(SD_MaxYawError=float(f"{np.rad2deg(s.shutdown_max_yaw_error):.12g}"),
                   SD_Stage_N=len(s.shutdown_pitch_rates))
    if s.startup_mode:
        out.update({key: getattr(s, attr) for key, attr in STARTUP_MAP.items()}, SU_LoadStages_N=len(s.startup_loads))
    n = len(s.speed_notch_freqs)
    if n:
        out.update(F_NumNotchFilts=n, F_NotchFreqs=s.speed_notch_freqs, F_NotchBetaNum=s.speed_notch_beta_num,
                   F_NotchBetaDen=s.speed_notch_beta_den, F_GenSpdNotch_N=n, F_GenSpdNotch_Ind=list(range(1, n + 1)))
    return out


def write_discon_in(settings: BaselineSettings, path, *, performance=None, other: Mapping[str, Any] | None = None,
                    title: str = "") -> Path:
    """Write ``settings`` as a ROSCO ``DISCON.IN`` at ``path`` and its performance file beside it.

    Parameters
    ----------
    settings : BaselineSettings
    path : str or Path
        The DISCON.IN to write (overwritten); its folder must exist.
    performance : PerformanceTable, optional, keyword-only
        Thrust and torque tables (and the grid) of the performance file; required when the settings use
        the wind-speed estimator (``wind_estimator = 2``), whose power table must equal ``performance.cp``.
        Written as ``Cp_Ct_Cq.txt`` beside ``path`` (``<stem>_Cp_Ct_Cq.txt`` for another stem).
    other : mapping, optional, keyword-only
        Values of the keys the settings do not hold (see :func:`discon_in_values`).
    title : str, optional, keyword-only
        A second comment line (e.g. the turbine).

    Returns
    -------
    Path
        The DISCON.IN written.

    Raises
    ------
    ParameterError
        No performance table for the estimator, or one whose grid or power table differs from the settings'.
    ControllerError
        See :func:`discon_in_values`; or a written file that does not read back as ``settings``.

    Examples
    --------
    >>> from mbsym.wind.operation.nrel5mw import write_nrel5mw_discon   # writes the package's NREL 5 MW one
    """
    from ..deck.performance import write_performance_table

    path = Path(path)
    perf_name = "Cp_Ct_Cq.txt" if path.stem == "DISCON" else f"{path.stem}_Cp_Ct_Cq.txt"
    values = discon_in_values(settings, other=other, performance_file=perf_name)
    if settings.wind_estimator == 2:
        write_performance_table(_checked_table(settings, performance), path.parent / perf_name,
                                turbine_name=title or "mbsym")
    lines = [HEADER] + ([f"! {title}"] if title else []) + \
        ["! Keys mapped to BaselineSettings are marked with the attribute; the others are the modes and",
         "! parameters mbsym's baseline does not model (see mbsym.wind.control.settings).", ""]
    attrs = {**DISCON_MAP, **IPC_MAP, **ACTUATOR_MAP, **TOWER_DAMPER_MAP, **POWER_REFERENCE_MAP, **SHUTDOWN_MAP,
             **STARTUP_MAP}
    for key, value in values.items():
        note = f" - BaselineSettings.{attrs[key]}" if key in attrs else ""
        lines.append(f"{_format(value):<23s} ! {key}{note}")
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    _check_round_trip(settings, path)
    return path


def _checked_table(settings: BaselineSettings, table):
    from ..deck.performance import PerformanceTable

    if not isinstance(table, PerformanceTable):
        raise ParameterError("the settings use the wind-speed estimator (wind_estimator = 2): pass performance= a "
                             "PerformanceTable with the thrust and torque tables on the settings' grid.")
    same = (np.array_equal(table.tsr, np.asarray(settings.cp_tsr)) and
            np.array_equal(table.pitch, np.asarray(settings.cp_pitch)) and
            np.allclose(table.cp, np.asarray(settings.cp), rtol=0.0, atol=5e-7))     # 6 decimals in the file
    if not same:
        raise ParameterError("performance must have the settings' grid (cp_tsr, cp_pitch) and power table (cp); "
                             "it differs, so the library's estimator would use another table.")
    return table


def _format(value: Any) -> str:
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (bool, np.bool_)):
        return str(int(value))
    if isinstance(value, (list, tuple, np.ndarray)):
        return "  ".join(_format(v) for v in np.asarray(value).reshape(-1).tolist())
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return repr(float(value))


def _check_round_trip(settings: BaselineSettings, path: Path) -> None:
    """The file reads back as ``settings`` (same ROSCO features, same numbers)."""
    back = BaselineSettings.from_discon(path, dt=settings.dt)
    keep = {"source"}
    differ = [f for f in settings.__dataclass_fields__ if f not in keep and
              not np.allclose(np.asarray(getattr(back, f), dtype=float), np.asarray(getattr(settings, f), dtype=float),
                              rtol=1e-12, atol=5e-7)]
    if differ:
        raise ControllerError(f"{path}: the DISCON.IN written does not read back as the settings ({differ}); "
                              "please report this.")
