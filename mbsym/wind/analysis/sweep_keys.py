"""Keys of a turbine sweep: what ``--set KEY=V1,V2`` may name, and where each value goes.

A key resolves, in this order, to

1. a **parameter of the model by its own name** (SI units), e.g. ``tower_fa1_damping_ratio``,
   ``air_density``, ``pitch_max``;
2. an **initial condition** of ElastoDyn (:data:`INITIAL_CONDITIONS`, the deck's units):
   ``TTDspFA``, ``TTDspSS`` [m], ``RotSpeed`` [rpm], ``NacYaw`` [deg], ``BlPitch`` [deg] (the
   operating turbine's pitch actuator); it sets the state at t = 0 and needs the DOF;
3. an **ElastoDyn deck key** of the named parameters
   (:mod:`mbsym.wind.structure.named_parameters`), in the deck's units: ``TwrFADmp(1)`` in %,
   ``FAStTunr(1)``, ``NacMass`` [kg], ... (any spelling ``canonical_key`` accepts, e.g. ``TwrFADmp1``).

The key is kept exactly as passed (it names the table's column). Anything else raises a
:class:`~mbsym.exceptions.ParameterError` naming what is known.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping, Sequence

from ...exceptions import ParameterError

__all__ = ["INITIAL_CONDITIONS", "RESERVED_KEYS", "KeyTarget", "resolve_key", "case_settings"]

#: ElastoDyn initial-condition key -> (candidate states, first present wins; SI value per key unit; unit).
INITIAL_CONDITIONS: dict[str, tuple[tuple[str, ...], float, str]] = {
    "TTDspFA": (("TFA1", "TFA2"), 1.0, "m"),
    "TTDspSS": (("TSS1", "TSS2"), 1.0, "m"),
    "RotSpeed": (("GeAz_d",), math.pi / 30.0, "rpm"),
    "NacYaw": (("Yaw",), math.pi / 180.0, "deg"),
    "BlPitch": (("BlPitch",), math.pi / 180.0, "deg"),
}
#: DOF flag that gives each initial-condition key its state (for messages).
_IC_DOFS = {"TTDspFA": "TwFADOF1", "TTDspSS": "TwSSDOF1", "RotSpeed": "GenDOF", "NacYaw": "YawDOF",
            "BlPitch": "the operating turbine (--wind)"}
#: Keys a sweep uses itself.
RESERVED_KEYS = ("wind", "error", "tmax", "dt")


@dataclass(frozen=True)
class KeyTarget:
    """Where the values of one swept key go.

    Attributes
    ----------
    key : str
        As passed (the table's column).
    kind : str
        ``"parameter"`` or ``"initial"``.
    name : str
        Parameter name of the model, or the state set at t = 0.
    factor : float
        Key value = ``factor`` x model value (100 for a damping ratio in %; 30/π for rpm).
    unit : str
        Unit of the key's values.
    lower : float
        Smallest physical value in key units (``-inf``: none). A case below it fails in its row.
    """

    key: str
    kind: str
    name: str
    factor: float = 1.0
    unit: str = ""
    lower: float = -math.inf

    def apply(self, value: float) -> dict:
        """``{"p": {name: v}}`` or ``{"x0": {state: v}}`` for one value in key units.

        Raises
        ------
        ParameterError
            A value that is not a finite number or lies below :attr:`lower` (the sweep records it
            in the case's row).
        """
        v = float(value)
        if not math.isfinite(v):
            raise ParameterError(f"{self.key} = {value!r} is not a finite number.")
        if v < self.lower:
            unit = "" if self.unit in ("", "-") else f" {self.unit}"
            raise ParameterError(f"{self.key} = {v:g}{unit} is below its physical lower bound {self.lower:g}{unit}.")
        part = "p" if self.kind == "parameter" else "x0"
        return {part: {self.name: v / self.factor}}


def resolve_key(key: str, *, parameters: Sequence[str], states: Sequence[str],
                dofs: Mapping[str, bool] | None = None) -> KeyTarget:
    """The :class:`KeyTarget` of ``key`` for a model with ``parameters`` and ``states`` (module docstring).

    Raises
    ------
    ParameterError
        A reserved, unknown or absent key (says which DOF or mode would make it present).
    """
    from ..structure.named_parameters import lookup, resolve

    if not isinstance(key, str) or not key.strip():
        raise ParameterError(f"a swept key must be a non-empty string; got {key!r}.")
    if key.strip().lower() in RESERVED_KEYS:
        raise ParameterError(f"{key!r} is not a swept key: 'wind' is set with --wind/wind=, 'tmax' with --tmax, and "
                             "'error' is a column of the table.")
    if key in parameters:
        try:
            e = lookup(key)
            return KeyTarget(key, "parameter", key, 1.0, _si_unit(e), e.lower / e.factor)
        except ParameterError:
            return KeyTarget(key, "parameter", key)
    ic = next((k for k in INITIAL_CONDITIONS if k.lower() == key.strip().lower()), None)
    if ic is not None:
        candidates, factor, unit = INITIAL_CONDITIONS[ic]
        state = next((s for s in candidates if s in states), None)
        if state is None:
            raise ParameterError(f"{key!r} sets the state {candidates[0]!r} at t = 0, which this model does not "
                                 f"have: enable {_IC_DOFS[ic]}. Its states are {list(states)}.")
        return KeyTarget(key, "initial", state, 1.0 / factor, unit)
    try:
        e = lookup(key)
    except ParameterError:
        raise ParameterError(
            f"unknown sweep key {key!r}: expected an ElastoDyn key of the named parameters (e.g. 'TwrFADmp(1)', "
            f"'FAStTunr(1)', 'NacMass'; see mbsym.wind.structure.named_parameters.parameter_table()), an initial "
            f"condition ({', '.join(INITIAL_CONDITIONS)}) or a parameter of the model: {list(parameters)}.") from None
    resolve(parameters, key, dofs=dofs)                 # raises, saying why the model lacks it
    return KeyTarget(key, "parameter", e.name, e.factor, e.unit, e.lower)


def _si_unit(entry) -> str:
    return entry.unit if entry.factor == 1.0 else ("-" if entry.unit == "%" else "")


def case_settings(targets: Sequence[KeyTarget], values: Sequence[float]) -> dict:
    """The ``{"p": {...}, "x0": {...}}`` of one combination of values (one per target)."""
    out: dict = {"p": {}, "x0": {}}
    for t, v in zip(targets, values):
        for part, d in t.apply(v).items():
            out[part].update(d)
    return out
