"""Operating points over wind speed (the power curve): trims of a turbine under its controller's settings.

* :func:`operating_points` trims a model at a list of wind speeds (continuation from point to
  point, :class:`~.trim.Trimmer`) and returns :class:`OperatingPoints`: every channel per wind
  speed, ``success``/``message`` per point, timing, the JSON object of ``mbsym
  operating-points --json``, linear models (:mod:`.trim_linear`) and plots (:mod:`.trim_plot`).
* :func:`turbine_and_control` resolves what the command-line tool trims: a deck (ElastoDyn,
  AeroDyn 15 and the ROSCO ``DISCON.IN`` its ServoDyn names) or, without a deck, the built-in
  NREL 5 MW with ROSCO 2.10.6's settings (package data).
* :func:`parse_wind_speeds` reads ``START:STOP:STEP`` (STOP included when on the grid) or a
  comma list.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator, Mapping, Sequence

import numpy as np

from ...exceptions import ControllerError, ModelWarning, WindInputError
from ..operation.steady_control import SteadyControl
from ..operation.trim import TRIM_TOLERANCE, Trimmer, TrimPoint

__all__ = ["OperatingPoints", "operating_points", "turbine_and_control", "parse_wind_speeds", "JSON_CHANNELS",
           "PLATFORM_CHANNELS", "MAX_WIND_SPEEDS"]

#: Channels of the ``--json`` object, with their OpenFAST units.
JSON_CHANNELS = {"RotSpeed": "rpm", "BldPitch1": "deg", "GenPwr": "kW", "RtAeroFxh": "N", "TTDspFA": "m"}
#: A floating turbine's mean offsets and fairlead tensions (added to the table, the JSON and the plot when present).
PLATFORM_CHANNELS = {"PtfmSurge": "m", "PtfmHeave": "m", "PtfmPitch": "deg"}
#: Largest number of wind speeds one call accepts.
MAX_WIND_SPEEDS = 10000


@dataclass(frozen=True)
class OperatingPoints:
    """Trimmed operating points of one turbine and controller, in wind-speed order of the request.

    Attributes
    ----------
    points : tuple of TrimPoint
    label : str
        The turbine (deck path or "built-in NREL 5 MW").
    control : SteadyControl
    seconds : float
        Wall time of the trims (model and trim problem built before) [s].
    build_seconds : float
        Wall time to build the trim problem [s].
    trimmer : Trimmer
        The trim problem (its model and Functions), for linearization.
    """

    points: tuple[TrimPoint, ...]
    label: str
    control: SteadyControl
    seconds: float
    build_seconds: float = 0.0
    trimmer: Trimmer | None = field(default=None, repr=False, compare=False)

    def __len__(self) -> int:
        return len(self.points)

    def __iter__(self) -> Iterator[TrimPoint]:
        return iter(self.points)

    def __getitem__(self, i: int) -> TrimPoint:
        return self.points[i]

    @property
    def wind_speed(self) -> np.ndarray:
        """[m/s]."""
        return np.array([p.wind_speed for p in self.points])

    @property
    def success(self) -> bool:
        """Whether every point was trimmed."""
        return all(p.success for p in self.points)

    @property
    def failures(self) -> list[TrimPoint]:
        return [p for p in self.points if not p.success]

    def channel(self, name: str) -> np.ndarray:
        """One channel over the points (OpenFAST name and unit, NaN where a point failed)."""
        return np.array([p[name] if p.success else np.nan for p in self.points])

    def units(self) -> Mapping[str, str]:
        return self.points[0].units if self.points else {}

    @property
    def floating(self) -> bool:
        """Whether the turbine stands on a floating platform (its points have platform offsets)."""
        return self.trimmer is not None and getattr(self.trimmer.model, "platform", None) is not None

    def platform_channels(self) -> tuple[str, ...]:
        """:data:`PLATFORM_CHANNELS` and the fairlead tensions ``FAIRTEN<k>`` of a floating turbine, else ()."""
        if not self.floating or not self.points:
            return ()
        lines = tuple(n for n in self.units() if n.startswith("FAIRTEN"))
        return tuple(PLATFORM_CHANNELS) + lines

    def to_dict(self, channels: Sequence[str] | None = None) -> dict:
        """``{"wind_speed": [...], <channel>: [...], "region": [...], "success": [...]}`` (failed: None); the
        channels default to :data:`JSON_CHANNELS` and, floating, :meth:`platform_channels`."""
        if channels is None:
            channels = tuple(JSON_CHANNELS) + self.platform_channels()
        out: dict = {"wind_speed": [float(p.wind_speed) for p in self.points]}
        for name in channels:
            out[name] = [None if not p.success or not math.isfinite(p[name]) else float(p[name]) for p in self.points]
        out["region"] = [p.region for p in self.points]
        out["success"] = [bool(p.success) for p in self.points]
        return out

    def table(self, channels: Sequence[str] | None = None) -> str:
        """A plain-text table: wind speed, region ("PS": peak-shaving minimum pitch active), the channels
        (with units; default the rotor's and, floating, :meth:`platform_channels`), the controller's wind
        estimate Û."""
        if channels is None:
            channels = ("RotSpeed", "BldPitch1", "GenTq", "GenPwr", "RtAeroFxh", "TTDspFA", "RtTSR", "RtAeroCp") \
                + self.platform_channels()
        units = self.units()
        head = ["U [m/s]", "region"] + [f"{c} [{units.get(c, '')}]" for c in channels] + ["Û [m/s]"]
        rows = []
        for p in self.points:
            if not p.success:
                rows.append([f"{p.wind_speed:g}", "FAILED", p.message])
                continue
            region = p.region + (" PS" if p.peak_shaving else "")
            rows.append([f"{p.wind_speed:g}", region] + [_fmt(p[c]) for c in channels] + [f"{p.wind_estimate:.4f}"])
        widths = [max(len(h), *(len(r[i]) for r in rows if len(r) > i and len(r) == len(head)))
                  for i, h in enumerate(head)] if rows else [len(h) for h in head]
        lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths))]
        for r in rows:
            lines.append("  ".join(v.rjust(w) for v, w in zip(r, widths)) if len(r) == len(head) else "  ".join(r))
        return "\n".join(lines)

    def linearize(self, *, outputs: Sequence[str] | None = None, keep_azimuth: bool = False,
                  inflow: str = "dynamic") -> list:
        """Linear models about every successful point (:func:`~.trim_linear.linearize_point`): SI units,
        the free azimuth left out unless ``keep_azimuth``, the wake ``inflow`` "dynamic" (default),
        "frozen" or "quasi-steady" (:mod:`.inflow_choice`)."""
        from .trim_linear import linearize_point

        return [linearize_point(self.trimmer, p, outputs=outputs, keep_azimuth=keep_azimuth, inflow=inflow)
                for p in self.points if p.success]

    def campbell(self):
        """Frequencies and damping of the labelled modes with aerodynamics (:func:`~.trim_linear.aero_campbell`)."""
        from .trim_linear import aero_campbell

        return aero_campbell(self)

    def plot(self, path, *, reference: Mapping[str, Sequence[float]] | None = None, title: str | None = None) -> None:
        """Write the operating-point figure to ``path`` (:func:`~.trim_plot.plot_operating_points`)."""
        from .trim_plot import plot_operating_points

        plot_operating_points(self, path, reference=reference, title=title)


def _fmt(v: float) -> str:
    return f"{v:.6g}" if abs(v) >= 1e-3 or v == 0 else f"{v:.3e}"


def operating_points(model, wind_speeds: Sequence[float], control: SteadyControl | None = None, *,
                     p: Mapping[str, float] | None = None, n_azimuth: int | None = None,
                     tol: float = TRIM_TOLERANCE, max_iter: int = 40, label: str = "") -> OperatingPoints:
    """Trim ``model`` at each wind speed (see the module docstring).

    Parameters
    ----------
    model : OperatingTurbine
    wind_speeds : sequence of float
        [m/s], each > 0 (any order; continuation follows the given order).
    control : SteadyControl, optional
        Default the built-in NREL 5 MW's (ROSCO 2.10.6).
    p, n_azimuth, tol, max_iter : optional, keyword-only
        See :class:`~.trim.Trimmer`.
    label : str, optional, keyword-only

    Returns
    -------
    OperatingPoints
        Check :attr:`OperatingPoints.success`; a failed point has ``success`` False and a message.

    Raises
    ------
    WindInputError
        No wind speeds, or one that is not a positive finite number.
    """
    speeds = _check_speeds(wind_speeds)
    t0 = time.perf_counter()
    trimmer = Trimmer(model, control, p=p, n_azimuth=n_azimuth, tol=tol, max_iter=max_iter)
    t1 = time.perf_counter()
    points = trimmer.sweep(speeds)
    return OperatingPoints(tuple(points), label or repr(model), trimmer.control, time.perf_counter() - t1,
                           t1 - t0, trimmer)


def _check_speeds(wind_speeds) -> list[float]:
    try:
        values = [float(v) for v in np.asarray(wind_speeds, dtype=float).reshape(-1)]
    except (TypeError, ValueError):
        raise WindInputError(f"wind speeds must be numbers [m/s]; got {wind_speeds!r}.") from None
    if not values:
        raise WindInputError("no wind speeds given; pass at least one (e.g. [4, 8, 12]).")
    if len(values) > MAX_WIND_SPEEDS:
        raise WindInputError(f"{len(values)} wind speeds is more than {MAX_WIND_SPEEDS}; use a coarser step.")
    bad = [v for v in values if not (math.isfinite(v) and v > 0)]
    if bad:
        raise WindInputError(f"wind speeds must be positive finite numbers [m/s]; got {bad[:5]}.")
    return values


def parse_wind_speeds(text: str) -> list[float]:
    """Wind speeds from ``START:STOP:STEP`` (STOP included when on the grid), a comma list or one number.

    Raises
    ------
    WindInputError
        Malformed text, a non-positive step or speed, STOP below START, too many speeds.

    Examples
    --------
    >>> parse_wind_speeds("4:8:2"), parse_wind_speeds("4:9:2"), parse_wind_speeds("3.5, 11.4")
    ([4.0, 6.0, 8.0], [4.0, 6.0, 8.0], [3.5, 11.4])
    """
    if not isinstance(text, str) or not text.strip():
        raise WindInputError("--wind needs START:STOP:STEP (e.g. 4:25:1) or a comma list of speeds [m/s].")
    s = text.strip()
    if ":" in s:
        parts = s.split(":")
        if len(parts) != 3:
            raise WindInputError(f"--wind {s!r}: expected START:STOP:STEP with three numbers, e.g. 4:25:1.")
        try:
            start, stop, step = (float(v) for v in parts)
        except ValueError:
            raise WindInputError(f"--wind {s!r}: START, STOP and STEP must be numbers [m/s], e.g. 4:25:1.") from None
        if not all(math.isfinite(v) for v in (start, stop, step)):
            raise WindInputError(f"--wind {s!r}: START, STOP and STEP must be finite.")
        if step <= 0:
            raise WindInputError(f"--wind {s!r}: STEP must be > 0; got {step:g}.")
        if stop < start:
            raise WindInputError(f"--wind {s!r}: STOP ({stop:g}) must be >= START ({start:g}).")
        n = math.floor((stop - start) / step + 1e-9) + 1
        if n > MAX_WIND_SPEEDS:
            raise WindInputError(f"--wind {s!r} gives {n} wind speeds, more than {MAX_WIND_SPEEDS}; use a larger STEP.")
        values = [round(start + k * step, 12) for k in range(n)]
    else:
        try:
            values = [float(v) for v in s.replace(";", ",").split(",") if v.strip()]
        except ValueError:
            raise WindInputError(f"--wind {s!r}: expected numbers separated by commas, or START:STOP:STEP.") from None
    return _check_speeds(values)


def turbine_and_control(fst: str | Path | None = None, *, discon_in: str | Path | None = None,
                        aero: str | None = None):
    """``(model, control, label)`` of a deck, or of the built-in NREL 5 MW without one.

    Parameters
    ----------
    fst : str or Path, optional
        An OpenFAST deck with ElastoDyn, AeroDyn 15 and ServoDyn naming a ROSCO ``DISCON.IN``
        (``DLL_InFile``); its DOFs are the deck's.
    discon_in : str or Path, optional, keyword-only
        The controller's input file instead of the deck's (or with the built-in turbine).
    aero : {"rotor", "blade"}, optional, keyword-only
        The deck's rotor model (default :meth:`OperatingDeck.default_aero`). The rotor-effective model of
        trims and linear models has the disk's moment (``disk_moments=True``, docs/operation.md: its damping
        across the shaft brings the tower fore-aft damping within 0.4 points of OpenFAST's linearization,
        1.3-1.9 points without), as ``mbsym identify``'s.

    Raises
    ------
    OpenFASTFormatError
        A malformed deck or controller file (file, line, key).
    ControllerError
        A deck without a controller input file, or a controller mode that changes the steady
        state and is not modelled.
    """
    from ..operation.deck import builtin_deck, operating_deck

    if fst is None:
        deck = builtin_deck()
        control = SteadyControl.nrel5mw() if discon_in is None else SteadyControl.from_discon(Path(discon_in))
        return deck.model(disk_moments=True), control, deck.label
    deck = operating_deck(fst)
    if aero == "rotor" and deck.default_aero() == "blade":
        warnings.warn(f"{fst}: operating points on the rotor-effective rung (uniform hub-height wind along the shaft, "
                      "no aerodynamic load on blade or yaw DOFs; the tower's influence on the blade inflow as its "
                      "azimuth average, unsteady airfoils at their steady state); the deck's wind, DOFs or AeroDyn "
                      "ask for the blade-element rung in time simulation (`mbsym simulate`), whose periodic trim is "
                      "not supported.", ModelWarning, stacklevel=2)
    source = Path(discon_in) if discon_in is not None else deck.discon_in
    if source is None:
        raise ControllerError(f"{fst}: the deck names no controller input file (ServoDyn DLL_InFile); operating "
                              "points need the controller's settings (a ROSCO DISCON.IN): pass --discon-input.")
    if not source.is_file():
        raise ControllerError(f"controller input file not found: tried '{source}'"
                              + ("" if discon_in is not None else f" (ServoDyn DLL_InFile of {fst})")
                              + ". Fix the path or pass --discon-input DISCON.IN.")
    options = {"disk_moments": True, "wind_given": True} if (aero or deck.default_aero()) == "rotor" else {}
    return deck.model(aero=aero, **options), SteadyControl.from_discon(source), deck.label
