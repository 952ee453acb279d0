"""The ``--wind SPEC`` strings of the command line, parsed into wind signals.

=========================  ==============================================================
SPEC                       signal
=========================  ==============================================================
``steady:U``               :class:`SteadyWind` ``U`` [m/s]
``step:U0:U1:T``           :class:`StepWind` ``U0 → U1`` [m/s] at ``T`` [s]
``ramp:U0:U1:T0:T1``       :class:`RampWind` ``U0 → U1`` over ``[T0, T1]`` [s]
``kaimal:U:TI:SEED``       :func:`kaimal_wind` (TI as a fraction, ``0.14``, or ``14%``)
``eog:U:T0:VGUST``         :class:`ExtremeOperatingGust` starting at ``T0`` with gust ``VGUST``
a file path                ``.csv``: :func:`read_wind_csv`; anything else: an InflowWind
                           uniform wind file (:func:`read_uniform_wind`)
=========================  ==============================================================
"""

from __future__ import annotations

import math
from pathlib import Path

from ...exceptions import WindInputError
from .files import read_uniform_wind, read_wind_csv
from .kaimal import kaimal_wind
from .signals import ExtremeOperatingGust, RampWind, SteadyWind, StepWind, WindSignal

__all__ = ["parse_wind_spec", "WIND_SPEC_FORMS"]

#: The accepted forms, for messages and help texts.
WIND_SPEC_FORMS = ("steady:U", "step:U0:U1:T", "ramp:U0:U1:T0:T1", "kaimal:U:TI:SEED", "eog:U:T0:VGUST",
                   "<path to an InflowWind uniform wind file or a Time_[s],Wind1VelX_[m/s] CSV>")
_ARGS = {"steady": ("U",), "step": ("U0", "U1", "T"), "ramp": ("U0", "U1", "T0", "T1"),
         "kaimal": ("U", "TI", "SEED"), "eog": ("U", "T0", "VGUST")}


def _float(spec: str, name: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise WindInputError(f"wind spec {spec!r}: {name} must be a number; got {text!r}.")
    return value


def parse_wind_spec(spec: str, *, duration: float = 600.0, dt: float = 0.05,
                    allow_unmodelled: bool = False) -> WindSignal:
    """Parse a ``--wind`` SPEC (see the module docstring) into a :class:`WindSignal`.

    Parameters
    ----------
    spec : str
        The specification or a file path.
    duration : float, optional
        Length [s] of generated turbulence (``kaimal``).
    dt : float, optional
        Time step [s] of generated turbulence.
    allow_unmodelled : bool, optional
        For uniform wind files: accept non-zero direction, shear or upflow and use
        only the hub-height speed (see :meth:`UniformWind.signal`).

    Raises
    ------
    WindInputError
        Unknown form, wrong number of fields, non-numeric or out-of-range fields,
        a path that does not exist.
    OpenFASTFormatError
        A wind file that exists but is malformed (names file and line).

    Examples
    --------
    >>> from mbsym.wind.inflow import parse_wind_spec
    >>> parse_wind_spec("step:10:14:30")(31.0)
    14.0
    """
    if not isinstance(spec, (str, Path)):
        raise TypeError(f"the wind spec must be a string; got {type(spec).__name__}.")
    text = str(spec).strip()
    kind, _, rest = text.partition(":")
    if kind.lower() in _ARGS and not Path(text).exists():
        return _from_fields(text, kind.lower(), rest.split(":") if rest else [], duration, dt)
    path = Path(text)
    if path.is_file():
        if path.suffix.lower() == ".csv":
            return read_wind_csv(path)
        return read_uniform_wind(path).signal(allow_unmodelled=allow_unmodelled)
    raise WindInputError(f"wind spec {text!r} is neither a known form nor an existing file (tried "
                         f"'{path.absolute()}'); expected one of: {', '.join(WIND_SPEC_FORMS)}.")


def _from_fields(spec: str, kind: str, fields: list[str], duration: float, dt: float) -> WindSignal:
    names = _ARGS[kind]
    if len(fields) != len(names):
        raise WindInputError(f"wind spec {spec!r}: '{kind}' takes {len(names)} field(s) "
                             f"{kind}:{':'.join(names)}; got {len(fields)}.")
    if kind == "kaimal":
        u = _float(spec, "U", fields[0])
        ti_text = fields[1].strip()
        ti = _float(spec, "TI", ti_text.rstrip("%")) / (100.0 if ti_text.endswith("%") else 1.0)
        if not 0.0 < ti < 1.0:
            raise WindInputError(f"wind spec {spec!r}: TI must be a fraction in (0, 1) such as 0.14, or a "
                                 f"percentage such as 14%; got {ti_text!r}.")
        seed_text = fields[2].strip()
        if not seed_text.isdigit():
            raise WindInputError(f"wind spec {spec!r}: SEED must be a non-negative integer; got {seed_text!r}.")
        return kaimal_wind(u, ti, int(seed_text), duration=duration, dt=dt)
    values = [_float(spec, n, f) for n, f in zip(names, fields)]
    try:
        if kind == "steady":
            return SteadyWind(values[0])
        if kind == "step":
            return StepWind(values[0], values[1], values[2])
        if kind == "ramp":
            return RampWind(*values)
        return ExtremeOperatingGust(values[0], start=values[1], gust_speed=values[2])
    except WindInputError as exc:
        raise WindInputError(f"wind spec {spec!r}: {exc}") from None
