"""Shared pytest configuration: the deterministic hypothesis profile used in CI."""

from hypothesis import settings

# Deterministic and quick: building CasADi graphs is costly, so few examples, no deadline.
settings.register_profile("ci", derandomize=True, database=None, deadline=None, max_examples=12)
settings.load_profile("ci")
