"""Read an OpenFAST InflowWind input file (``*_IfW.dat``): steady and uniform-file wind.

Only the wind types a hub-height wind signal can represent are supported:
``WindType = 1`` (steady: ``HWindSpeed``, ``RefHt``, ``PLexp``) and ``WindType = 2``
(uniform wind file ``Filename_Uni``, ``RefHt_Uni``, ``RefLength``); full-field
types (TurbSim, Bladed, HAWC, ...) raise with the line of ``WindType``.  The file
named by ``Filename_Uni`` is resolved relative to the InflowWind file, as
InflowWind does.  Keys not used here are kept, as text, in ``extra``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from ...exceptions import OpenFASTFormatError, WindInputError
from ._format import _Deck, _Key, _read_keys, _resolve

__all__ = ["InflowWindSettings", "read_inflowwind", "deck_inflowwind", "INFLOWWIND_KEYS"]

_DEG = math.pi / 180.0
_k = _Key
_WIND_TYPES = {1: "steady", 2: "uniform wind file", 3: "binary TurbSim full-field", 4: "binary Bladed full-field",
               5: "HAWC", 6: "user defined", 7: "native Bladed full-field"}
_KEYS = (
    _k("WindType", "wind_type", "int",
       check=(lambda v: v in (1, 2), "must be 1 (steady) or 2 (uniform wind file): mbsym models a hub-height "
              "wind speed and does not read full-field wind")),
    _k("PropagationDir", "propagation_direction", scale=_DEG, default=0.0),
    _k("VFlowAng", "upflow_angle", scale=_DEG, default=0.0),
    _k("VelInterpCubic", "cubic_interpolation", "bool", default=False),
    _k("HWindSpeed", "steady_speed", check=(lambda v: v >= 0, "must not be negative")),
    _k("RefHt", "steady_reference_height", check=(lambda v: v > 0, "must be greater than 0")),
    _k("PLexp", "steady_power_law_exponent"),
    _k("Filename_Uni", "uniform_file_name", "str"),
    _k("RefHt_Uni", "uniform_reference_height", check=(lambda v: v > 0, "must be greater than 0")),
    _k("RefLength", "uniform_reference_length", default=None),
)
#: InflowWind key → :class:`InflowWindSettings` attribute (angles deg → rad).
INFLOWWIND_KEYS = {k.key: k.attr for k in _KEYS}


@dataclass(frozen=True)
class InflowWindSettings:
    """The wind an InflowWind file describes (SI units, angles in rad).

    Attributes
    ----------
    wind_type : int
        1 (steady) or 2 (uniform wind file).
    propagation_direction, upflow_angle : float
        ``PropagationDir`` and ``VFlowAng`` [rad].
    cubic_interpolation : bool
        ``VelInterpCubic`` (uniform wind in time: cubic instead of linear).
    steady_speed, steady_reference_height, steady_power_law_exponent : float
        ``HWindSpeed`` [m/s], ``RefHt`` [m], ``PLexp`` [-] (used by type 1).
    uniform_file : Path or None
        ``Filename_Uni`` resolved against the InflowWind file's directory (type 2).
    uniform_reference_height, uniform_reference_length : float
        ``RefHt_Uni``, ``RefLength`` [m].
    path : str
        The InflowWind file.
    extra : dict
        Raw text of the keys not used here.
    """

    wind_type: int
    propagation_direction: float
    upflow_angle: float
    cubic_interpolation: bool
    steady_speed: float
    steady_reference_height: float
    steady_power_law_exponent: float
    uniform_file_name: str
    uniform_file: Path | None
    uniform_reference_height: float
    uniform_reference_length: float | None
    path: str
    extra: dict = field(default_factory=dict, compare=False)
    lines: dict = field(default_factory=dict, compare=False)

    def wind(self, *, allow_unmodelled: bool = False):
        """The hub-height wind as a :class:`~mbsym.wind.inflow.WindSignal`.

        Raises
        ------
        WindInputError
            A non-zero propagation direction, upflow or steady power-law exponent, cubic
            interpolation in time
            (or, for type 2, non-zero direction/shear columns in the file), unless
            ``allow_unmodelled``: a hub-height signal cannot carry them.
        OpenFASTFormatError
            The uniform wind file is missing or malformed.
        """
        from ..inflow import SteadyWind, read_uniform_wind  # the inflow package reads files; no cycle at import

        bad = {name: getattr(self, name) for name in ("propagation_direction", "upflow_angle")
               if getattr(self, name) != 0.0}
        if self.wind_type == 2 and self.cubic_interpolation:
            bad["cubic_interpolation (VelInterpCubic; mbsym interpolates linearly)"] = 1.0
        if self.wind_type == 1 and self.steady_power_law_exponent != 0.0:
            bad["steady_power_law_exponent (PLexp)"] = self.steady_power_law_exponent
        if bad and not allow_unmodelled:
            where = ", ".join(f"{k} = {v:g}" for k, v in bad.items())
            raise WindInputError(f"{self.path}: {where}. The hub-height wind signal models only the speed along "
                                 "the rotor axis; set these to zero or pass allow_unmodelled=True.")
        if self.wind_type == 1:
            return SteadyWind(self.steady_speed)
        if self.uniform_file is None:
            raise OpenFASTFormatError(f"{self.path}, line {self.lines.get('Filename_Uni', '?')}, key "
                                      f"'Filename_Uni': uniform wind file not found: tried "
                                      f"'{self.uniform_file_name}'. Fix the file name.")
        return read_uniform_wind(self.uniform_file).signal(allow_unmodelled=allow_unmodelled)


def read_inflowwind(path) -> InflowWindSettings:
    """Read an InflowWind input file (see the module docstring).

    Raises
    ------
    OpenFASTFormatError
        Missing file or key, malformed value, unsupported ``WindType``; names the
        file, line and key.  A missing uniform wind file is reported when the
        wind is requested (:meth:`InflowWindSettings.wind`), so a deck can be read
        without its wind file.

    Examples
    --------
    >>> from mbsym.wind.deck.inflowwind import read_inflowwind
    >>> ifw = read_inflowwind("step_10_14_IfW.dat")  # doctest: +SKIP
    >>> ifw.wind_type, ifw.wind()(35.0)  # doctest: +SKIP
    (2, 14.0)
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"InflowWind input file not found: tried '{p.absolute()}'. Check the path.")
    deck = _Deck(p)
    values = _read_keys(deck, _KEYS)
    deck.raise_problems()
    name = values["uniform_file_name"]
    resolved = None
    for candidate in (Path(name), Path(name.replace("\\", "/"))):
        full = candidate if candidate.is_absolute() else p.parent / candidate
        if full.is_file():
            resolved = full
            break
    lines = {k.key: deck.line_of(k.key) for k in _KEYS if k.key.lower() in deck.entries}
    return InflowWindSettings(**values, uniform_file=resolved, path=str(p), extra=deck.extra(), lines=lines)


def deck_inflowwind(fst) -> InflowWindSettings | None:
    """The InflowWind settings a main ``.fst`` file names (``CompInflow = 1``, ``InflowFile``), or None.

    Raises
    ------
    OpenFASTFormatError
        Missing or malformed ``.fst`` keys, a missing InflowWind file (file, line, key).
    """
    p = Path(fst)
    if not p.is_file():
        raise OpenFASTFormatError(f"OpenFAST main input file not found: tried '{p.absolute()}'. Check the path.")
    deck = _Deck(p)
    mode = deck.value(_k("CompInflow", "", "int", check=(lambda v: v in (0, 1, 2), "must be 0, 1 or 2")))
    deck.value(_k("InflowFile", "", "str", default=""))
    deck.raise_problems()
    if mode != 1:
        return None
    return read_inflowwind(_resolve(deck, "InflowFile", "InflowWind input file"))
