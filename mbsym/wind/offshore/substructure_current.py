"""SeaState's steady current (``CurrMod = 1``) on HydroDyn's members over a SubDyn substructure (OpenFAST v5.0.0).

HydroDyn's drag per unit length on a member is quadratic in the water's velocity relative to the node,
``½ ρ C_d D |v_n| v_n`` with ``v = u_waves + U − ṙ`` (``Morison.f90``, ``Morison_CalcOutput``: ``vrel = FV −
TranslationVel``, ``FV`` SeaState's grid velocity, which holds the current; the end plates' axial drag alike), so a
steady current ``U(z)`` (:mod:`.current`) acts in two ways, both modelled (:mod:`.substructure_water`,
:mod:`.bottom_fixed`):

1. **at rest**: the drag of ``u_waves + U`` — in still water a constant load (the mean current drag, in
   :attr:`~.substructure_water.SubstructureWater.static_loads` as the part ``current``), in waves the drag of the
   sum less that constant (the waves' share, whose mean is not zero);
2. **the structure's velocity at first order**: ``F(u + U − ṙ) ≈ F(u + U) − B ṙ`` with ``B = ⟨∂F/∂v⟩``, per strip
   ``ρ C_d r Δl (|v_n| P + v_n v_nᵀ/|v_n|)`` (``P`` the projector across the member;
   :func:`~.substructure_water.drag_slope`), averaged over the sea's record in waves: a constant nodal damping
   (:meth:`~.substructure_water.SubstructureWater.drag_damping`) that :mod:`.bottom_fixed` projects with the Guyan
   shapes and the Craig–Bampton modes into the turbine's equations. Zero in still water without a current (the
   drag is quadratic); with the IEA 15 MW monopile's 0.8 m/s current it adds 0.002 % of critical damping to the
   first fore-aft tower mode and 0.017 % to the second, as OpenFAST's runs show; in waves alone it is the waves'
   mean slope (2.0e4 N s/m in surge at the TP).

Chosen by measurement against OpenFAST (``tests/data/openfast_subdyn_current/README.md``): with ``B`` the released
monopile's TP motion follows OpenFAST's within ε = mean|Δ|/range 0.01-0.05 % in still water with the current and
0.02-0.05 % in waves with it (0.08-0.10 % without ``B``); in the deck's sea without a current 0.02-0.05 % (0.05-0.07 %
without). Left out: the drag's terms of second order in the structure's velocity (``|ṙ| ≪ |u + U|`` under the sea
level) and the slope's correlation with the waves (its time mean is used).

:func:`grid_current` reads the current off SeaState's grid as :func:`~.current.current_at` does, but evaluates the
profile at the grid's heights **in single precision**, as SeaState does (``SeaState_Input.f90`` stores
``WaveKinGridzi`` as ``SiKi``; ``Current.f90``'s ``Calc_Current`` takes ``z`` and ``h`` as ``SiKi``): the grid's
bottom node is then exactly at ``−Z_Depth`` and its sub-surface current ``((z + h)/h)^{1/7}`` exactly zero, where the
double-precision height (1.8e-15 m above it) gives 0.0053 ``CurrSSV0`` — 1.3e-4 of the IEA 15 MW monopile's current
drag, through the grid's interpolation to the lowest nodes.
"""

from __future__ import annotations

import numpy as np

from .current import current_at, sea_current

__all__ = ["grid_current", "current_problems_with_waves"]


def grid_current(sea, water_depth: float, points) -> np.ndarray | None:
    """SeaState's current ``(n, 3)`` [m/s] at ``points`` (n, 3) [m; undisplaced, inertial, z from the still-water level]
    as HydroDyn reads it off SeaState's grid (module docstring); None without a current (``CurrMod = 0``).

    Parameters
    ----------
    sea : SeaStateInput
    water_depth : float
        SeaState's water depth [m] (its own ``WtrDpth``, else the ``.fst``'s).
    points : array_like (n, 3)

    Raises
    ------
    UnsupportedFeatureError
        ``CurrMod = 2`` (:func:`~.current.current_problems`).
    ParameterError
        What SeaState refuses of the current's values (:func:`~.current.sea_current`).
    """
    current = sea_current(sea, water_depth)
    if current is None:
        return None
    return current_at(current, sea, points)           # the grid's heights in single precision (.current)


def current_problems_with_waves(sea) -> list[str]:
    """What of a current with waves is not modelled: wave-current interaction (``WvCrntMod`` > 0; SeaState ignores it
    in still water, ``SeaState_Input.f90``)."""
    if sea is None or not sea.current_model or sea.wave_model == 0 or not sea.wave_current_model:
        return []
    return [f"WvCrntMod = {sea.wave_current_model} (wave-current interaction) is not modelled; use 0"]
