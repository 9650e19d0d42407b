"""Test-wide fixtures: the fake analyses of ``fake_analysis.py`` are registered for every
test (``SWEEP_EXTRA_ANALYSES``), as the command line and the runner see them."""

import pytest
from jobfiles import EXTRA

from sweep import analyses


@pytest.fixture(autouse=True)
def fake_registered(monkeypatch):
    monkeypatch.setenv(analyses.EXTRA_ENV, EXTRA)
