"""Read a ROSCO ``DISCON.IN`` controller input file into a typed record.

A ``DISCON.IN`` line is ``<value(s)>  ! <Key>  - description``; lines starting with
``!`` are comments, other lines without that form are skipped (as ROSCO does) and
listed in :attr:`DisconInput.ignored_lines`.  ROSCO finds keys anywhere in the file (order is free); so do
we (case-insensitively).  :data:`DISCON_KEYS` lists every key ROSCO 2.10.6 reads,
its type (``int``, ``float``, ``str`` or a vector of ints/floats), the key giving a
vector's length, and when the key is required (ROSCO makes most keys optional when
the mode that uses them is off).  Values keep ROSCO's units (rad, rad/s, N m, W,
m/s; ``VS_GenEff`` in %).

Checks (each reported with file, line and key, all problems of a file at once):
syntax, types, a vector's length against its count key (for keys the active modes
use), duplicate keys, the mode ranges and limits of ROSCO's ``CheckInputs``
(corner frequencies > 0, ``PC_MinPit < PC_MaxPit``, ``PC_MinRat < 0 < PC_MaxRat``,
``VS_MaxTq >= VS_RtTq``, ``IPC_SatMode`` in 0-3, ``IPC_KI >= 0``, ...), and strictly
increasing breakpoints of every table ROSCO interpolates (``PC_GS_angles``, ``PS_WindSpeeds``, ``WE_FOPoles_v``, ...).
Unknown keys are kept, as text, in :attr:`DisconInput.extra`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Callable, Mapping

import numpy as np

from ...exceptions import OpenFASTFormatError
from ._format import _INT, _real

__all__ = ["DisconInput", "read_discon_in", "DISCON_KEYS"]

_Cond = Callable[[Mapping[str, Any]], bool]
_ALWAYS: _Cond = lambda m: True  # noqa: E731


@dataclass(frozen=True)
class _Spec:
    key: str
    kind: str                      # int, float, str, ints, floats
    length: int | str | None = None  # vector length: a number or the key holding it
    required: _Cond = _ALWAYS      # required when this holds for the values read so far
    default: Any = 0


def _mode(name: str, test: Callable[[int], bool]) -> _Cond:
    return lambda m: test(int(m.get(name, 0) or 0))


def _on(name: str) -> _Cond:
    return _mode(name, lambda v: v != 0)


_S = _Spec
_FLAGS = ("F_LPFType", "IPC_ControlMode", "VS_ControlMode", "PC_ControlMode", "Y_ControlMode", "SS_Mode",
          "PRC_Mode", "WE_Mode", "PS_Mode", "SU_Mode", "SD_Mode", "Fl_Mode", "TD_Mode", "TRA_Mode", "Flp_Mode",
          "OL_Mode", "PA_Mode", "PF_Mode", "AWC_Mode", "Ext_Mode", "ZMQ_Mode", "CC_Mode", "StC_Mode")
_NOTCH = _on("F_NumNotchFilts")
_PC = _on("PC_ControlMode")
_IPC = _on("IPC_ControlMode")
_FBP = _on("VS_FBP")
_PRC = _on("PRC_Mode")
_PRC2_CONST = lambda m: m.get("PRC_Mode") == 2 and m.get("PRC_Comm", 0) == 0  # noqa: E731
_PRC2_PITCH = lambda m: m.get("PRC_Mode") == 2 and m.get("PRC_R_Pitch", 1.0) != 1.0  # noqa: E731
_WE = _on("WE_Mode")
_Y = _on("Y_ControlMode")
_SU = _on("SU_Mode")
_SD = _on("SD_Mode")
_FL = _on("Fl_Mode")
_FLP = _on("Flp_Mode")
_OL = _on("OL_Mode")
_OL2 = _mode("OL_Mode", lambda v: v == 2)
_AWC = _on("AWC_Mode")
_CC = _on("CC_Mode")
_STC = _on("StC_Mode")
_NEVER: _Cond = lambda m: False  # noqa: E731

#: Every key ROSCO 2.10.6 reads (ReadControlParameterFileSub), in file order.
DISCON_KEYS: tuple[_Spec, ...] = (
    _S("LoggingLevel", "int", required=_NEVER), _S("DT_Out", "float", required=_NEVER),
    _S("Ext_Interface", "int", required=_NEVER), _S("Echo", "int", required=_NEVER),
    *(_S(n, "int", required=_NEVER) for n in _FLAGS[:3]),
    _S("VS_ConstPower", "int", required=_NEVER), _S("VS_FBP", "int", required=_NEVER),
    *(_S(n, "int", required=_NEVER) for n in _FLAGS[3:]),
    _S("F_LPFCornerFreq", "float"), _S("F_LPFDamping", "float", required=_mode("F_LPFType", lambda v: v != 1)),
    _S("F_NumNotchFilts", "int", required=_NEVER),
    *(_S(n, "floats", "F_NumNotchFilts", _NOTCH) for n in ("F_NotchFreqs", "F_NotchBetaNum", "F_NotchBetaDen")),
    _S("F_GenSpdNotch_N", "int", required=_NOTCH), _S("F_GenSpdNotch_Ind", "ints", "F_GenSpdNotch_N",
                                                        _on("F_GenSpdNotch_N")),
    _S("F_TwrTopNotch_N", "int", required=_NOTCH), _S("F_TwrTopNotch_Ind", "ints", "F_TwrTopNotch_N",
                                                        _on("F_TwrTopNotch_N")),
    _S("F_SSCornerFreq", "float", required=_on("SS_Mode")), _S("F_WECornerFreq", "float"),
    _S("F_YawErr", "float", required=_Y), _S("F_FlCornerFreq", "floats", 2, _FL),
    _S("F_FlHighPassFreq", "float", required=_FL), _S("F_FlpCornerFreq", "floats", 2, _FLP),
    _S("F_VSRefSpdCornerFreq", "float", required=_mode("VS_ControlMode", lambda v: v >= 2)),
    _S("PC_GS_n", "int", required=_PC),
    *(_S(n, "floats", "PC_GS_n", _PC) for n in ("PC_GS_angles", "PC_GS_KP", "PC_GS_KI", "PC_GS_KD", "PC_GS_TF")),
    *(_S(n, "float", required=_PC) for n in ("PC_MaxPit", "PC_MinPit", "PC_MaxRat", "PC_MinRat", "PC_RefSpd",
                                              "PC_FinePit", "PC_Switch")),
    _S("IPC_Vramp", "floats", 2, _IPC), _S("IPC_SatMode", "int", required=_IPC),
    _S("IPC_IntSat", "float", required=_IPC), _S("IPC_KP", "floats", 2, _IPC), _S("IPC_KI", "floats", 2, _IPC),
    _S("IPC_aziOffset", "floats", 2, _IPC), _S("IPC_CornerFreqAct", "float", required=_IPC),
    _S("VS_GenEff", "float"), _S("VS_ArSatTq", "float", required=_mode("VS_ControlMode", lambda v: v == 1)),
    _S("VS_MaxRat", "float", required=_mode("VS_ControlMode", lambda v: v == 1)),
    _S("VS_MaxTq", "float"), _S("VS_MinTq", "float"), _S("VS_MinOMSpd", "float", required=_NEVER),
    _S("VS_Rgn2K", "float", required=_mode("VS_ControlMode", lambda v: v != 2)),
    _S("VS_RtPwr", "float"), _S("VS_RtTq", "float"), _S("VS_RefSpd", "float"), _S("VS_n", "int"),
    _S("VS_KP", "floats", "VS_n"), _S("VS_KI", "floats", "VS_n"),
    _S("VS_TSRopt", "float", required=_mode("VS_ControlMode", lambda v: v >= 2)),
    _S("VS_FBP_n", "int", required=_FBP),
    *(_S(n, "floats", "VS_FBP_n", _FBP) for n in ("VS_FBP_U", "VS_FBP_Omega", "VS_FBP_Tau")),
    _S("SS_VSGain", "float", required=_on("SS_Mode")), _S("SS_PCGain", "float", required=_on("SS_Mode")),
    _S("PRC_Comm", "int", required=_mode("PRC_Mode", lambda v: v == 1)),
    *(_S(n, "float", required=_PRC2_CONST, default=1.0) for n in ("PRC_R_Torque", "PRC_R_Speed", "PRC_R_Pitch")),
    _S("PRC_Table_n", "int", required=_PRC2_PITCH),
    _S("PRC_R_Table", "floats", "PRC_Table_n", _PRC2_PITCH),
    _S("PRC_Pitch_Table", "floats", "PRC_Table_n", _PRC2_PITCH),
    _S("PRC_n", "int", required=_PRC), _S("PRC_LPF_Freq", "float", required=_PRC),
    _S("PRC_WindSpeeds", "floats", "PRC_n", _PRC), _S("PRC_GenSpeeds", "floats", "PRC_n", _PRC),
    _S("WE_BladeRadius", "float"), _S("WE_CP_n", "int", required=_NEVER), _S("WE_CP", "floats", required=_NEVER),
    _S("WE_Gamma", "float", required=_mode("WE_Mode", lambda v: v == 1)), _S("WE_GearboxRatio", "float"),
    _S("WE_Jtot", "float", required=_WE), _S("WE_RhoAir", "float", required=_mode("WE_Mode", lambda v: v == 2)),
    _S("PerfFileName", "str", required=_WE, default=""), _S("PerfTableSize", "ints", 2, _WE),
    _S("WE_FOPoles_N", "int", required=_mode("WE_Mode", lambda v: v == 2)),
    _S("WE_FOPoles_v", "floats", "WE_FOPoles_N", _mode("WE_Mode", lambda v: v == 2)),
    _S("WE_FOPoles", "floats", "WE_FOPoles_N", _mode("WE_Mode", lambda v: v == 2)),
    _S("Y_uSwitch", "float", required=_Y), _S("Y_ErrThresh", "floats", 2, _Y),
    *(_S(n, "float", required=_Y) for n in ("Y_Rate", "Y_MErrSet", "Y_IPC_IntSat", "Y_IPC_KP", "Y_IPC_KI")),
    *(_S(n, "float", required=_on("TRA_Mode")) for n in ("TRA_ExclSpeed", "TRA_ExclBand", "TRA_RateLimit")),
    *(_S(n, "float", required=_on("TD_Mode")) for n in ("FA_KI", "FA_HPFCornerFreq", "FA_IntSat")),
    _S("PS_BldPitchMin_N", "int", required=_on("PS_Mode")),
    _S("PS_WindSpeeds", "floats", "PS_BldPitchMin_N", _on("PS_Mode")),
    _S("PS_BldPitchMin", "floats", "PS_BldPitchMin_N", _on("PS_Mode")),
    *(_S(n, "float", required=_SU) for n in ("SU_StartTime", "SU_FW_MinDuration", "SU_RotorSpeedThresh",
                                              "SU_RotorSpeedCornerFreq")),
    _S("SU_LoadStages_N", "int", required=_SU),
    *(_S(n, "floats", "SU_LoadStages_N", _on("SU_LoadStages_N"))
      for n in ("SU_LoadStages", "SU_LoadRampDuration", "SU_LoadHoldDuration")),
    _S("SD_TimeActivate", "float", required=_SD),
    *(_S(n, "int", required=_SD) for n in ("SD_EnablePitch", "SD_EnableYawError", "SD_EnableGenSpeed",
                                            "SD_EnableTime")),
    *(_S(n, "float", required=_SD) for n in ("SD_MaxPit", "SD_PitchCornerFreq", "SD_MaxYawError",
                                              "SD_YawErrorCornerFreq", "SD_MaxGenSpd", "SD_GenSpdCornerFreq",
                                              "SD_Time")),
    _S("SD_Method", "int", required=_SD), _S("SD_Stage_N", "int", required=_SD),
    _S("SD_StageTime", "floats", "SD_Stage_N", _mode("SD_Method", lambda v: v == 1)),
    _S("SD_StagePitch", "floats", "SD_Stage_N", _mode("SD_Method", lambda v: v == 2)),
    _S("SD_MaxTorqueRate", "floats", "SD_Stage_N", _SD), _S("SD_MaxPitchRate", "floats", "SD_Stage_N", _SD),
    _S("Fl_n", "int", required=_NEVER, default=1), _S("Fl_Kp", "floats", "Fl_n", _FL),
    _S("Fl_U", "floats", "Fl_n", lambda m: (m.get("Fl_n") or 1) > 1),
    *(_S(n, "float", required=_FLP) for n in ("Flp_Angle", "Flp_Kp", "Flp_Ki", "Flp_MaxPit")),
    _S("OL_Filename", "str", required=_OL, default="unused"), _S("OL_BP_Mode", "int", required=_OL),
    _S("OL_BP_FiltFreq", "float", required=_OL), _S("Ind_Breakpoint", "int", required=_NEVER),
    _S("Ind_BldPitch", "ints", 3, _NEVER), _S("Ind_GenTq", "int", required=_NEVER),
    _S("Ind_YawRate", "int", required=_NEVER),
    *(_S(n, "int", required=_OL2) for n in ("Ind_Azimuth", "Ind_R_Speed", "Ind_R_Torque", "Ind_R_Pitch")),
    _S("RP_Gains", "floats", 4, _OL2),
    _S("PA_CornerFreq", "float", required=_on("PA_Mode")), _S("PA_Damping", "float", required=_on("PA_Mode")),
    _S("PF_Offsets", "floats", 3, _mode("PF_Mode", lambda v: v == 1)),
    _S("PF_TimeStuck", "floats", 3, _mode("PF_Mode", lambda v: v == 2)),
    _S("AWC_NumModes", "int", required=_AWC), _S("AWC_n", "ints", "AWC_NumModes", _mode("AWC_Mode", lambda v: v == 1)),
    _S("AWC_harmonic", "ints", "AWC_NumModes", _mode("AWC_Mode", lambda v: v >= 2)),
    *(_S(n, "floats", "AWC_NumModes", _AWC) for n in ("AWC_freq", "AWC_amp", "AWC_clockangle")),
    _S("AWC_phaseoffset", "float", required=_AWC),
    _S("AWC_CntrGains", "floats", 2, _mode("AWC_Mode", lambda v: v >= 3)),
    *(_S(n, "str", required=_on("Ext_Mode"), default="unused") for n in ("DLL_FileName", "DLL_InFile",
                                                                         "DLL_ProcName")),
    _S("ZMQ_CommAddress", "str", required=_on("ZMQ_Mode"), default=""),
    _S("ZMQ_UpdatePeriod", "float", required=_on("ZMQ_Mode")), _S("ZMQ_ID", "int", required=_NEVER),
    _S("CC_Group_N", "int", required=_CC), _S("CC_GroupIndex", "ints", "CC_Group_N", _CC),
    _S("CC_ActTau", "float", required=_CC),
    _S("StC_Group_N", "int", required=_STC), _S("StC_GroupIndex", "ints", "StC_Group_N", _STC),
    _S("Ind_CableControl", "ints", "CC_Group_N", _mode("CC_Mode", lambda v: v == 2)),
    _S("Ind_StructControl", "ints", "StC_Group_N", _mode("StC_Mode", lambda v: v == 2)),
)
_BY_NAME = {s.key.lower(): s for s in DISCON_KEYS}
#: Breakpoints ROSCO interpolates (interp1d needs them strictly increasing) → the mode that uses them.
_INCREASING = {"PC_GS_angles": "PC_ControlMode", "PS_WindSpeeds": "PS_Mode", "WE_FOPoles_v": "WE_Mode",
               "VS_FBP_U": "VS_FBP", "PRC_WindSpeeds": "PRC_Mode"}
_TOKEN = re.compile(r'"[^"]*"|\'[^\']*\'|[^\s,]+')


@dataclass(frozen=True)
class DisconInput:
    """A ROSCO ``DISCON.IN`` read by :func:`read_discon_in`.

    Values are looked up by ROSCO key, case-insensitively (``d["PC_GS_KP"]``):
    ``int``/``float``/``str`` scalars and read-only numpy arrays for vectors; keys
    absent from the file give ROSCO's default (0, or as listed in :data:`DISCON_KEYS`).

    Attributes
    ----------
    path : Path
        The file read.
    values : Mapping[str, Any]
        Every value read (keys spelled as in :data:`DISCON_KEYS`).
    lines : Mapping[str, int]
        Line number of each key read.
    extra : Mapping[str, str]
        Raw text of keys ROSCO 2.10.6 does not read.
    ignored_lines : Mapping[int, str]
        Lines that are neither comments nor ``<value(s)> ! <Key>`` (ROSCO skips them too).
    """

    path: Path
    values: Mapping[str, Any]
    lines: Mapping[str, int] = field(compare=False)
    extra: Mapping[str, str] = field(default_factory=dict, compare=False)
    ignored_lines: Mapping[int, str] = field(default_factory=dict, compare=False)

    def __getitem__(self, key: str) -> Any:
        spec = _BY_NAME.get(key.lower())
        if spec is None:
            raise KeyError(f"{key!r} is not a ROSCO 2.10.6 DISCON.IN key (see DISCON_KEYS).")
        if spec.key in self.values:
            return self.values[spec.key]
        return np.zeros(0) if spec.kind in ("ints", "floats") else spec.default

    def __contains__(self, key: str) -> bool:
        spec = _BY_NAME.get(key.lower())
        return spec is not None and spec.key in self.values

    def where(self, key: str) -> str:
        """``"<file>, line <n>, key '<Key>'"`` for messages (line after the last if absent)."""
        spec = _BY_NAME.get(key.lower())
        name = spec.key if spec else key
        line = self.lines.get(name, max(self.lines.values(), default=0) + 1)
        return f"{self.path}, line {line}, key '{name}'"

    @property
    def performance_file(self) -> Path | None:
        """``PerfFileName`` resolved against the directory of the ``DISCON.IN`` (as ROSCO does)."""
        name = self["PerfFileName"]
        if not name or name == "unused":
            return None
        path = Path(name.replace("\\", "/"))
        return path if path.is_absolute() else self.path.parent / path


def _split(text: str) -> tuple[list[str], str | None]:
    """Tokens before the ``!`` (outside quotes) and the key after it."""
    tokens, key = [], None
    for match in _TOKEN.finditer(text):
        token = match.group(0)
        if token.startswith("!"):
            rest = text[match.start() + 1:].split() if token == "!" else [token[1:]] + \
                text[match.end():].split()
            key = rest[0] if rest else None
            break
        tokens.append(token)
    return tokens, key


def _convert(spec: _Spec, tokens: list[str]) -> tuple[Any, str | None]:
    if spec.kind == "str":
        if len(tokens) != 1:
            return None, f"expected one (quoted) string, got {len(tokens)} values"
        return tokens[0].strip("\"'"), None
    if spec.kind in ("int", "ints"):
        bad = [t for t in tokens if not _INT.match(t)]
        if bad:
            return None, f"expected integer(s), got {bad[0]!r}"
        values = [int(t) for t in tokens]
    else:
        values = [_real(t) for t in tokens]
        bad = [t for t, v in zip(tokens, values) if v is None]
        if bad:
            return None, f"expected finite number(s), got {bad[0]!r}"
    if spec.kind in ("int", "float"):
        if len(values) != 1:
            return None, f"expected one value, got {len(values)}"
        return values[0], None
    arr = np.array(values, dtype=int if spec.kind == "ints" else float)
    arr.setflags(write=False)
    return arr, None


class _Reader:
    def __init__(self, path: Path) -> None:
        self.path, self.problems = path, []
        self.values: dict[str, Any] = {}
        self.lines: dict[str, int] = {}
        self.extra: dict[str, str] = {}
        self.ignored: dict[int, str] = {}

    def problem(self, key: str, text: str, line: int | None = None) -> None:
        line = line if line is not None else self.lines.get(key, max(self.lines.values(), default=0) + 1)
        self.problems.append(f"{self.path}, line {line}, key '{key}': {text}")

    def parse(self, text: str) -> None:
        for number, raw in enumerate(text.splitlines(), start=1):
            line = raw.strip()
            if not line or line.startswith("!"):
                continue
            tokens, key = _split(line)
            if key is None or not tokens:
                self.ignored[number] = line  # ROSCO skips lines without '<value> ! <Key>' too
                continue
            spec = _BY_NAME.get(key.lower())
            if spec is None:
                self.extra[key] = " ".join(tokens)
                continue
            if spec.key in self.lines:
                self.problem(spec.key, f"duplicate key (also on line {self.lines[spec.key]}). Remove one.", number)
                continue
            self.lines[spec.key] = number
            value, error = _convert(spec, tokens)
            if error:
                self.problem(spec.key, f"{error}. Fix the value.", number)
            else:
                self.values[spec.key] = value

    def check_presence(self) -> None:
        for spec in DISCON_KEYS:
            needed = spec.required(self.values)
            if spec.key not in self.values:
                if needed and spec.key not in self.lines:
                    self.problem(spec.key, f"missing; the active modes need it. Add a line '<{spec.kind}>  ! "
                                 f"{spec.key}  - ...'.", max(self.lines.values(), default=0) + 1)
                continue
            if spec.kind in ("ints", "floats") and spec.length is not None and needed:
                expected = spec.length if isinstance(spec.length, int) else self.values.get(spec.length)
                got = self.values[spec.key].size
                if isinstance(expected, int) and got != expected:
                    source = "" if isinstance(spec.length, int) else \
                        f" ({spec.length} = {expected} on line {self.lines.get(spec.length, '?')})"
                    self.problem(spec.key, f"expected {expected} values{source}, got {got}. "
                                 "Make the count and the vector agree.")


def _check_ranges(r: _Reader) -> None:
    v = r.values
    ranges = {"F_LPFType": (1, 2), "IPC_ControlMode": (0, 2), "VS_ControlMode": (0, 4), "VS_ConstPower": (0, 1),
              "VS_FBP": (0, 3), "PC_ControlMode": (0, 1), "Y_ControlMode": (0, 2), "SS_Mode": (0, 1),
              "PRC_Mode": (0, 2), "WE_Mode": (0, 2), "PS_Mode": (0, 3), "SU_Mode": (0, 1), "SD_Mode": (0, 1),
              "Fl_Mode": (0, 2), "TD_Mode": (0, 1), "TRA_Mode": (0, 1), "Flp_Mode": (0, 3), "OL_Mode": (0, 2),
              "PA_Mode": (0, 2), "PF_Mode": (0, 2), "AWC_Mode": (0, 3), "Ext_Mode": (0, 1), "ZMQ_Mode": (0, 1),
              "CC_Mode": (0, 2), "StC_Mode": (0, 2), "LoggingLevel": (0, 3)}
    for key, (lo, hi) in ranges.items():
        if key in v and not lo <= v[key] <= hi:
            r.problem(key, f"must be between {lo} and {hi}; got {v[key]}.")

    def need(key: str, ok: bool, text: str) -> None:
        if key in v and not ok:
            r.problem(key, f"{text}; got {v[key]}.")
    need("F_LPFCornerFreq", v.get("F_LPFCornerFreq", 1) > 0, "must be greater than 0 [rad/s]")
    need("F_WECornerFreq", v.get("F_WECornerFreq", 1) > 0, "must be greater than 0 [rad/s]")
    if v.get("SS_Mode"):
        need("F_SSCornerFreq", v.get("F_SSCornerFreq", 1) > 0, "must be greater than 0 [rad/s] (SS_Mode = 1)")
    if v.get("F_LPFType") == 2:
        need("F_LPFDamping", v.get("F_LPFDamping", 1) > 0, "must be greater than 0 (F_LPFType = 2)")
    if v.get("PC_ControlMode"):
        need("PC_MinPit", v.get("PC_MinPit", 0) < v.get("PC_MaxPit", 1), "must be less than PC_MaxPit")
        need("PC_RefSpd", v.get("PC_RefSpd", 1) > 0, "must be greater than 0 [rad/s]")
        need("PC_MaxRat", v.get("PC_MaxRat", 1) > 0, "must be greater than 0 [rad/s]")
        need("PC_MinRat", v.get("PC_MinRat", -1) < 0, "must be less than 0 [rad/s]")
    need("VS_GenEff", 0 < v.get("VS_GenEff", 100) <= 100, "must be in (0, 100] %")
    need("VS_MaxRat", v.get("VS_MaxRat", 1) > 0, "must be greater than 0 [N m/s]")
    need("VS_Rgn2K", v.get("VS_Rgn2K", 0) >= 0, "must not be negative")
    need("VS_MaxTq", v.get("VS_MaxTq", 0) >= v.get("VS_RtTq", 0), "must not be less than VS_RtTq")
    need("VS_MinOMSpd", v.get("VS_MinOMSpd", 0) >= 0, "must not be negative [rad/s]")
    need("WE_BladeRadius", v.get("WE_BladeRadius", 1) > 0, "must be greater than 0 [m]")
    need("WE_GearboxRatio", v.get("WE_GearboxRatio", 1) > 0, "must be greater than 0")
    if v.get("WE_Mode"):
        need("WE_Jtot", v.get("WE_Jtot", 1) > 0, "must be greater than 0 [kg m^2] (WE_Mode > 0)")
    if v.get("IPC_ControlMode"):
        need("IPC_SatMode", 0 <= v.get("IPC_SatMode", 0) <= 3, "must be 0, 1, 2 or 3 (IPC_ControlMode > 0)")
        need("IPC_CornerFreqAct", v.get("IPC_CornerFreqAct", 0) >= 0, "must not be negative [rad/s] (0 disables the "
             "filter)")
        need("IPC_KI", bool(np.all(v.get("IPC_KI", np.zeros(0)) >= 0)), "must not be negative")
    if v.get("WE_Mode") == 2:
        need("WE_RhoAir", v.get("WE_RhoAir", 1) > 0, "must be greater than 0 [kg/m^3] (WE_Mode = 2)")
    for key, mode in _INCREASING.items():
        if v.get(mode) and key in v and v[key].size > 1 and np.any(np.diff(v[key]) <= 0):
            j = int(np.flatnonzero(np.diff(v[key]) <= 0)[0])
            r.problem(key, f"breakpoints must strictly increase ({mode} = {v[mode]} interpolates in them); "
                      f"entry {j + 2} ({v[key][j + 1]:g}) follows {v[key][j]:g}.")


def read_discon_in(path) -> DisconInput:
    """Read a ROSCO ``DISCON.IN`` (see the module docstring).

    Raises
    ------
    OpenFASTFormatError
        Missing file; a malformed line, value or vector; a missing key the active
        modes need; a value out of ROSCO's range; names file, line and key (all
        problems at once).

    Examples
    --------
    >>> from mbsym.wind.deck.discon_in import read_discon_in
    >>> d = read_discon_in("DISCON.IN")  # doctest: +SKIP
    >>> d["VS_ControlMode"], d["PC_GS_KP"].size, d.performance_file.name  # doctest: +SKIP
    (2, 30, 'Cp_Ct_Cq.NREL5MW.txt')
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"DISCON.IN controller input file not found: tried '{p.absolute()}'. "
                                  "Check the path (ServoDyn's DLL_InFile).")
    reader = _Reader(p)
    reader.parse(p.read_text(encoding="latin-1"))
    if not reader.problems:
        reader.check_presence()
    if not reader.problems:
        _check_ranges(reader)
    if len(reader.problems) == 1:
        raise OpenFASTFormatError(reader.problems[0])
    if reader.problems:
        raise OpenFASTFormatError(f"{len(reader.problems)} problems in {p}:\n  - " + "\n  - ".join(reader.problems))
    return DisconInput(p, MappingProxyType(dict(reader.values)), MappingProxyType(dict(reader.lines)),
                       MappingProxyType(dict(reader.extra)), MappingProxyType(dict(reader.ignored)))
