"""Shared pytest configuration: the deterministic hypothesis profile used in CI, and the time limit of slow tests."""

import pytest
from hypothesis import settings

# Deterministic and quick: building CasADi graphs is costly, so few examples, no deadline.
settings.register_profile("ci", derandomize=True, database=None, deadline=None, max_examples=12)
settings.load_profile("ci")


#: Time limit of a test marked ``slow`` [s] (pytest-timeout), unless it sets its own with
#: ``@pytest.mark.timeout(seconds)``; other tests have the ``timeout`` of pyproject.toml.
SLOW_TIMEOUT_S = 3600


def pytest_collection_modifyitems(config, items):
    """Give slow tests the longer limit :data:`SLOW_TIMEOUT_S` (only with pytest-timeout installed: ``.[test]``)."""
    if not config.pluginmanager.hasplugin("timeout"):
        return
    for item in items:
        if item.get_closest_marker("slow") is not None and item.get_closest_marker("timeout") is None:
            item.add_marker(pytest.mark.timeout(SLOW_TIMEOUT_S))
