"""Error messages of the model that no other test triggers: each is raised by the call a
user could make and checked by its text (the key or value, and what was expected)."""

import re

import numpy as np
import pytest

from model import prestretch as pre
from model.materials import NeoHookean
from model.backbone import linear_mode
from model.free import FreeRom
from model.codim2 import continue_curve
from model.forced import ForcedMap
from model.integrate import lockstep_table
from model.params import Loading, Membrane
from model.response import stepped_sweep
from model.rom import build_rom


@pytest.fixture(scope="module")
def ps():
    return pre.solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "analytic")


@pytest.fixture(scope="module")
def fmap(ps):
    return ForcedMap.from_loading(build_rom(ps, [(1, 0)]), Loading(Omega=30.0, P0=1.0, c=0.05))


def test_a_rom_without_modes(ps):
    with pytest.raises(ValueError, match=re.escape("modes = [] is invalid: give at least one (m, n) pair")):
        build_rom(ps, [])


def test_a_probe_outside_the_annulus(ps):
    with pytest.raises(ValueError, match=re.escape("probe_rho = 1.5 is invalid: must lie in (Ro, Re) = (0.2, 1.0) m")):
        build_rom(ps, [(1, 0)], probe_rho=1.5)


def test_a_batch_of_states_of_the_wrong_shape(fmap):
    with pytest.raises(ValueError, match=re.escape("states shape (3, 4) is invalid: expected (N, 2)")):
        fmap.advance_batch(np.zeros((3, 4)))


def test_a_pre_stretch_whose_collocation_does_not_converge(monkeypatch):
    # No membrane is known where the collocation fails from both seeds (Eq. 21 and the
    # shooting solution): the failure is forced, the shooting itself runs for real.
    monkeypatch.setattr(pre, "_collocate", lambda *args: None)
    with pytest.raises(ArithmeticError, match=re.escape(
            "pre-stretch collocation did not converge at delta = 1.1, delta_o = 0.2")):
        pre._numeric_coef(NeoHookean(), 1.1, 0.2)


def test_a_backbone_of_a_mode_that_vanishes_at_the_probe(ps):
    rom = build_rom(ps, [(1, -1)])  # the sine companion: zero on the ray theta = 0 of the probe
    with pytest.raises(ValueError, match=re.escape(
            "the lowest mode of the ROM of [(1, -1)] (probe at rho = 0.5 m) vanishes at the probe point: its "
            "backbone cannot be measured there")):
        linear_mode(FreeRom(rom))


def test_a_fold_curve_from_a_point_that_is_no_fold(fmap):
    # rest at Omega = 30 rad/s, far from the saddle-nodes of the resonance near 33 rad/s
    with pytest.raises(RuntimeError, match=re.escape("the fold point at c = 0.05 could not be refined")):
        continue_curve(fmap, "Omega", "c", 0.05, 0.1, np.zeros(2), 30.0, 30.0)


def test_a_stepped_sweep_with_an_impossible_criterion(fmap):
    with pytest.raises(ValueError, match=re.escape(
            "(tol, consecutive, min_periods, max_periods) = (0.0, 20, 10, 5) is invalid: need tol > 0, "
            "consecutive >= 1, 1 <= min_periods <= max_periods")):
        stepped_sweep(fmap, "Omega", [30.0], tol=0.0, min_periods=10, max_periods=5)


def test_lock_step_integration_without_a_force_table(ps):
    rom = build_rom(ps, [(1, 0), (2, 0)])
    with pytest.raises(ValueError, match=re.escape(
            "the ROM has no force table: lock-step integration needs a one-mode ROM")):
        lockstep_table(rom.tables)
