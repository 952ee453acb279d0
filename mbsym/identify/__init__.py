"""Parameter identification: least-squares fits of model parameters to measured time series.

:func:`identify` fits chosen parameters (and optionally initial states) of any model
:func:`mbsym.as_dynamics` accepts to one or several records, by multiple shooting on
the measurement grid with Gauss–Newton and exact Jacobians, and returns estimates,
standard errors, correlations and the fit error per channel. This layer is general:
it knows models only through their named :class:`~mbsym.Dynamics` (and the optional
``resolve_parameter(key)`` hook by which a model maps its own keys, e.g. ElastoDyn's,
to parameter names).
"""

from .api import METHODS, Parameter, identify
from .data import Record, read_csv
from .result import IdentificationResult
from .shooting import choose_substeps

__all__ = ["identify", "Parameter", "IdentificationResult", "Record", "read_csv", "choose_substeps", "METHODS"]
