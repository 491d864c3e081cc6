"""Shared test settings: locate the reference data shipped in data/."""

import os

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(REPO, "data")


@pytest.fixture
def data_dir():
    return DATA
