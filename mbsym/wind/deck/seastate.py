"""Read an OpenFAST SeaState input file: water, waves (still, regular, JONSWAP, external), current.

SeaState reads its file line by line (``SeaState_Input.f90``); :func:`read_seastate` does
the same (:class:`~mbsym.wind.deck._lines._Lines`), keeping every key: environment
(``WtrDens``, ``WtrDpth``, ``MSL2SWL``, each ``"default"`` = the ``.fst`` value), the wave
grid, the wave model (``WaveMod`` 0 still water, 1 regular, ``1P<deg>`` regular with a
given phase, 2 JONSWAP/Pierson–Moskowitz, 3 white noise, 4 user spectrum, 5 external
elevation series ``WvKinFile + ".Elev"``, 6 external kinematics), the spectrum
(``WaveHs``, ``WaveTp``, ``WavePkShp`` — ``"default"`` resolved as SeaState does, see
:func:`default_peak_shape` — cut-offs, direction, spreading, seeds), the second-order and
constrained-wave switches, the current, MacCamy–Fuchs, and the output points and channels.

Angles are in rad (the file's deg); frequencies in rad/s as in the file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from ._lines import _Lines

__all__ = ["SeaStateInput", "read_seastate", "default_peak_shape", "WAVE_MODELS"]

_DEG = math.pi / 180.0
#: SeaState WaveMod → meaning (10 is mbsym's code for ``1P#``: regular with a given phase, as SeaState's own).
WAVE_MODELS = {0: "still water", 1: "regular", 10: "regular with a given phase", 2: "JONSWAP/Pierson-Moskowitz",
               3: "white noise", 4: "user spectrum", 5: "external elevation series", 6: "external wave kinematics",
               7: "wave components from a file"}


def default_peak_shape(wave_model: int, hs: float, tp: float) -> float:
    """SeaState's default JONSWAP peak-shape parameter γ (IEC 61400-3; SeaState ``Waves.f90``).

    γ = 5 for Tp/√Hs ≤ 3.6 s/√m, 1 for Tp/√Hs ≥ 5, exp(5.75 − 1.15 Tp/√Hs) between; 1 for
    other wave models or Hs ≤ 0.

    Examples
    --------
    >>> round(default_peak_shape(2, 1.10, 8.52), 6)
    1.0
    >>> round(default_peak_shape(2, 4.0, 8.0), 4)
    3.1582
    """
    if wave_model != 2 or hs <= 0:
        return 1.0
    ratio = tp / math.sqrt(hs)
    return 5.0 if ratio <= 3.6 else 1.0 if ratio >= 5.0 else math.exp(5.75 - 1.15 * ratio)


@dataclass(frozen=True)
class SeaStateInput:
    """SeaState settings (SI units, angles in rad). ``"default"`` where the file says so
    for ``water_density``, ``water_depth``, ``msl_to_swl`` and ``domain_depth`` (the ``.fst``'s
    values, see :meth:`resolved`)."""

    water_density: float | str
    water_depth: float | str
    msl_to_swl: float | str
    x_half_width: float
    y_half_width: float
    domain_depth: float | str
    nx: int
    ny: int
    nz: int
    wave_model: int
    wave_phase: float
    stretching_model: int
    wave_current_model: int
    wave_time_max: float
    wave_time_step: float
    wave_height: float
    peak_period: float
    peak_shape: float
    low_cutoff: float
    high_cutoff: float
    wave_direction: float
    direction_model: int
    direction_spread: float
    n_directions: int
    direction_range: float
    seeds: tuple[int, int | str]
    normal_amplitudes: bool
    kinematics_file: str
    difference_qtf: bool
    sum_qtf: bool
    qtf_cutoffs: tuple[float, float, float, float]
    constrained_wave_model: int
    crest: tuple[float, float, float, float]
    current_model: int
    current_subsurface_speed: float
    current_subsurface_direction: float | str
    current_near_surface_depth: float
    current_near_surface_speed: float
    current_near_surface_direction: float
    current_uniform_speed: float
    current_uniform_direction: float
    maccamy_fuchs_radius: float
    elevation_points: tuple[tuple[float, float], ...]
    kinematics_points: tuple[tuple[float, float, float], ...]
    outputs: tuple[str, ...]
    path: str
    lines: dict = field(default_factory=dict, compare=False)

    @property
    def wave_model_name(self) -> str:
        """``"still water"``, ``"regular"``, ``"JONSWAP/Pierson-Moskowitz"``, …"""
        return WAVE_MODELS.get(self.wave_model, "unknown")

    @property
    def elevation_file(self) -> Path | None:
        """The external wave-elevation series (``WvKinFile + ".Elev"``) for WaveMod 5, else None."""
        if self.wave_model != 5:
            return None
        path = Path(self.kinematics_file.replace("\\", "/") + ".Elev")
        return path if path.is_absolute() else Path(self.path).parent / path

    @property
    def components_file(self) -> Path | None:
        """The wave-component file (``WvKinFile`` itself) for WaveMod 7, else None."""
        if self.wave_model != 7:
            return None
        path = Path(self.kinematics_file.replace("\\", "/"))
        return path if path.is_absolute() else Path(self.path).parent / path

    def resolved(self, water_density: float, water_depth: float, msl_to_swl: float = 0.0) -> dict[str, float]:
        """Water density [kg/m^3], depth [m] and MSL-to-SWL offset [m], ``"default"`` replaced by the given ``.fst`` values."""
        pick = (lambda v, d: float(d) if v == "default" else float(v))
        return {"water_density": pick(self.water_density, water_density),
                "water_depth": pick(self.water_depth, water_depth),
                "msl_to_swl": pick(self.msl_to_swl, msl_to_swl)}


def _wave_model(f: _Lines) -> tuple[int | None, float]:
    """``WaveMod``: an integer, or ``1P<phase deg>`` (regular waves with a given phase)."""
    text = f.key("WaveMod", "str")
    if text is None:
        return None, 0.0
    line = f.line_of["WaveMod"]
    if text.upper().startswith("1P"):
        try:
            return 10, float(text[2:]) * _DEG
        except ValueError:
            f.problem(line, "WaveMod", f"'1P' must be followed by the wave phase in deg (e.g. 1P45); got {text!r}.")
            return None, 0.0
    if text.lstrip("+-").isdigit() and int(text) in WAVE_MODELS:
        return int(text), 0.0
    names = ", ".join(f"{k}: {v}" for k, v in WAVE_MODELS.items() if k != 10)
    f.problem(line, "WaveMod", f"must be 0-7 or 1P<phase> ({names}); got {text!r}. Fix the value in that line.")
    return None, 0.0


def _seed2(f: _Lines) -> int | str | None:
    text = f.key("WaveSeed(2)", "str")
    if text is None:
        return None
    if text.lstrip("+-").isdigit():
        return int(text)
    if text.upper() != "RANLUX":
        f.problem(f.line_of["WaveSeed(2)"], "WaveSeed(2)", f"must be an integer or RANLUX; got {text!r}.")
    return text.upper()


def _waves(f: _Lines, out: dict) -> None:
    f.rule("WAVES")
    out["wave_model"], out["wave_phase"] = _wave_model(f)
    nonneg = (lambda v: v >= 0, "must not be negative")
    out["stretching_model"] = f.key("WaveStMod", "int", check=(lambda v: v in (0, 1, 2, 3), "must be 0, 1, 2 or 3"))
    out["wave_current_model"] = f.key("WvCrntMod", "int", check=(lambda v: v in (0, 1, 2), "must be 0, 1 or 2"))
    out["wave_time_max"] = f.key("WaveTMax", check=nonneg)
    out["wave_time_step"] = f.key("WaveDT", check=nonneg)
    out["wave_height"] = f.key("WaveHs", check=nonneg)
    out["peak_period"] = f.key("WaveTp", check=nonneg)
    shape = f.key("WavePkShp", "float|default")
    if shape == "default" and None not in (out["wave_model"], out["wave_height"], out["peak_period"]):
        shape = default_peak_shape(out["wave_model"], out["wave_height"], out["peak_period"])
    elif out["wave_model"] == 2 and shape is not None and not 1.0 <= shape <= 7.0:
        f.problem(f.line_of["WavePkShp"], "WavePkShp", f"must be in [1, 7] for a JONSWAP spectrum (SeaState's "
                  f"check); got {shape}.")
    out["peak_shape"] = shape
    out["low_cutoff"] = f.key("WvLowCOff", check=nonneg)
    out["high_cutoff"] = f.key("WvHiCOff", check=nonneg)
    out["wave_direction"] = (f.key("WaveDir") or 0.0) * _DEG
    out["direction_model"] = f.key("WaveDirMod", "int", check=(lambda v: v in (0, 1), "must be 0 or 1"))
    out["direction_spread"] = f.key("WaveDirSpread")
    out["n_directions"] = f.key("WaveNDir", "int")
    out["direction_range"] = (f.key("WaveDirRange") or 0.0) * _DEG
    out["seeds"] = (f.key("WaveSeed(1)", "int"), _seed2(f))
    out["normal_amplitudes"] = f.key("WaveNDAmp", "bool")
    out["kinematics_file"] = f.key("WvKinFile", "str")


def _current(f: _Lines, out: dict) -> None:
    f.rule("CURRENT")
    out["current_model"] = f.key("CurrMod", "int", check=(lambda v: v in (0, 1, 2), "must be 0, 1 or 2"))
    out["current_subsurface_speed"] = f.key("CurrSSV0")
    direction = f.key("CurrSSDir", "float|default")
    out["current_subsurface_direction"] = direction if direction in (None, "default") else direction * _DEG
    out["current_near_surface_depth"] = f.key("CurrNSRef")
    out["current_near_surface_speed"] = f.key("CurrNSV0")
    out["current_near_surface_direction"] = (f.key("CurrNSDir") or 0.0) * _DEG
    out["current_uniform_speed"] = f.key("CurrDIV")
    out["current_uniform_direction"] = (f.key("CurrDIDir") or 0.0) * _DEG


def _points(f: _Lines, count_key: str, axes: str) -> tuple:
    count = f.key(count_key, "int", check=(lambda v: 0 <= v <= 9, "must be 0 to 9")) or 0
    stem = "WaveElev" if count_key == "NWaveElev" else "WaveKin"
    columns = [f.key(f"{stem}{a}i", "floats", n=max(count, 1)) or (0.0,) * max(count, 1) for a in axes]
    return tuple(tuple(c[k] for c in columns) for k in range(count))


def read_seastate(path) -> SeaStateInput:
    """Read a SeaState input file (see the module docstring).

    Raises
    ------
    OpenFASTFormatError
        Missing file, a line out of order (expected and found key), malformed numbers or
        switches (``WaveMod`` not 0-6 or ``1P#``, ``WavePkShp`` outside [1, 7] for JONSWAP);
        names the file, line and key.

    Examples
    --------
    >>> from mbsym.wind.deck.seastate import read_seastate
    >>> sea = read_seastate("fl_decay_a_SeaState.dat")  # doctest: +SKIP
    >>> sea.wave_model_name, sea.water_density  # doctest: +SKIP
    ('still water', 'default')
    """
    f = _Lines(Path(path), "SeaState input file")
    f.key("Echo", "bool")
    f.rule("ENVIRONMENTAL CONDITIONS")
    positive = (lambda v: v > 0, "must be greater than 0")
    out = {"water_density": f.key("WtrDens", "float|default", check=positive),
           "water_depth": f.key("WtrDpth", "float|default", check=positive),
           "msl_to_swl": f.key("MSL2SWL", "float|default")}
    f.rule("SPATIAL DISCRETIZATION")
    out.update(x_half_width=f.key("X_HalfWidth", check=positive), y_half_width=f.key("Y_HalfWidth", check=positive),
               domain_depth=f.key("Z_Depth", "float|default", check=positive),
               nx=f.key("NX", "int"), ny=f.key("NY", "int"), nz=f.key("NZ", "int"))
    _waves(f, out)
    f.rule("2ND-ORDER WAVES")
    out["difference_qtf"] = f.key("WvDiffQTF", "bool")
    out["sum_qtf"] = f.key("WvSumQTF", "bool")
    out["qtf_cutoffs"] = tuple(f.key(k) for k in ("WvLowCOffD", "WvHiCOffD", "WvLowCOffS", "WvHiCOffS"))
    f.rule("CONSTRAINED WAVES")
    out["constrained_wave_model"] = f.key("ConstWaveMod", "int", check=(lambda v: v in (0, 1, 2), "must be 0, 1 or 2"))
    out["crest"] = tuple(f.key(k) for k in ("CrestHmax", "CrestTime", "CrestXi", "CrestYi"))
    _current(f, out)
    f.rule("MacCamy-Fuchs")
    out["maccamy_fuchs_radius"] = f.key("MCFD")
    f.rule("OUTPUT")
    for key, kind in (("SeaStSum", "bool"), ("OutSwtch", "int"), ("OutFmt", "str"), ("OutSFmt", "str")):
        f.key(key, kind)
    out["elevation_points"] = _points(f, "NWaveElev", "xy")
    out["kinematics_points"] = _points(f, "NWaveKin", "xyz")
    f.rule("OUTPUT CHANNELS")
    out["outputs"] = tuple(f.outlist())
    f.raise_problems()
    return SeaStateInput(**out, path=str(f.path), lines=dict(f.line_of))
