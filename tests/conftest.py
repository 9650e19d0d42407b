"""Test-wide fixtures: the fake analyses of ``fake_analysis.py`` are registered for every
test (``SWEEP_EXTRA_ANALYSES``), as the command line and the runner see them; the Fig. 14a
resonance branch with the n = 1 family, shared by the tests of two-parameter continuation and
branch switching.  Importing :mod:`sweep.threads` first gives the tests one BLAS and numba
thread, as the command line does (a multi-threaded BLAS on a loaded two-core machine is many
times slower on the small matrices of the variational equations)."""

import sweep.threads  # noqa: F401  (before numpy)

from types import SimpleNamespace

import pytest
from jobfiles import EXTRA

from model.continuation import continue_orbits
from model.families import build_family
from model.forced import ForcedMap
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom
from sweep import analyses


@pytest.fixture(autouse=True)
def fake_registered(monkeypatch):
    monkeypatch.setenv(analyses.EXTRA_ENV, EXTRA)


@pytest.fixture(scope="session")
def fig14a_n1():
    """delta = 1.1, delta_o = 0.2, P0 = 1 Pa, c = 0.05 N s/m^3, one mode: the branch in Omega
    from 25 to 55 rad/s with the n = 1 family (radial modes 1..2); fields ``prestretch``,
    ``rom``, ``family``, ``fmap`` (at Omega = 25) and ``branch``."""
    ps = solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric")
    rom = build_rom(ps, [(1, 0)])
    family = build_family(ps, rom, 1, 2)
    fmap = ForcedMap.from_loading(rom, Loading(Omega=25.0, P0=1.0, c=0.05))
    branch = continue_orbits(fmap, "Omega", 25.0, 55.0, ds_max=0.3, max_points=1000, families=[family])
    return SimpleNamespace(prestretch=ps, rom=rom, family=family, fmap=fmap, branch=branch)
