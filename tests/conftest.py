"""Shared pytest configuration: the deterministic hypothesis profile used in CI, the time limit of slow tests, and
a summary of what was skipped and why (missing reference data, ROSCO wheel, compiler)."""

from collections import Counter
from pathlib import Path

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


#: Where the tests look for the shared reference data (``../shared`` beside the repository).
SHARED = Path(__file__).resolve().parents[1].parent / "shared"
#: Skip reasons grouped by what is missing: (words in the reason, what it is and how to get it).
SKIP_CAUSES = (
    (("shared",), f"the shared OpenFAST/TurbSim reference data (looked for {SHARED}; put the ../shared folder "
                  "beside the repository, see README 'What the tests need from their environment')"),
    (("rosco",), "the ROSCO 2.10.6 wheel (fetched once with 'pip download --no-deps rosco==2.10.6' into "
                 "~/.cache/mbsym/rosco or $MBSYM_ROSCO_DIR: needs registry access)"),
    (("compiler", "gcc"), "a C compiler (gcc or cc on the PATH, or $MBSYM_CC)"),
)


def skip_cause(reason: str) -> str:
    """The cause of a skip (:data:`SKIP_CAUSES`), or ``"other"``."""
    text = reason.lower()
    for words, cause in SKIP_CAUSES:
        if any(w in text for w in words):
            return cause
    return "other"


def pytest_terminal_summary(terminalreporter, exitstatus, config):  # noqa: ARG001 - pytest hook
    """Say how many tests were skipped for want of what, and how to provide it (never silent)."""
    skipped = terminalreporter.stats.get("skipped", [])
    causes = Counter()
    for report in skipped:
        longrepr = getattr(report, "longrepr", None)
        reason = longrepr[2] if isinstance(longrepr, tuple) and len(longrepr) == 3 else str(longrepr)
        causes[skip_cause(reason)] += 1
    if not causes:
        return
    terminalreporter.section("skipped tests, by what they need")
    for cause, n in causes.most_common():
        what = "other reasons (pytest -rs lists them)" if cause == "other" else cause
        terminalreporter.write_line(f"{n:5d} skipped: {what}")
