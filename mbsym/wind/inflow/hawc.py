"""HAWC-format full-field wind boxes (InflowWind ``WindType = 5``): three binary files of fluctuations.

A HAWC box (HAWC2's and Mann's turbulence generator's format; TurbSim writes it with ``WrHAWCFF``) is three
files of little-endian float32, one per component ``u``, ``v``, ``w``, without a header: ``nx`` planes one
after the other, each ``ny`` columns of ``nz`` values (``z`` fastest). Everything else comes from the
InflowWind file (``nx``, ``ny``, ``nz``, ``dx``, ``dy``, ``dz``, ``RefHt_Hawc``, the scaling and the mean
profile). Read as OpenFAST v5.0.0 InflowWind does (``IfW_HAWC_Init``, ``Grid3D_ScaleTurbulence`` in
``modules/inflowwind/src/InflowWind_IO.f90``):

1. plane ``i`` is the field's time step ``i`` (``dt = dx / URef``); the lateral order is reversed
   (file column ``j`` is InflowWind's ``y`` index ``ny + 1 - j``); the grid is centred on ``RefHt_Hawc``
   (bottom ``RefHt - (nz - 1) dz / 2``) and on the tower laterally;
2. ``ScaleMethod`` 1 multiplies each component by ``SFx``, ``SFy``, ``SFz``; 2 by ``SigmaF / σ`` with ``σ`` the
   component's standard deviation over time at the grid's centre point (``((n + 1) // 2)`` in y and z, 1-based);
   0 leaves the data as they are;
3. with ``ScaleMethod`` 1 or 2 the time mean of ``u`` at every grid point is removed;
4. the field is periodic, starts at ``x = XOffset`` (``InitXPosition``), is interpolated to zero at the
   ground below the grid (``InterpTower``), and the mean profile (``WindProfile``: constant, logarithmic
   with ``Z0``, power law with ``PLExp_Hawc``, at ``URef`` and ``RefHt_Hawc``) is added to ``u`` after
   interpolation at each point's height (:class:`~mbsym.wind.inflow.profile.MeanProfile`).

Memory: the box is kept once as float32 (``4 nx ny nz 3`` bytes); reading maps each file and fills the
grid component by component.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError, WindInputError
from .field import FullFieldWind
from .profile import MeanProfile

__all__ = ["HawcBox", "read_hawc", "write_hawc", "SCALE_METHODS"]

#: InflowWind's ``ScaleMethod``.
SCALE_METHODS = {0: "none", 1: "direct scaling factors", 2: "target standard deviations"}


@dataclass(frozen=True)
class HawcBox:
    """A HAWC box as an InflowWind file describes it (SI units).

    Attributes
    ----------
    files : tuple of 3 Path
        ``FileName_u``, ``FileName_v``, ``FileName_w``.
    nx, ny, nz : int
        Grid points along x (time), y, z.
    dx, dy, dz : float
        Spacing [m].
    reference_height : float
        ``RefHt_Hawc``: the height of the grid's vertical centre and of the profile's reference [m].
    scale_method : int
        ``ScaleMethod`` (0 none, 1 factors, 2 standard deviations).
    scale_factors : tuple of 3 float
        ``SFx``, ``SFy``, ``SFz`` [-] (method 1).
    target_sigmas : tuple of 3 float
        ``SigmaFx``, ``SigmaFy``, ``SigmaFz`` [m/s] (method 2).
    mean_speed : float
        ``URef`` [m/s]: the profile's speed at the reference height and the advection speed.
    profile : int
        ``WindProfile`` (0 constant, 1 logarithmic, 2 power law).
    exponent : float
        ``PLExp_Hawc`` [-].
    roughness : float
        ``Z0`` [m].
    x_offset : float
        ``XOffset`` [m].
    source : str
        Where the description came from (for messages).
    """

    files: tuple
    nx: int
    ny: int
    nz: int
    dx: float
    dy: float
    dz: float
    reference_height: float
    scale_method: int = 0
    scale_factors: tuple = (1.0, 1.0, 1.0)
    target_sigmas: tuple = (1.0, 1.0, 1.0)
    mean_speed: float = 0.0
    profile: int = 2
    exponent: float = 0.2
    roughness: float = 0.03
    x_offset: float = 0.0
    source: str = ""

    def check(self) -> None:
        """Raise :class:`~mbsym.exceptions.WindInputError` naming every value InflowWind (or mbsym's
        interpolation, which needs 2 points per axis) refuses."""
        bad = [f"{k} = {getattr(self, k)} (at least 2 points)" for k in ("nx", "ny", "nz") if getattr(self, k) < 2]
        bad += [f"{k} = {getattr(self, k):g} (must be > 0 m)" for k in ("dx", "dy", "dz", "reference_height")
                if not (math.isfinite(getattr(self, k)) and getattr(self, k) > 0.0)]
        if not (math.isfinite(self.mean_speed) and self.mean_speed > 0.0):
            bad.append(f"URef = {self.mean_speed:g} (must be > 0 m/s: it carries the box past the rotor)")
        if self.scale_method not in SCALE_METHODS:
            bad.append(f"ScaleMethod = {self.scale_method} (0 none, 1 direct factors, 2 standard deviations)")
        if self.scale_method == 1 and any(not (math.isfinite(v) and v >= 0.0) for v in self.scale_factors):
            bad.append(f"SFx, SFy, SFz = {tuple(self.scale_factors)} (must not be negative)")
        if self.scale_method == 2 and any(not (math.isfinite(v) and v >= 0.0) for v in self.target_sigmas):
            bad.append(f"SigmaFx, SigmaFy, SigmaFz = {tuple(self.target_sigmas)} (must not be negative)")
        if self.profile == 1 and not self.roughness > 0.0:
            bad.append(f"Z0 = {self.roughness:g} (must be > 0 m for the logarithmic profile)")
        if self.profile not in (0, 1, 2):
            bad.append(f"WindProfile = {self.profile} (0 constant, 1 logarithmic, 2 power law)")
        if not math.isfinite(self.x_offset):
            bad.append(f"XOffset = {self.x_offset} (must be finite)")
        if bad:
            raise WindInputError(f"{self.source or 'HAWC box'}: {'; '.join(bad)}. Fix these InflowWind values.")


def read_hawc(box: HawcBox, *, propagation_direction: float = 0.0, upflow_angle: float = 0.0) -> FullFieldWind:
    """Read a HAWC box (see the module docstring) into a :class:`~mbsym.wind.inflow.field.FullFieldWind`.

    Parameters
    ----------
    box : HawcBox
        The files and the InflowWind values.
    propagation_direction, upflow_angle : float, optional, keyword-only
        InflowWind's ``PropagationDir`` and ``VFlowAng`` [rad].

    Returns
    -------
    FullFieldWind
        Periodic, interpolated to the ground below the grid, with the mean profile added after
        interpolation and ``x_offset = XOffset``.

    Raises
    ------
    WindInputError
        Invalid values (:meth:`HawcBox.check`); ``ScaleMethod = 2`` with a component constant at the centre
        point but a non-zero target.
    OpenFASTFormatError
        A missing file, or a file with fewer than ``nx ny nz`` float32 values (names the file and sizes).
    """
    box.check()
    grid = np.empty((box.nx, box.nz, box.ny, 3), dtype=np.float32)
    for c, name in enumerate(box.files):
        grid[..., c] = _component(Path(name), box, "uvw"[c])
    _scale(grid, box)
    if box.scale_method != 0:                                  # InflowWind removes u's mean at each grid point
        mean = grid[..., 0].mean(axis=0, dtype=np.float64)
        grid[..., 0] = (grid[..., 0] - mean).astype(np.float32)
    half_height = 0.5 * box.dz * (box.nz - 1)
    profile = MeanProfile(box.profile, box.mean_speed, box.reference_height, exponent=box.exponent,
                          roughness=box.roughness)
    return FullFieldWind(grid, dy=box.dy, dz=box.dz, dt=box.dx / box.mean_speed, mean_speed=box.mean_speed,
                         reference_height=box.reference_height, grid_bottom=box.reference_height - half_height,
                         periodic=True, interpolate_to_ground=True, mean_profile=profile, x_offset=box.x_offset,
                         propagation_direction=propagation_direction, upflow_angle=upflow_angle,
                         source=str(box.files[0]), description=f"HAWC box ({SCALE_METHODS[box.scale_method]})")


def _component(path: Path, box: HawcBox, comp: str) -> np.ndarray:
    """One component as (nx, nz, ny) float32 in InflowWind's index order (lateral order reversed)."""
    if not path.is_file():
        raise OpenFASTFormatError(f"HAWC {comp}-component file not found: tried '{path.absolute()}' "
                                  f"(FileName_{comp}). Check the path (relative to the InflowWind file).")
    n = box.nx * box.ny * box.nz
    size = path.stat().st_size
    if size < 4 * n:
        raise OpenFASTFormatError(f"{path}: {size} bytes, fewer than the nx * ny * nz = {box.nx} x {box.ny} x "
                                  f"{box.nz} float32 values ({4 * n} bytes) the InflowWind file announces. Check "
                                  "nx, ny, nz or the file.")
    if size > 4 * n:
        warnings.warn(f"{path}: {size} bytes, more than the nx * ny * nz = {4 * n} bytes the InflowWind file "
                      "announces; the first ones are read (as InflowWind does). Check nx, ny, nz.",
                      stacklevel=3)
    raw = np.memmap(path, dtype="<f4", mode="r", shape=(box.nx, box.ny, box.nz))
    out = np.ascontiguousarray(np.swapaxes(raw[:, ::-1, :], 1, 2))
    del raw
    if not np.isfinite(out).all():
        raise OpenFASTFormatError(f"{path}: non-finite values in the {comp} component. Check the file.")
    return out


def _scale(grid: np.ndarray, box: HawcBox) -> None:
    """InflowWind's ``Grid3D_ScaleTurbulence`` in place (float64 factors, float32 results)."""
    if box.scale_method == 0:
        return
    if box.scale_method == 1:
        factors = np.asarray(box.scale_factors, dtype=float)
    else:
        centre = grid[:, (box.nz + 1) // 2 - 1, (box.ny + 1) // 2 - 1, :].astype(np.float64)
        mean = centre.sum(axis=0) / box.nx
        sigma = np.sqrt(np.abs((centre ** 2).sum(axis=0) / box.nx - mean ** 2))
        target = np.asarray(box.target_sigmas, dtype=float)
        zero = np.isclose(sigma, 0.0, rtol=0.0, atol=1e-12)
        if np.any(zero & (target != 0.0)):
            raise WindInputError(f"{box.source or 'HAWC box'}: ScaleMethod = 2, but component(s) "
                                 f"{[c for c, z in zip('uvw', zero) if z]} are constant at the grid's centre "
                                 "point: no scaling reaches a non-zero SigmaF. Use ScaleMethod 1 or 0.")
        factors = np.where(zero, 0.0, target / np.where(zero, 1.0, sigma))
    for c in range(3):
        grid[..., c] = (factors[c] * grid[..., c].astype(np.float64)).astype(np.float32)


def write_hawc(root, field: FullFieldWind) -> tuple[Path, Path, Path]:
    """Write ``field``'s grid as HAWC files ``<root>-u.bin``, ``-v.bin``, ``-w.bin`` (the layout above, the grid's
    values as they are: a field read with :func:`read_hawc` and ``ScaleMethod = 0`` has them back).

    Returns
    -------
    tuple of Path
        The three files.
    """
    if not isinstance(field, FullFieldWind):
        raise TypeError(f"field must be a FullFieldWind; got {type(field).__name__}.")
    out = []
    for c, comp in enumerate("uvw"):
        path = Path(f"{root}-{comp}.bin")
        data = np.swapaxes(field.grid[..., c], 1, 2)[:, ::-1, :]          # (nx, ny reversed, nz)
        path.write_bytes(np.ascontiguousarray(data, dtype="<f4").tobytes())
        out.append(path)
    return tuple(out)
