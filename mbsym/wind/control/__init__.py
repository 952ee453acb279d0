"""Controllers of wind turbines: DISCON libraries in the loop and our ROSCO-scheme baseline.

- :mod:`.swap`: the Bladed swap-array record map;
- :mod:`.discon`: :class:`DisconController`, any ``DISCON`` library through ctypes.
"""

from .discon import REQUIRED_MEASUREMENTS, DisconController

__all__ = ["DisconController", "REQUIRED_MEASUREMENTS"]
