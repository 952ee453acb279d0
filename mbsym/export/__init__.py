"""Export a model's equations: standalone C, a numpy-only Python module, LaTeX.

- :func:`export_c` (CasADi's code generator): ``<name>.c``, ``<name>.h`` and a
  minimal ``main.c``;
- :func:`export_python`: a module of plain Python generated from the SX
  algorithms, called like ``eom.functions``;
- :func:`latex`: the mass matrix and forcing of a small model as LaTeX.

The same functions are exported to C and Python (:mod:`mbsym.export.functions`).
"""

from .c import ExportedC, export_c
from .functions import FUNCTION_NAMES
from .latex import latex, latex_entries, latex_name
from .python import export_python, python_source

__all__ = ["FUNCTION_NAMES", "export_python", "python_source", "export_c", "ExportedC", "latex", "latex_entries",
           "latex_name"]
