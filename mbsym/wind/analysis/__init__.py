"""Analyses of turbine models: multi-blade coordinates, Campbell diagrams, fidelity ladder, comparison with OpenFAST.

Imports :mod:`mbsym.wind.deck`, :mod:`mbsym.wind.structure` and the general layers.
"""
