"""Names of ElastoDyn's rotating-frame blade coordinates and the blade-1 azimuth.

The one place that knows that blade coordinates are named ``B<blade><type>``
(``F1`` 1st flap, ``E1`` 1st edge, ``F2`` 2nd flap): the template names them so,
the output channels and the multi-blade transformation
(:mod:`mbsym.wind.structure.mbc`) read them so.
"""

from __future__ import annotations

import re
from typing import Sequence

import numpy as np

from ...exceptions import ModelDefinitionError

__all__ = ["N_BLADES", "BLADE_COORDINATE", "blade_dof", "blade_indices", "mbc_coordinate_names", "blade1_azimuth"]

#: Number of blades the transformation handles (ElastoDyn's 3-bladed rotors).
N_BLADES = 3
#: Names of rotating-frame blade coordinates: ``B<blade><type>`` with blade 1, 2, … and type
#: ``F1`` (1st flap), ``E1`` (1st edge) or ``F2`` (2nd flap), ElastoDyn's DOF names.
BLADE_COORDINATE = re.compile(r"B(\d+)(F1|E1|F2)")


def blade_dof(name: str) -> tuple[int, str] | None:
    """``(blade, type)`` of a blade coordinate name (blade 1-based), or None for other names.

    Examples
    --------
    >>> blade_dof("B2E1"), blade_dof("TFA1")
    ((2, 'E1'), None)
    """
    m = BLADE_COORDINATE.fullmatch(str(name))
    return (int(m.group(1)), m.group(2)) if m else None


def blade_indices(coordinates: Sequence[str]) -> list[tuple[int, ...]]:
    """Indices of blades 1, 2, … in ``coordinates``, one tuple per blade DOF type (first-seen order).

    Examples
    --------
    >>> blade_indices(["TFA1", "B1F1", "B2F1", "B3F1", "B1E1", "B2E1", "B3E1"])
    [(1, 2, 3), (4, 5, 6)]
    """
    by_type: dict[str, dict[int, int]] = {}
    for i, name in enumerate(coordinates):
        dof = blade_dof(name)
        if dof:
            by_type.setdefault(dof[1], {})[dof[0]] = i
    return [tuple(g[b] for b in sorted(g)) for g in by_type.values()]


def mbc_coordinate_names(coordinates: Sequence[str]) -> tuple[str, ...]:
    """Coordinate names after the transformation: blade triplets become ``<type>_coll``, ``_cos``, ``_sin``.

    Raises
    ------
    ModelDefinitionError
        A blade DOF type without exactly the blades 1..N_BLADES.

    Examples
    --------
    >>> mbc_coordinate_names(["TFA1", "B1F1", "B2F1", "B3F1"])
    ('TFA1', 'F1_coll', 'F1_cos', 'F1_sin')
    """
    by_type: dict[str, dict[int, int]] = {}
    for i, name in enumerate(coordinates):
        dof = blade_dof(name)
        if dof:
            by_type.setdefault(dof[1], {})[dof[0]] = i
    names = list(coordinates)
    for kind, blades in by_type.items():
        if sorted(blades) != list(range(1, N_BLADES + 1)):
            raise ModelDefinitionError(f"multi-blade coordinates need blades 1..{N_BLADES} for each blade DOF; "
                                       f"{kind} has blades {sorted(blades)}.")
        for b, suffix in zip(range(1, N_BLADES + 1), ("coll", "cos", "sin")):
            names[blades[b]] = f"{kind}_{suffix}"
    return tuple(names)


def blade1_azimuth(generator_azimuth, azimuth_blade1_up: float, drivetrain_torsion=0.0):
    """Azimuth of blade 1 [rad]: ElastoDyn's ``Azimuth`` output ``q_GeAz + q_DrTr + AzimB1Up + π/2``.

    Not wrapped; numbers or arrays. Zero with blade 1 up (for AzimB1Up = 0), increasing
    with the rotation.

    Examples
    --------
    >>> import numpy as np
    >>> round(float(blade1_azimuth(3 * np.pi / 2, 0.0)), 6)      # ElastoDyn's q_GeAz at Azimuth 0
    6.283185
    """
    return generator_azimuth + drivetrain_torsion + azimuth_blade1_up + np.pi / 2
