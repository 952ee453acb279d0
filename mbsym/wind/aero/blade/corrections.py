"""Corrections AeroDyn applies to the induction after DBEMT: Pitt/Peters skewed wake, low TSR.

**Skewed wake** (``Skew_Mod = 1``, ``SkewRedistr_Mod = 1``, ``BEM_Mod = 1``; BEMTUncoupled.f90
``ApplySkewedWakeCorrection``): the axial induction of every node that is not tip/hub-fixed is
redistributed over the disk,

    a ← a (1 + K tan(χ/2) (r / R_tip) sin ψ_s),    χ = (0.6 a + 1) χ₀,

with ``K = SkewRedistrFactor`` (default 15π/32), ``tan(χ/2)`` replaced by 1 beyond ``|χ| > π/2``
(AeroDyn's limit), and no tip-loss factor (that one is for ``BEM_Mod = 2``). ``χ₀ >= 0`` is the
angle between the disk-averaged relative wind and the shaft axis (AeroDyn's ``chi0``, unsigned
for ``BEM_Mod = 1``; it is the ``RtSkew`` channel). ``ψ_s`` is AeroDyn's skew azimuth of the
blade (DiskAvgValues): 90° when the blade points along the in-plane component of the wind
(the side the wake is skewed towards), so ``sin ψ_s = cos(ψ - ψ_w)`` with ``ψ`` the blade
azimuth and ``ψ_w`` the azimuth, in the same convention, at which a blade would point along
the in-plane wind. AeroDyn uses the axial induction *after* DBEMT in ``χ``, and the quasi-steady
induction (before this correction) as DBEMT's input: so does :mod:`.rotor`.

**Low TSR** (``check_turnOffBEMT``): below a rotor tip-speed ratio of 2, every node's ``a`` and
``a'`` are multiplied by ``(1 - cos(π (λ - 1))) / 2`` clipped to [0, 1] (zero below λ = 1).
"""

from __future__ import annotations

import math
from typing import Any

import casadi as ca

__all__ = ["skewed_wake", "low_tsr_weight", "DEFAULT_SKEW_FACTOR"]

#: AeroDyn's default SkewRedistrFactor.
DEFAULT_SKEW_FACTOR = 15.0 * math.pi / 32.0


def skewed_wake(a: Any, chi0: Any, sin_psi_s: Any, radius_ratio: Any, factor: float) -> Any:
    """Pitt/Peters redistribution of the axial induction ``a`` (SX column) [-]."""
    chi = (0.6 * a + 1.0) * chi0
    tan_half = ca.tan(ca.fmin(ca.fmax(chi, -math.pi / 2.0), math.pi / 2.0) / 2.0)
    return a * (1.0 + factor * tan_half * radius_ratio * sin_psi_s)


def low_tsr_weight(tsr: Any) -> Any:
    """AeroDyn's cosine blend of the induction between TSR 1 (0) and 2 (1)."""
    x = ca.fmin(ca.fmax(ca.fabs(tsr) - 1.0, 0.0), 1.0)
    return 0.5 * (1.0 - ca.cos(math.pi * x))
