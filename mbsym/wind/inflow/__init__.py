"""Wind inputs: hub-height wind speed signals for simulations and OpenFAST wind files.

- :mod:`.signals`: :class:`SteadyWind`, :class:`StepWind`, :class:`RampWind`, the IEC
  :class:`ExtremeOperatingGust`, :class:`TabulatedWind` — all :class:`WindSignal`\\ s:
  numpy-evaluable (``wind(t)``), tabulated (``wind.table(t_end)``) and CasADi
  (``wind.to_casadi()``), usable as :func:`mbsym.simulate` inputs;
- :mod:`.kaimal`: reproducible turbulent series with the IEC Kaimal spectrum;
- :mod:`.files`: OpenFAST InflowWind uniform wind files (``.hh``) and
  ``Time_[s],Wind1VelX_[m/s]`` CSV, read and written;
- :mod:`.spec`: the command line's ``--wind SPEC`` strings;
- :mod:`.field`, :mod:`.turbsim`, :mod:`.uniform`: spatial wind as OpenFAST's InflowWind evaluates it:
  :class:`FullFieldWind` (TurbSim ``.bts`` grids, :func:`read_turbsim_bts`; HAWC boxes, :func:`read_hawc`, and
  native Bladed boxes, :func:`read_bladed_native`, with the :class:`MeanProfile` InflowWind adds after
  interpolation; TurbSim's Bladed-style boxes, :func:`read_bladed_wnd`; a CasADi External through
  :meth:`FullFieldWind.casadi_function`) and :class:`UniformFieldWind` (steady and uniform-file wind,
  :func:`uniform_velocity_expr` in CasADi);
- :mod:`.rotor`: :func:`rotor_effective_wind`, disk averages and linear shears of a field (docs/inflow.md);
- :mod:`.lidar`: :class:`PointLidar`, InflowWind's single-point lidar (speeds at focal points upstream);
- :mod:`.cubic`, :mod:`.cubic_signal`: InflowWind's ``VelInterpCubic`` (cubic in time; ``cubic=True`` of the fields,
  :class:`HermiteTableWind` and :class:`CubicUniformHubWind` hub signals).

Example
-------
>>> from mbsym.wind.inflow import parse_wind_spec
>>> wind = parse_wind_spec("steady:12")
>>> grid, values = wind.table(60.0)   # or inputs={"wind": wind} in mbsym.simulate
>>> float(values[0])
12.0
"""

from .field import GRID_TOLERANCE, FullFieldWind, rotation_to_wind
from .files import (UNIFORM_COLUMNS, UniformWind, read_uniform_wind, read_wind_csv, write_uniform_wind,
                    write_wind_csv)
from .kaimal import IEC_LENGTH_SCALE, KaimalWind, kaimal_spectrum, kaimal_wind
from .signals import (ExtremeOperatingGust, RampWind, SteadyWind, StepWind, TabulatedWind, WindSignal,
                      iec_gust_speed)
from .spec import WIND_SPEC_FORMS, parse_wind_spec
from .uniform import COLUMN_NAMES, POWER_LAW_MIN_HEIGHT, UniformFieldWind, uniform_velocity_expr
from .rotor import DEFAULT_REFERENCE, disk_points, rotor_effective_wind
from .turbsim import TURBSIM_FILE_IDS, read_turbsim_bts, write_turbsim_bts
from .profile import MeanProfile
from .hawc import HawcBox, read_hawc, write_hawc
from .bladed import read_bladed_native, read_bladed_wnd
from .lidar import LIDAR_RECORD_START, PointLidar, lidar_records
from .cubic_signal import CubicUniformHubWind, HermiteTableWind

__all__ = [
    "WindSignal", "SteadyWind", "StepWind", "RampWind", "ExtremeOperatingGust", "TabulatedWind", "iec_gust_speed",
    "KaimalWind", "kaimal_wind", "kaimal_spectrum", "IEC_LENGTH_SCALE",
    "UniformWind", "read_uniform_wind", "write_uniform_wind", "read_wind_csv", "write_wind_csv", "UNIFORM_COLUMNS",
    "parse_wind_spec", "WIND_SPEC_FORMS",
    "FullFieldWind", "rotation_to_wind", "GRID_TOLERANCE", "read_turbsim_bts", "write_turbsim_bts", "TURBSIM_FILE_IDS",
    "MeanProfile", "HawcBox", "read_hawc", "write_hawc", "read_bladed_wnd", "read_bladed_native",
    "UniformFieldWind", "uniform_velocity_expr", "COLUMN_NAMES", "POWER_LAW_MIN_HEIGHT",
    "rotor_effective_wind", "disk_points", "DEFAULT_REFERENCE",
    "PointLidar", "LIDAR_RECORD_START", "lidar_records",
    "HermiteTableWind", "CubicUniformHubWind",
]
