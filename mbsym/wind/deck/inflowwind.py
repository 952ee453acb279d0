"""Read an OpenFAST InflowWind input file (``*_IfW.dat``): steady, uniform-file and full-field wind.

Supported: ``WindType = 1`` (steady: ``HWindSpeed``, ``RefHt``, ``PLexp``), ``WindType = 2``
(uniform wind file ``Filename_Uni``, ``RefHt_Uni``, ``RefLength``), ``WindType = 3`` (TurbSim
binary full field ``FileName_BTS``), ``WindType = 4`` (TurbSim's Bladed-style box ``FileNameRoot.wnd`` with
its ``.sum`` and, with ``TowerFile``, ``.twr``), ``WindType = 5`` (HAWC box: ``FileName_u/v/w``, ``nx`` …
``XOffset``; :mod:`mbsym.wind.inflow.hawc`) and ``WindType = 7`` (native Bladed: ``FileNameRoot`` is its
summary file, whose propagation direction and upflow replace the InflowWind file's, as InflowWind does;
:mod:`mbsym.wind.inflow.bladed`), with ``PropagationDir`` and ``VFlowAng``; user-defined wind (6) and the
continuous-wave and pulsed lidars (``SensorType`` 2, 3) raise with the file, line and key; the single-point
lidar (``SensorType = 1``) is read into :attr:`InflowWindSettings.lidar` (:class:`~mbsym.wind.inflow.PointLidar`).
The files named by ``Filename_Uni``, ``FileName_BTS``, ``FileNameRoot`` and ``FileName_u/v/w`` are resolved
relative to the InflowWind file, as InflowWind does (absolute paths are used as they are).
``VelInterpCubic = True`` makes every wind cubic in time as InflowWind v5.0.0 does (:mod:`mbsym.wind.inflow.cubic`;
full fields with a :class:`~mbsym.exceptions.ModelWarning` on OpenFAST's vertical component); a main file with
``Linearize = True`` turns it off with a warning, as InflowWind does (:func:`deck_inflowwind`). Keys not used here
(output points ``WindV*List``, the sections of the other wind types, the unused lidar keys, ``OutList``) are kept,
as text, in ``extra``.

:meth:`InflowWindSettings.wind` gives the hub-height wind signal (types 1 and 2, as before);
:meth:`InflowWindSettings.field` the spatial description (:class:`~mbsym.wind.inflow.UniformFieldWind`
for types 1 and 2, :class:`~mbsym.wind.inflow.FullFieldWind` for the full fields 3, 4, 5 and 7).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError, WindInputError
from ._format import _Deck, _Key, _read_keys, _resolve

__all__ = ["InflowWindSettings", "read_inflowwind", "deck_inflowwind", "INFLOWWIND_KEYS"]

_DEG = math.pi / 180.0
_k = _Key
_FULL_FIELD = (3, 4, 5, 7)
_WIND_TYPES = {1: "steady", 2: "uniform wind file", 3: "binary TurbSim full-field", 4: "binary Bladed full-field",
               5: "HAWC", 6: "user defined", 7: "native Bladed full-field"}
_KEYS = (
    _k("WindType", "wind_type", "int",
       check=(lambda v: v in (1, 2, 3, 4, 5, 7), "must be 1 (steady), 2 (uniform wind file), 3 (binary TurbSim "
              "full field), 4 (Bladed-style full field from TurbSim), 5 (HAWC) or 7 (native Bladed): mbsym does "
              "not model user-defined wind (6)")),
    _k("PropagationDir", "propagation_direction", scale=_DEG, default=0.0),
    _k("VFlowAng", "upflow_angle", scale=_DEG, default=0.0),
    _k("VelInterpCubic", "cubic_interpolation", "bool", default=False),
    _k("HWindSpeed", "steady_speed", check=(lambda v: v >= 0, "must not be negative")),
    _k("RefHt", "steady_reference_height", check=(lambda v: v > 0, "must be greater than 0")),
    _k("PLexp", "steady_power_law_exponent"),
    _k("Filename_Uni", "uniform_file_name", "str"),
    _k("RefHt_Uni", "uniform_reference_height", check=(lambda v: v > 0, "must be greater than 0")),
    _k("RefLength", "uniform_reference_length", default=None),
    _k("FileName_BTS", "full_field_file_name", "str", default=""),
    _k("SensorType", "lidar_sensor_type", "int",
       check=(lambda v: v in (0, 1), "must be 0 (no lidar) or 1 (single-point beams): mbsym does not model "
              "InflowWind's continuous-wave (2) or pulsed (3) lidars"), default=0),
)
#: The single-point lidar's keys (read when ``SensorType = 1``; ``NumPulseGate``, ``PulseSpacing``,
#: ``URefLid`` and ``LidRadialVel`` are not used by that sensor in InflowWind, so not read).
_LIDAR_KEYS = (
    _k("NumBeam", "n_beams", "int", check=(lambda v: 1 <= v <= 5, "must be 1 to 5 beams for SensorType = 1")),
    _k("FocalDistanceX", "x", "floats"),
    _k("FocalDistanceY", "y", "floats"),
    _k("FocalDistanceZ", "z", "floats"),
    _k("RotorApexOffsetPos", "apex", "floats"),
    _k("MeasurementInterval", "interval", check=(lambda v: v > 0, "must be a time > 0 [s]")),
    _k("ConsiderHubMotion", "hub_motion", "int", check=(lambda v: v in (0, 1), "must be 0 or 1")),
)
#: The Bladed keys (``WindType`` 4 and 7).
_BLADED_KEYS = (
    _k("FileNameRoot", "root", "str"),
    _k("TowerFile", "tower", "bool", default=False),
)
_POSITIVE = (lambda v: v > 0, "must be greater than 0")
_NOT_NEGATIVE = (lambda v: v >= 0, "must not be negative")
#: The HAWC keys (``WindType = 5``).
_HAWC_KEYS = (
    _k("FileName_u", "file_u", "str"), _k("FileName_v", "file_v", "str"), _k("FileName_w", "file_w", "str"),
    _k("nx", "nx", "int", check=(lambda v: v >= 2, "must be at least 2 grid points")),
    _k("ny", "ny", "int", check=(lambda v: v >= 2, "must be at least 2 grid points")),
    _k("nz", "nz", "int", check=(lambda v: v >= 2, "must be at least 2 grid points")),
    _k("dx", "dx", check=_POSITIVE), _k("dy", "dy", check=_POSITIVE), _k("dz", "dz", check=_POSITIVE),
    _k("RefHt_Hawc", "reference_height", check=_POSITIVE),
    _k("ScaleMethod", "scale_method", "int", check=(lambda v: v in (0, 1, 2), "must be 0 (none), 1 (direct "
                                                     "scaling factors) or 2 (target standard deviations)")),
    _k("SFx", "sfx", check=_NOT_NEGATIVE), _k("SFy", "sfy", check=_NOT_NEGATIVE),
    _k("SFz", "sfz", check=_NOT_NEGATIVE),
    _k("SigmaFx", "sigx", check=_NOT_NEGATIVE), _k("SigmaFy", "sigy", check=_NOT_NEGATIVE),
    _k("SigmaFz", "sigz", check=_NOT_NEGATIVE),
    _k("URef", "mean_speed", check=(lambda v: v > 0, "must be greater than 0 m/s (it carries the box past "
                                                     "the rotor)")),
    _k("WindProfile", "profile", "int", check=(lambda v: v in (0, 1, 2), "must be 0 (constant), 1 "
                                                "(logarithmic) or 2 (power law)")),
    _k("PLExp_Hawc", "exponent"),
    _k("Z0", "roughness"),
    _k("XOffset", "x_offset", default=0.0),
)
#: InflowWind key → :class:`InflowWindSettings` attribute (angles deg → rad).
INFLOWWIND_KEYS = {k.key: k.attr for k in _KEYS}


@dataclass(frozen=True)
class InflowWindSettings:
    """The wind an InflowWind file describes (SI units, angles in rad).

    Attributes
    ----------
    wind_type : int
        1 (steady), 2 (uniform wind file), 3 (TurbSim), 4 (TurbSim's Bladed-style box), 5 (HAWC) or 7
        (native Bladed).
    propagation_direction, upflow_angle : float
        ``PropagationDir`` and ``VFlowAng`` [rad].
    cubic_interpolation : bool
        ``VelInterpCubic``: the wind is cubic in time between the file's samples instead of linear (all wind
        types; steady wind has one sample).
    steady_speed, steady_reference_height, steady_power_law_exponent : float
        ``HWindSpeed`` [m/s], ``RefHt`` [m], ``PLexp`` [-] (used by type 1).
    uniform_file : Path or None
        ``Filename_Uni`` resolved against the InflowWind file's directory (type 2).
    uniform_reference_height, uniform_reference_length : float
        ``RefHt_Uni``, ``RefLength`` [m].
    full_field_file : Path or None
        ``FileName_BTS`` resolved against the InflowWind file's directory (type 3); None if absent.
    lidar_sensor_type : int
        ``SensorType`` (0 none, 1 single-point beams; 2 and 3 are refused).
    lidar : PointLidar or None
        The single-point lidar of ``SensorType = 1`` (:class:`~mbsym.wind.inflow.PointLidar`).
    hawc : HawcBox or None
        The HAWC box of type 5 (:class:`~mbsym.wind.inflow.hawc.HawcBox`, files resolved).
    bladed_file_name : str
        ``FileNameRoot`` as written (types 4 and 7).
    bladed_file : Path or None
        Type 4: ``FileNameRoot`` + ``.wnd``; type 7: ``FileNameRoot`` (the native Bladed summary), resolved
        against the InflowWind file's directory; None if not found.
    bladed_tower_file : bool
        ``TowerFile`` (type 4: read ``<root>.twr``).
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
    full_field_file_name: str
    full_field_file: Path | None
    lidar_sensor_type: int
    path: str
    lidar: object = None
    hawc: object = None
    bladed_file_name: str = ""
    bladed_file: Path | None = None
    bladed_tower_file: bool = False
    extra: dict = field(default_factory=dict, compare=False)
    lines: dict = field(default_factory=dict, compare=False)

    def wind(self, *, allow_unmodelled: bool = False):
        """The hub-height wind as a :class:`~mbsym.wind.inflow.WindSignal`.

        For a full field (type 3) only with ``allow_unmodelled=True``: the longitudinal wind at the
        reference point ``(0, 0, RefHt)`` (OpenFAST's ``Wind1VelX`` there) at the file's time step, over
        the times the file covers there; a rotor sweeps the field, so consider
        :func:`~mbsym.wind.inflow.rotor_effective_wind` of :meth:`field` instead.

        With ``VelInterpCubic = True`` the signal is cubic in time as InflowWind's
        (:class:`~mbsym.wind.inflow.cubic_signal.CubicUniformHubWind`, full fields
        :class:`~mbsym.wind.inflow.cubic_signal.HermiteTableWind`).

        Raises
        ------
        WindInputError
            A non-zero propagation direction, upflow or steady power-law exponent
            (or, for type 2, non-zero direction/shear columns in the file; for type 3, always), unless
            ``allow_unmodelled``: a hub-height signal cannot carry them.
        OpenFASTFormatError
            The uniform wind file is missing or malformed.
        """
        from ..inflow import SteadyWind, read_uniform_wind  # the inflow package reads files; no cycle at import

        bad = {name: getattr(self, name) for name in ("propagation_direction", "upflow_angle")
               if getattr(self, name) != 0.0}
        if self.wind_type in _FULL_FIELD:
            bad[f"full field (WindType = {self.wind_type}; a hub-height signal drops its spatial variation)"] = \
                float(self.wind_type)
        if self.wind_type == 1 and self.steady_power_law_exponent != 0.0:
            bad["steady_power_law_exponent (PLexp)"] = self.steady_power_law_exponent
        if bad and not allow_unmodelled:
            where = ", ".join(f"{k} = {v:g}" for k, v in bad.items())
            raise WindInputError(f"{self.path}: {where}. The hub-height wind signal models only the speed along "
                                 "the rotor axis; set these to zero or pass allow_unmodelled=True.")
        if self.wind_type == 1:
            return SteadyWind(self.steady_speed)
        if self.wind_type in _FULL_FIELD:
            return self._hub_series(allow_unmodelled)
        if self.uniform_file is None:
            raise OpenFASTFormatError(f"{self.path}, line {self.lines.get('Filename_Uni', '?')}, key "
                                      f"'Filename_Uni': uniform wind file not found: tried "
                                      f"'{self.uniform_file_name}'. Fix the file name.")
        table = read_uniform_wind(self.uniform_file)
        if not self.cubic_interpolation:
            return table.signal(allow_unmodelled=allow_unmodelled)
        from ..inflow import UniformFieldWind                  # the columns' cubic (the length acts off the hub)

        length = self.uniform_reference_length if (self.uniform_reference_length or 0.0) > 0.0 else 1.0
        return UniformFieldWind(table, self.uniform_reference_height, length, source=str(self.uniform_file),
                                cubic=True).hub_signal(allow_unmodelled=allow_unmodelled)


    def _hub_series(self, allow_unmodelled: bool):
        from ..inflow import TabulatedWind

        field = self.field()
        t0, t1 = field.time_range
        times = t0 + field.dt * np.arange(int(round((t1 - t0) / field.dt)) + 1)
        # read a billionth of a step inside the ends: t0 = -x0/URef lands a rounding error outside a non-periodic
        # field's data (τ = t + x0/URef < 0), which InflowWind would refuse there; the values move by ~1e-9 of a step
        inside = np.clip(times, t0 + 1e-9 * field.dt, t1 - 1e-9 * field.dt)
        u = field.velocity(inside, np.array([[0.0, 0.0, field.reference_height]]))[:, 0, 0]
        source = f"{field.source or self.full_field_file} at (0, 0, {field.reference_height:g}) m"
        if field.cubic:                               # the slices joined by InflowWind's zero-slope cubic
            from ..inflow.cubic_signal import HermiteTableWind

            return HermiteTableWind(times, u, np.zeros_like(u), source=source)
        return TabulatedWind(times, u, source=source)

    def field(self, *, allow_cubic: bool = False):
        """The wind over space: a :class:`~mbsym.wind.inflow.UniformFieldWind` (types 1, 2) or a
        :class:`~mbsym.wind.inflow.FullFieldWind` (types 3, 4, 5, 7), with ``PropagationDir`` and ``VFlowAng``,
        cubic in time with ``VelInterpCubic = True`` (``allow_cubic`` is kept for compatibility and unused).

        Warns
        -----
        ModelWarning
            ``VelInterpCubic = True`` with a full field: OpenFAST v5.0.0 computes the vertical component there
            with uninitialised slopes (:mod:`mbsym.wind.inflow.cubic`); mbsym uses zero slopes, as OpenFAST does
            for the other components.

        Raises
        ------
        OpenFASTFormatError
            A missing or malformed wind file, ``RefLength`` missing or not positive for type 2 (file, line, key).
        """
        field = self._field()
        if self.cubic_interpolation and self.wind_type in _FULL_FIELD:
            import warnings

            from ...exceptions import ModelWarning

            warnings.warn(f"{self._where('VelInterpCubic')}: True with a full field: mbsym joins the slices with "
                          "InflowWind's cubic at zero slopes, which is what OpenFAST v5.0.0 computes for u and v; "
                          "its w inside the grid uses uninitialised slopes (OpenFAST pull request #3428, fixed in "
                          "5.0.1) and may differ by tenths of m/s from mbsym's.", ModelWarning, stacklevel=2)
            return field.with_cubic(True)
        return field

    def _field(self):
        from ..inflow import UniformFieldWind, read_turbsim_bts, read_uniform_wind

        angles = {"propagation_direction": self.propagation_direction, "upflow_angle": self.upflow_angle}
        if self.wind_type == 1:
            return UniformFieldWind.steady(self.steady_speed, reference_height=self.steady_reference_height,
                                           power_law_exponent=self.steady_power_law_exponent, **angles)
        if self.wind_type == 2:
            if self.uniform_file is None:
                raise OpenFASTFormatError(f"{self._where('Filename_Uni')}: uniform wind file not found: tried "
                                          f"'{self.uniform_file_name}'. Fix the file name.")
            length = self.uniform_reference_length
            if length is None or not length > 0.0:
                raise OpenFASTFormatError(f"{self._where('RefLength')}: must be a positive reference length [m] "
                                          f"for a uniform wind file; got {length}. Fix the value.")
            return UniformFieldWind(read_uniform_wind(self.uniform_file), self.uniform_reference_height, length,
                                    source=str(self.uniform_file), cubic=self.cubic_interpolation, **angles)
        if self.wind_type in (4, 5, 7):
            return self._other_field(angles)
        if self.full_field_file is None:
            raise OpenFASTFormatError(f"{self._where('FileName_BTS')}: TurbSim full-field file not found: tried "
                                      f"'{self.full_field_file_name}' (relative paths start at the directory of "
                                      f"{Path(self.path).name}). Fix the file name.")
        return read_turbsim_bts(self.full_field_file, **angles)

    def _other_field(self, angles: dict):
        """HAWC (5), TurbSim's Bladed-style (4) and native Bladed (7) boxes."""
        if self.wind_type == 5:
            from ..inflow.hawc import read_hawc

            return read_hawc(self.hawc, **angles)
        from ..inflow.bladed import read_bladed_native, read_bladed_wnd

        if self.bladed_file is None:
            tried = self.bladed_file_name + (".wnd" if self.wind_type == 4 else "")
            what = "Bladed-style wind file" if self.wind_type == 4 else "native Bladed summary file"
            raise OpenFASTFormatError(f"{self._where('FileNameRoot')}: {what} not found: tried '{tried}' (relative "
                                      f"paths start at the directory of {Path(self.path).name}). Fix the name.")
        if self.wind_type == 4:
            return read_bladed_wnd(self.bladed_file, tower_file=self.bladed_tower_file, **angles)
        if self.propagation_direction != 0.0 or self.upflow_angle != 0.0:
            import warnings

            warnings.warn(f"{self._where('PropagationDir')}: WindType = 7 takes the propagation direction and upflow "
                          f"from the native Bladed summary {self.bladed_file.name}; the InflowWind file's "
                          "PropagationDir and VFlowAng are not used (as in InflowWind). Set them to 0 to silence "
                          "this.", stacklevel=3)
        return read_bladed_native(self.bladed_file)       # its own PropagationDir/VFlowAng, as InflowWind

    def _where(self, key: str) -> str:
        return f"{self.path}, line {self.lines.get(key, '?')}, key '{key}'"


def _resolve_wind_file(ifw: Path, name: str) -> Path | None:
    """InflowWind's rule: a relative path starts at the InflowWind file's directory."""
    if not name:
        return None
    for candidate in (Path(name), Path(name.replace("\\", "/"))):
        full = candidate if candidate.is_absolute() else ifw.parent / candidate
        if full.is_file():
            return full
    return None


def read_inflowwind(path) -> InflowWindSettings:
    """Read an InflowWind input file (see the module docstring).

    Raises
    ------
    OpenFASTFormatError
        Missing file or key, malformed value, unsupported ``WindType``; names the
        file, line and key.  A missing wind file is reported when the
        wind is requested (:meth:`InflowWindSettings.wind`, :meth:`~InflowWindSettings.field`), so a
        deck can be read without its wind file.

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
    if values["wind_type"] == 3 and not values["full_field_file_name"]:
        deck.problem(deck.line_of("WindType"), "FileName_BTS", "missing: WindType = 3 needs the TurbSim file "
                     "name. Add a line '\"<file>.bts\"  FileName_BTS'.")
        deck.raise_problems()
    uniform = _resolve_wind_file(p, values["uniform_file_name"])
    full = _resolve_wind_file(p, values["full_field_file_name"])
    lidar = _read_lidar(deck) if values["lidar_sensor_type"] == 1 else None
    kind = values["wind_type"]
    others = _read_other_field(deck, p, kind)
    keys = _KEYS + (_LIDAR_KEYS if lidar is not None else ()) + (_HAWC_KEYS if kind == 5 else ()) \
        + (_BLADED_KEYS if kind in (4, 7) else ())
    lines = {k.key: deck.line_of(k.key) for k in keys if k.key.lower() in deck.entries}
    return InflowWindSettings(**values, uniform_file=uniform, full_field_file=full, path=str(p), extra=deck.extra(),
                              lines=lines, lidar=lidar, **others)


def _read_other_field(deck: _Deck, ifw: Path, kind: int) -> dict:
    """The HAWC (5) or Bladed (4, 7) section's settings (file, line and key in every error)."""
    if kind in (4, 7):
        v = _read_keys(deck, _BLADED_KEYS)
        deck.raise_problems()
        name = v["root"] + (".wnd" if kind == 4 else "")
        return {"bladed_file_name": v["root"], "bladed_file": _resolve_wind_file(ifw, name),
                "bladed_tower_file": bool(v["tower"]) and kind == 4}
    if kind != 5:
        return {}
    from ..inflow.hawc import HawcBox

    v = _read_keys(deck, _HAWC_KEYS)
    deck.raise_problems()
    files = []
    for c in "uvw":
        name = v[f"file_{c}"]
        found = _resolve_wind_file(ifw, name)
        files.append(found if found is not None else (Path(name) if Path(name).is_absolute() else ifw.parent / name))
    box = HawcBox(tuple(files), v["nx"], v["ny"], v["nz"], v["dx"], v["dy"], v["dz"], v["reference_height"],
                  scale_method=v["scale_method"], scale_factors=(v["sfx"], v["sfy"], v["sfz"]),
                  target_sigmas=(v["sigx"], v["sigy"], v["sigz"]), mean_speed=v["mean_speed"],
                  profile=v["profile"], exponent=v["exponent"], roughness=v["roughness"], x_offset=v["x_offset"],
                  source=str(ifw))
    if v["profile"] == 1 and not v["roughness"] > 0.0:
        deck.problem(deck.line_of("Z0"), "Z0", f"must be greater than 0 m for WindProfile = 1 (logarithmic); got "
                     f"{v['roughness']:g}. Fix the value.")
        deck.raise_problems()
    return {"hawc": box}


def _read_lidar(deck: _Deck):
    """The single-point lidar of ``SensorType = 1`` (file, line and key in every error)."""
    from ..inflow import PointLidar

    v = _read_keys(deck, _LIDAR_KEYS)
    deck.raise_problems()
    n = v["n_beams"]
    for key, attr, size in (("FocalDistanceX", "x", n), ("FocalDistanceY", "y", n), ("FocalDistanceZ", "z", n),
                            ("RotorApexOffsetPos", "apex", 3)):
        if len(v[attr]) < size:
            deck.problem(deck.line_of(key), key, f"needs {size} values (NumBeam = {n}); got {len(v[attr])}. "
                         "Give one value per beam.")
    deck.raise_problems()
    focal = np.column_stack([np.asarray(v[a][:n], dtype=float) for a in ("x", "y", "z")])
    return PointLidar(focal, np.asarray(v["apex"][:3], dtype=float), v["interval"], bool(v["hub_motion"]))


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
    linearize = deck.value(_k("Linearize", "", "bool", default=False))
    deck.raise_problems()
    if mode != 1:
        return None
    settings = read_inflowwind(_resolve(deck, "InflowFile", "InflowWind input file"))
    if linearize and settings.cubic_interpolation:        # InflowWind_Init does the same (InflowWind.f90)
        import dataclasses
        import warnings

        from ...exceptions import ModelWarning

        warnings.warn(f"{settings._where('VelInterpCubic')}: True, but {p.name} has Linearize = True: InflowWind "
                      "disables cubic interpolation of the wind for linearization, and so does mbsym (linear in "
                      "time).", ModelWarning, stacklevel=2)
        settings = dataclasses.replace(settings, cubic_interpolation=False)
    return settings
