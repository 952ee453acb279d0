"""Controllers of wind turbines: DISCON libraries in the loop and our ROSCO-scheme baseline.

- :mod:`.swap`: the Bladed swap-array record map;
- :mod:`.discon`: :class:`DisconController`, any ``DISCON`` library through ctypes;
- :mod:`.settings`: :class:`BaselineSettings` and the mapping from ROSCO's ``DISCON.IN``;
- :mod:`.baseline`: :class:`BaselineController`, the ROSCO scheme as a discrete-time CasADi Function;
- :mod:`.ipc`: its individual pitch control (ROSCO's ``IPC_ControlMode`` 1 and 2);
- :mod:`.estimator`, :mod:`.tower`, :mod:`.power_reference`: its wind-speed estimator, its floating feedback and
  tower damper (``Fl_Mode``, ``TD_Mode``), its power reference (``PRC_Mode`` 1 and 2);
- :mod:`.shutdown`, :mod:`.startup`: its shut-down (``SD_Mode 1``) and start-up (``SU_Mode 1``);
- :mod:`.tuning`: ROSCO's tuning (:func:`tune_rosco`) and :func:`pi_gains`;
- :mod:`.discon_export`: :func:`export_discon`, the baseline compiled into a self-contained DISCON library;
- :mod:`.discon_write`: :func:`write_discon_in`, settings written out as ROSCO's ``DISCON.IN`` for its library;
- :mod:`.linear`: :func:`linearize_controller`, the baseline about its fixed point at a trim (a discrete linear model).
"""

from .baseline import COMMANDS, IPC_COMMANDS, IPC_MEASUREMENTS, MEASUREMENTS, BaselineController
from .discon import REQUIRED_MEASUREMENTS, DisconController
from .discon_export import export_discon
from .discon_write import write_discon_in
from .linear import LinearizedController, controller_fixed_point, linearize_controller
from .settings import DISCON_MAP, IPC_MAP, BaselineSettings
from .tuning import RoscoTuning, pi_gains, tune_rosco

__all__ = ["DisconController", "REQUIRED_MEASUREMENTS", "BaselineController", "BaselineSettings", "DISCON_MAP",
           "MEASUREMENTS", "COMMANDS", "IPC_MEASUREMENTS", "IPC_COMMANDS", "IPC_MAP", "tune_rosco", "pi_gains",
           "RoscoTuning", "export_discon", "write_discon_in", "LinearizedController", "controller_fixed_point",
           "linearize_controller"]
