"""The ElastoDyn-equivalent structure of a turbine.

ElastoDyn's analysis nodes and mass integrals (:mod:`.elastodyn_nodes`), the tower and
blade shape integrals (:mod:`.elastodyn_bodies`), coordinate names (:mod:`.dofs`), the
:class:`~.turbine.TurbineModel` template with its DOF tables (:mod:`.dof_tables`), platform
joint (:mod:`.platform`) and initial blade deflection (:mod:`.initial_conditions`), and its
OpenFAST output channels (:mod:`.channels`). Imports :mod:`mbsym.wind.deck` and the general layers only.
"""
