"""Former location of the turbine template, kept so that ``from mbsym.wind.turbine import TurbineModel`` works.

The template lives in :mod:`mbsym.wind.structure.turbine`; import it as
``from mbsym.wind import TurbineModel``.
"""

from .structure.turbine import *  # noqa: F401,F403
from .structure.turbine import __all__  # noqa: F401
