"""The mean wind InflowWind adds to a full field *after* interpolation (HAWC and native Bladed boxes).

A TurbSim box (``.bts``, and TurbSim's Bladed-style ``.wnd``) stores the full velocity, mean included. A HAWC
box (``WindType = 5``) and a native Bladed box (``WindType = 7``) store fluctuations only; InflowWind adds the
mean wind at the point's own height after interpolating them (``AddMeanAfterInterp``;
``CalculateMeanVelocity`` in OpenFAST v5.0.0 ``modules/inflowwind/src/IfW_FlowField.f90``), in the wind frame
(the point turned by ``PropagationDir``/``VFlowAng``, see :mod:`mbsym.wind.inflow.field`):

* ``z' <= 0``: 0;
* constant (``WindProfile = 0``): ``U = URef``;
* logarithmic (1): ``U = URef ln(z'/z0) / ln(RefHt/z0)`` (0 when ``RefHt == z0``);
* power law (2): ``U = URef (z'/RefHt)^PLExp``;
* then ``+ URef VLinShr (z' - RefHt) / RefLength + URef HLinShr y' / RefLength`` (native Bladed only; HAWC
  has no linear shears).

The profile is evaluated in float64 (OpenFAST's ``ReKi`` in its double-precision build).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import WindInputError

__all__ = ["MeanProfile", "PROFILE_KINDS"]

#: InflowWind's ``WindProfileType`` numbers.
PROFILE_KINDS = {0: "constant", 1: "logarithmic", 2: "power law"}


@dataclass(frozen=True)
class MeanProfile:
    """InflowWind's mean wind profile added after interpolation (see the module docstring).

    Parameters
    ----------
    kind : int
        ``WindProfile``: 0 constant, 1 logarithmic, 2 power law.
    speed : float
        ``URef``, the mean speed at the reference height [m/s] (not negative).
    reference_height : float
        ``RefHt`` [m] (> 0).
    exponent : float
        ``PLExp`` [-] (power law).
    roughness : float
        ``Z0`` [m] (logarithmic; > 0 there).
    vertical_linear_shear, horizontal_linear_shear : float
        ``VLinShr``, ``HLinShr`` [-] (native Bladed).
    reference_length : float
        ``RefLength`` [m] for the linear shears (> 0 when one is non-zero).

    Raises
    ------
    WindInputError
        A value InflowWind's ``Grid3D_ValidateInput`` refuses, naming it.
    """

    kind: int
    speed: float
    reference_height: float
    exponent: float = 0.0
    roughness: float = 0.0
    vertical_linear_shear: float = 0.0
    horizontal_linear_shear: float = 0.0
    reference_length: float = 1.0

    def __post_init__(self) -> None:
        values = {k: float(getattr(self, k)) for k in ("speed", "reference_height", "exponent", "roughness",
                                                        "vertical_linear_shear", "horizontal_linear_shear",
                                                        "reference_length")}
        bad = [k for k, v in values.items() if not math.isfinite(v)]
        if self.kind not in PROFILE_KINDS:
            bad.append(f"kind = {self.kind!r} (expected 0 constant, 1 logarithmic or 2 power law)")
        if values["speed"] < 0.0:
            bad.append("speed < 0 (URef must not be negative)")
        if not values["reference_height"] > 0.0:
            bad.append("reference_height <= 0 (RefHt must be positive)")
        if self.kind == 1 and not values["roughness"] > 0.0:
            bad.append("roughness <= 0 (Z0 must be positive for a logarithmic profile)")
        shears = values["vertical_linear_shear"] != 0.0 or values["horizontal_linear_shear"] != 0.0
        if shears and not values["reference_length"] > 0.0:
            bad.append("reference_length <= 0 (RefLength must be positive with linear shears)")
        if bad:
            raise WindInputError(f"MeanProfile: {'; '.join(bad)}. Fix the InflowWind (or Bladed summary) values.")
        object.__setattr__(self, "kind", int(self.kind))
        for k, v in values.items():
            object.__setattr__(self, k, v)

    def __call__(self, y, z) -> np.ndarray:
        """Mean longitudinal speed [m/s] at wind-frame lateral position ``y`` and height ``z`` [m] (arrays)."""
        y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
        up = z > 0.0
        zz = np.where(up, z, 1.0)
        if self.kind == 2:
            u = self.speed * (zz / self.reference_height) ** self.exponent
        elif self.kind == 1:
            if self.reference_height == self.roughness:
                u = np.zeros_like(zz)
            else:
                u = self.speed * np.log(zz / self.roughness) / math.log(self.reference_height / self.roughness)
        else:
            u = np.full_like(zz, self.speed)
        if self.vertical_linear_shear != 0.0:
            u = u + self.speed * self.vertical_linear_shear * (zz - self.reference_height) / self.reference_length
        if self.horizontal_linear_shear != 0.0:
            u = u + self.speed * self.horizontal_linear_shear * y / self.reference_length
        return np.where(up, u, 0.0)

    def c_source(self) -> str:
        """A C function ``static double mean_profile(double y, double z)`` with the same arithmetic."""
        r = repr
        if self.kind == 2:
            body = f"u = {r(self.speed)} * pow(z / {r(self.reference_height)}, {r(self.exponent)});"
        elif self.kind == 1 and self.reference_height != self.roughness:
            body = (f"u = {r(self.speed)} * log(z / {r(self.roughness)}) / "
                    f"{r(math.log(self.reference_height / self.roughness))};")
        elif self.kind == 1:
            body = "u = 0.0;"
        else:
            body = f"u = {r(self.speed)};"
        if self.vertical_linear_shear != 0.0:
            body += (f" u += {r(self.speed * self.vertical_linear_shear)} * (z - {r(self.reference_height)}) / "
                     f"{r(self.reference_length)};")
        if self.horizontal_linear_shear != 0.0:
            body += f" u += {r(self.speed * self.horizontal_linear_shear)} * y / {r(self.reference_length)};"
        return ("static double mean_profile(double y, double z) {\n  double u;\n  (void)y;\n"
                f"  if (!(z > 0.0)) return 0.0;\n  {body}\n  return u;\n}}\n")

    def describe(self) -> str:
        """One line for reprs and messages."""
        extra = {0: "", 1: f", z0={self.roughness:g} m", 2: f", PLExp={self.exponent:g}"}[self.kind]
        return f"{PROFILE_KINDS[self.kind]} mean {self.speed:g} m/s at {self.reference_height:g} m{extra}"
