"""Shared test settings: locate the reference data shipped in data/; mark each test with its tier.

Tiers are the folders: ``unit``, ``contract`` (every registered wall model through the same
checks), ``regression`` (stored short series compared tightly), ``physics`` (short runs against
measured references). ``-m regression`` etc. selects one; ``slow`` marks the long runs left out
of the default tier (pyproject.toml), ``-m slow`` runs them.
"""

import os

# The suite compiles seawall's particle loops serially (seawall.jit): about a third of the
# threaded build's cold compile. tests/unit/test_jit.py runs the threaded build against it.
# Set here, before any test imports seawall; SEAWALL_LOOPS=threaded runs the suite threaded.
os.environ.setdefault("SEAWALL_LOOPS", "serial")
# No compile helper (seawall.compile_ahead): the suite's two worker processes fill both cores
# already; tests/unit/test_compile_ahead.py turns it on where it tests it.
os.environ.setdefault("SEAWALL_COMPILE_AHEAD", "0")

import pytest  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(REPO, "data")
TIERS = ("unit", "contract", "regression", "physics")


def pytest_configure(config):
    for tier in TIERS:
        config.addinivalue_line("markers", f"{tier}: tests under tests/{tier}/")


def pytest_collection_modifyitems(config, items):
    for item in items:
        parts = os.path.relpath(str(item.path), os.path.dirname(__file__)).split(os.sep)
        if parts[0] in TIERS:
            item.add_marker(parts[0])


@pytest.fixture
def data_dir():
    return DATA
