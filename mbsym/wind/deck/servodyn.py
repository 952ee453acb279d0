"""Read an OpenFAST ServoDyn input file: control modes, generator and Bladed-DLL settings.

What a controller in the loop needs: the pitch and torque control modes
(``PCMode``, ``VSContrl``; 5 = Bladed-style DLL), the generator efficiency and
start/stop times, the simple variable-speed controller, and the Bladed interface
(``DLL_FileName``, ``DLL_InFile``, ``DLL_ProcName``, ``DLL_DT``, the swap-array
parameters of records 5-9, 13, 16-19, 22, 28 and the torque-speed look-up table).
Values are converted to SI units (deg → rad, rpm → rad/s, % → fraction); the DLL
and its input file are resolved relative to the ServoDyn file, as ServoDyn does
(they need not exist to read the file: :attr:`ServoDynSettings.library_exists`).
Keys not listed in :data:`SERVODYN_KEYS` are kept, as text, in ``extra``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError
from ._format import _Deck, _Key, _read_keys, _read_table_columns, _resolve as _resolve_key, _TableSpec

__all__ = ["ServoDynSettings", "read_servodyn", "deck_servodyn", "SERVODYN_KEYS"]

_DEG, _RPM, _PCT = math.pi / 180.0, math.pi / 30.0, 0.01
_k = _Key
_MODE = {"PCMode": (0, 3, 4, 5), "VSContrl": (0, 1, 3, 4, 5), "YCMode": (0, 3, 4, 5), "HSSBrMode": (0, 1, 3, 4, 5)}


def _one_of(allowed: tuple[int, ...], what: str):
    return (lambda v: v in allowed, f"must be one of {', '.join(map(str, allowed))} ({what})")


_KEYS = (
    _k("DT", "time_step", "float|default", check=(lambda v: v > 0, "must be greater than 0")),
    _k("PCMode", "pitch_control_mode", "int", check=_one_of(_MODE["PCMode"], "5 = Bladed-style DLL")),
    _k("TPCOn", "pitch_control_start_time", default=0.0),
    _k("VSContrl", "torque_control_mode", "int", check=_one_of(_MODE["VSContrl"], "5 = Bladed-style DLL")),
    _k("GenModel", "generator_model", "int", check=_one_of((1, 2, 3), "1 simple, 2 Thevenin, 3 user")),
    _k("GenEff", "generator_efficiency", scale=_PCT, check=(lambda v: 0 <= v <= 100, "must be in [0, 100] %")),
    _k("GenTiStr", "generator_start_timed", "bool"),
    _k("GenTiStp", "generator_stop_timed", "bool"),
    _k("SpdGenOn", "generator_start_speed", scale=_RPM),
    _k("TimGenOn", "generator_start_time"),
    _k("TimGenOf", "generator_stop_time"),
    _k("VS_RtGnSp", "simple_vs_rated_generator_speed", scale=_RPM),
    _k("VS_RtTq", "simple_vs_rated_torque"),
    _k("VS_Rgn2K", "simple_vs_region2_gain", scale=1.0 / _RPM**2),
    _k("VS_SlPc", "simple_vs_slip", scale=_PCT),
    _k("HSSBrMode", "hss_brake_mode", "int", check=_one_of(_MODE["HSSBrMode"], "brake model")),
    _k("YCMode", "yaw_control_mode", "int", check=_one_of(_MODE["YCMode"], "yaw control")),
    _k("DLL_FileName", "library_name", "str"),
    _k("DLL_InFile", "library_input_name", "str"),
    _k("DLL_ProcName", "procedure_name", "str", default="DISCON"),
    _k("DLL_DT", "library_time_step", "float|default", check=(lambda v: v > 0, "must be greater than 0")),
    _k("DLL_Ramp", "library_ramp", "bool", default=False),
    _k("BPCutoff", "pitch_filter_cutoff", scale=2 * math.pi, check=(lambda v: v > 0, "must be greater than 0")),
    _k("NacYaw_North", "nacelle_yaw_north", scale=_DEG, default=0.0),
    _k("Ptch_Cntrl", "individual_pitch", "int", check=_one_of((0, 1), "0 collective, 1 individual")),
    _k("Ptch_SetPnt", "pitch_setpoint", scale=_DEG),
    _k("Ptch_Min", "pitch_min", scale=_DEG),
    _k("Ptch_Max", "pitch_max", scale=_DEG),
    _k("PtchRate_Min", "pitch_rate_min", scale=_DEG),
    _k("PtchRate_Max", "pitch_rate_max", scale=_DEG),
    _k("Gain_OM", "optimal_mode_gain"),
    _k("GenSpd_MinOM", "optimal_mode_min_speed", scale=_RPM),
    _k("GenSpd_MaxOM", "optimal_mode_max_speed", scale=_RPM),
    _k("GenSpd_Dem", "demanded_speed", scale=_RPM),
    _k("GenTrq_Dem", "demanded_torque"),
    _k("GenPwr_Dem", "demanded_power"),
    _k("DLL_NumTrq", "n_torque_table", "int", check=(lambda v: v >= 0, "must not be negative")),
    _k("EXavrSWAP", "extended_swap", "bool", default=False),
    # settings that act on DOFs mbsym models (mbsym.wind.deck.servo_audit: modelled or refused);
    # optional here so that older or trimmed files still read: the defaults are "off"/"never"
    _k("TPitManS(*)", "pitch_maneuver_start_time", default=math.inf),
    _k("THSSBrDp", "hss_brake_start_time", default=math.inf),
    _k("HSSBrDT", "hss_brake_deploy_time", default=0.0, check=(lambda v: v >= 0, "must not be negative")),
    _k("HSSBrTqF", "hss_brake_torque", default=0.0, check=(lambda v: v >= 0, "must not be negative")),
    _k("TYCOn", "yaw_control_start_time", default=math.inf),
    _k("YawNeut", "yaw_neutral", scale=_DEG, default=0.0,
       check=(lambda v: -180 < v <= 180, "must be in (-180, 180] deg (ServoDyn's range)")),
    _k("YawSpr", "yaw_spring", default=0.0, check=(lambda v: v >= 0, "must not be negative [N m/rad]")),
    _k("YawDamp", "yaw_damping", default=0.0, check=(lambda v: v >= 0, "must not be negative [N m s/rad]")),
    _k("TYawManS", "yaw_maneuver_start_time", default=math.inf),
    _k("YawManRat", "yaw_maneuver_rate", scale=_DEG, default=0.0),
    _k("NacYawF", "yaw_maneuver_final", scale=_DEG, default=0.0),
    _k("AfCmode", "airfoil_control_mode", "int", default=0),
    _k("NumBStC", "n_blade_structural_controllers", "int", default=0),
    _k("NumNStC", "n_nacelle_structural_controllers", "int", default=0),
    _k("NumTStC", "n_tower_structural_controllers", "int", default=0),
    _k("NumSStC", "n_substructure_structural_controllers", "int", default=0),
    _k("CCmode", "cable_control_mode", "int", default=0),
)
_TABLE = _TableSpec("torque-speed look-up table", "DLL_NumTrq", ("genspd_tlu",), (
    ("GenSpd_TLU", "torque_table_speed", _RPM, True), ("GenTrq_TLU", "torque_table_torque", None, True)))
#: ServoDyn key → :class:`ServoDynSettings` attribute (deg → rad, rpm → rad/s, % → fraction, Hz → rad/s).
SERVODYN_KEYS = {k.key: k.attr for k in _KEYS} | {c[0]: f"{c[1]} (table column)" for c in _TABLE.columns}


@dataclass(frozen=True)
class ServoDynSettings:
    """ServoDyn settings in SI units (see :data:`SERVODYN_KEYS` for the key of each attribute).

    ``time_step`` and ``library_time_step`` may be ``"default"`` (the glue-code time
    step, resp. ``time_step``): see :meth:`controller_time_step`.  ``library`` and
    ``library_input`` are the DLL and its input file resolved against the
    ServoDyn file's directory.
    """

    time_step: float | str
    pitch_control_mode: int
    pitch_control_start_time: float
    torque_control_mode: int
    generator_model: int
    generator_efficiency: float
    generator_start_timed: bool
    generator_stop_timed: bool
    generator_start_speed: float
    generator_start_time: float
    generator_stop_time: float
    simple_vs_rated_generator_speed: float
    simple_vs_rated_torque: float
    simple_vs_region2_gain: float
    simple_vs_slip: float
    hss_brake_mode: int
    yaw_control_mode: int
    library_name: str
    library_input_name: str
    procedure_name: str
    library_time_step: float | str
    library_ramp: bool
    pitch_filter_cutoff: float
    nacelle_yaw_north: float
    individual_pitch: int
    pitch_setpoint: float
    pitch_min: float
    pitch_max: float
    pitch_rate_min: float
    pitch_rate_max: float
    optimal_mode_gain: float
    optimal_mode_min_speed: float
    optimal_mode_max_speed: float
    demanded_speed: float
    demanded_torque: float
    demanded_power: float
    n_torque_table: int
    extended_swap: bool
    torque_table_speed: np.ndarray
    torque_table_torque: np.ndarray
    library: Path
    library_input: Path
    path: str
    pitch_maneuver_start_time: list = field(default_factory=lambda: [math.inf] * 3)
    hss_brake_start_time: float = math.inf
    hss_brake_deploy_time: float = 0.0
    hss_brake_torque: float = 0.0
    yaw_control_start_time: float = math.inf
    yaw_neutral: float = 0.0
    yaw_spring: float = 0.0
    yaw_damping: float = 0.0
    yaw_maneuver_start_time: float = math.inf
    yaw_maneuver_rate: float = 0.0
    yaw_maneuver_final: float = 0.0
    airfoil_control_mode: int = 0
    n_blade_structural_controllers: int = 0
    n_nacelle_structural_controllers: int = 0
    n_tower_structural_controllers: int = 0
    n_substructure_structural_controllers: int = 0
    cable_control_mode: int = 0
    extra: dict = field(default_factory=dict, compare=False)
    lines: dict = field(default_factory=dict, compare=False)

    @property
    def uses_library(self) -> bool:
        """Whether pitch or torque is controlled by the Bladed-style DLL (mode 5)."""
        return self.pitch_control_mode == 5 or self.torque_control_mode == 5

    @property
    def library_exists(self) -> bool:
        """Whether the DLL file named by ``DLL_FileName`` exists."""
        return self.library.is_file()

    def controller_time_step(self, glue_time_step: float) -> float:
        """The DLL's communication interval [s]: ``DLL_DT``, else ``DT``, else the glue step."""
        for value in (self.library_time_step, self.time_step):
            if value != "default":
                return float(value)
        return float(glue_time_step)


def _resolve(base: Path, name: str) -> Path:
    path = Path(name.replace("\\", "/"))
    return path if path.is_absolute() else base.parent / path


def read_servodyn(path) -> ServoDynSettings:
    """Read a ServoDyn input file (see the module docstring).

    Raises
    ------
    OpenFASTFormatError
        Missing file or key, malformed value, unsupported mode, a look-up table whose
        row count differs from ``DLL_NumTrq``; names the file, line and key.

    Examples
    --------
    >>> from mbsym.wind.deck.servodyn import read_servodyn
    >>> srv = read_servodyn("NRELOffshrBsline5MW_Onshore_ServoDyn.dat")  # doctest: +SKIP
    >>> srv.uses_library, srv.library_input.name, round(srv.generator_efficiency, 3)  # doctest: +SKIP
    (True, 'DISCON.IN', 0.944)
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"ServoDyn input file not found: tried '{p.absolute()}'. Check the path.")
    deck = _Deck(p, (_TABLE,))
    values = _read_keys(deck, _KEYS)
    table: dict = {}
    if values.get("n_torque_table"):
        _read_table_columns(deck, _TABLE, table)
    if values.get("pitch_control_mode") == 5 and values.get("library_name") in ("", "unused"):
        deck.problem(deck.line_of("DLL_FileName"), "DLL_FileName", "PCMode = 5 needs a Bladed-style DLL; got "
                     f"{values['library_name']!r}. Give the library file.")
    deck.raise_problems()
    speeds = np.asarray(table.get("torque_table_speed", np.zeros(0)), dtype=float)
    torques = np.asarray(table.get("torque_table_torque", np.zeros(0)), dtype=float)
    names = [k.key.replace("(*)", f"({b})") for k in _KEYS for b in ((1, 2, 3) if "(*)" in k.key else (0,))]
    lines = {n: deck.line_of(n) for n in names if n.replace("(", "").replace(")", "").lower() in deck.entries}
    return ServoDynSettings(**values, torque_table_speed=speeds, torque_table_torque=torques,
                            library=_resolve(p, values["library_name"]),
                            library_input=_resolve(p, values["library_input_name"]),
                            path=str(p), extra=deck.extra(), lines=lines)


def deck_servodyn(fst) -> tuple[ServoDynSettings | None, float]:
    """The ServoDyn settings a main ``.fst`` file names (``CompServo = 1``, ``ServoFile``), and the glue ``DT`` [s].

    Returns ``(None, DT)`` when ``CompServo = 0``.  ``DT`` is what ``"default"`` time
    steps of ServoDyn resolve to (:meth:`ServoDynSettings.controller_time_step`).

    Raises
    ------
    OpenFASTFormatError
        Missing or malformed ``.fst`` keys, a missing ServoDyn file (file, line, key).
    """
    p = Path(fst)
    if not p.is_file():
        raise OpenFASTFormatError(f"OpenFAST main input file not found: tried '{p.absolute()}'. Check the path.")
    deck = _Deck(p)
    mode = deck.value(_k("CompServo", "", "int", check=(lambda v: v in (0, 1), "must be 0 or 1")))
    dt = deck.value(_k("DT", "", check=(lambda v: v > 0, "must be greater than 0")))
    deck.value(_k("ServoFile", "", "str", default=""))
    deck.raise_problems()
    if mode != 1:
        return None, dt
    return read_servodyn(_resolve_key(deck, "ServoFile", "ServoDyn input file")), dt
