"""Basins of attraction (model/basins.py, sweep/analyses/basins.py) at small sizes.

Reference values: the linear forced response (closed form) for the Newton search, the
Floquet multiplier modulus ``exp(-c T / 2)`` of a linear damped oscillator, and
brute-force long integration for the fast lattice classification.
"""

import math

import numpy as np
import pytest
import xarray as xr

from model import attractors as ma
from model import basin_cells as mc
from model import basins as mb
from model import lattice as ml
from model.forced import ForcedMap
from model.linear import galerkin_frequencies
from model.params import Loading, Membrane
from model.prestretch import solve_prestretch
from model.rom import _force_table, build_rom
from sweep.analyses.base import JobError
from sweep.analyses.basins import BASINS
from sweep.figures.basins import basins_figures
from sweep.jobspec import grid_point

GRID = {k: np.array([v]) for k, v in
        dict(delta=1.1, delta_o=0.2, Omega=33.5, P0=1.0, c=0.05).items()}
MEMBRANE = Membrane()
POINT = grid_point(MEMBRANE, {k: float(v[0]) for k, v in GRID.items()})
C_DAMP = 0.05 / (2200.0 * 1e-3)  # c / (Gamma h), s-1


def _fmap(rom, omega=33.5, p0=1.0, steps=mb.DEFAULT_STEPS):
    """The stroboscopic map at c = 0.05 N s/m^3."""
    return ForcedMap.from_loading(rom, Loading(omega, p0, 0.05), steps)


@pytest.fixture(scope="module")
def rom():
    return build_rom(solve_prestretch(Membrane(1.1, 0.2), "numeric"), [(1, 0)])


def test_newton_finds_the_linear_forced_response(rom):
    """At tiny forcing the periodic orbit is q = A cos(Omega t) + B sin(Omega t)."""
    ps = solve_prestretch(Membrane(1.1, 0.2), "numeric")
    w0 = galerkin_frequencies(ps, 0, 1, basis=1)[0][0]
    p0, om = 1e-4, 33.5
    F = p0 * rom.tables.load[0]
    D = (w0**2 - om**2) ** 2 + (C_DAMP * om) ** 2
    A, B = F * (w0**2 - om**2) / D, F * C_DAMP * om / D
    scale = np.array([1 / 0.6, 1 / 20.0])
    att = ma.find_periodic_orbit(np.zeros(2), 1, _fmap(rom, om, p0, 96), scale, 1e-13)
    assert att is not None and att.period == 1
    np.testing.assert_allclose(att.points[0], [A, B * om], rtol=2e-3)
    np.testing.assert_allclose(np.abs(att.multipliers), math.exp(-C_DAMP * np.pi / om),
                               rtol=1e-6)


def test_one_mode_newton_finds_what_the_quadrature_map_finds(rom):
    """The compiled one-mode search (force table) and the general iteration on the same ROM
    without a table (quadrature force, LAPACK solves) end on the same orbits from the same
    starts: the resonant and non-resonant responses and the saddle of Fig. 19a (period 1),
    no orbit of least period 2 from a period-1 orbit, and the same failures (a start far
    out, whose damped Newton steps cannot reach an orbit in 3 iterations).  With a table of
    1e-6 m the compiled search leaves it at once and the general iteration takes over: the
    quadrature's result exactly.  With a table of 0.10003 m the resonant start leaves it
    at once, the non-resonant one never, and the saddle's start (0.1 m, reaching 0.10007 m
    within the period) in its first period (checked): the table's orbits again."""
    ps = solve_prestretch(Membrane(1.1, 0.2), "numeric")
    table, quadrature = _fmap(rom), _fmap(build_rom(ps, [(1, 0)], force_table=False))
    assert table.rom.tables.table_max > 0.0 and quadrature.rom.tables.table_max == 0.0
    tiny, partial = (ForcedMap(rom.__class__(**{**rom.__dict__, "tables": quadrature.rom.tables._replace(
        **_force_table(quadrature.rom.tables, q_max))}), table.forcing, table.steps) for q_max in (1e-6, 0.10003))
    scale = np.array([1 / 0.6, 1 / 20.0])
    pts, phi = np.empty((2, 2)), np.empty((2, 2))  # the saddle's start leaves the partial table mid-period
    assert not ma._map_power_one_mode(0.1, -0.2, 1, partial.period / partial.steps, partial.steps,
                                      partial.rom.tables, partial.forcing, pts, phi)
    starts = [(np.array([-0.12, -0.3]), 1, 30), (np.array([0.02, 0.0]), 1, 30), (np.array([0.1, -0.2]), 1, 30),
              (np.array([-0.12, -0.3]), 2, 30), (np.array([0.25, 8.0]), 1, 3)]
    found = []
    for y0, k, iterations in starts:
        a = ma.find_periodic_orbit(y0, k, table, scale, 1e-11, max_iter=iterations)
        b = ma.find_periodic_orbit(y0, k, quadrature, scale, 1e-11, max_iter=iterations)
        c = ma.find_periodic_orbit(y0, k, tiny, scale, 1e-11, max_iter=iterations)
        d = ma.find_periodic_orbit(y0, k, partial, scale, 1e-11, max_iter=iterations)
        assert (a is None) == (b is None) == (c is None) == (d is None)
        assert b is None or (np.array_equal(b.points, c.points) and np.array_equal(b.multipliers, c.multipliers))
        if a is not None:
            # the two maps differ by the table's 1e-13: orbits within 1e-9 of the window
            assert np.abs((a.points - b.points) * scale).max() < 1e-9
            assert np.abs((d.points - b.points) * scale).max() < 1e-9
            np.testing.assert_allclose(np.sort(np.abs(a.multipliers)), np.sort(np.abs(b.multipliers)), rtol=1e-8)
            # both searches keep the derivative of P at the converged point (the compiled
            # one's closed-form 2 x 2 products, the general one's matrix products) as the map has it
            for att, fmap in ((a, table), (b, quadrature)):
                np.testing.assert_allclose(att.jacobian, fmap.monodromy(att.points[att.found_at])[1], rtol=1e-10)
            found.append(a)
    assert len(found) == 3 and len({round(float(a.points[0, 0]), 4) for a in found}) == 3
    assert sum(np.max(np.abs(a.multipliers)) > 1.0 for a in found) == 1  # the saddle


def test_one_mode_map_power_derivative_is_the_chain_rule(rom):
    """P^k and its derivative as the compiled one-mode Newton search computes them (the
    monodromy matrices multiplied along the orbit, the latest on the left) against the map
    integrated again (rk4_steps) and central differences of it, k = 1, 2, 3, from a state
    on no orbit (where the order of the product matters).  Central differences of steps
    1e-6 m and 1e-5 m/s: truncation and rounding below 1e-8 of the derivative; the two
    orders of the product differ by far more (checked)."""
    fmap = _fmap(rom)
    h = fmap.period / fmap.steps
    y = np.array([0.05, 1.0])
    steps = [np.array([1e-6, 0.0]), np.array([0.0, 1e-5])]
    for k in (1, 2, 3):
        pts, phi = np.empty((k + 1, 2)), np.empty((2, 2))
        assert ma._map_power_one_mode(y[0], y[1], k, h, fmap.steps, rom.tables, fmap.forcing, pts, phi)
        for j in range(k + 1):
            np.testing.assert_allclose(pts[j], fmap.advance(y, j), rtol=1e-12)
        fd = np.column_stack([(fmap.advance(y + e, k) - fmap.advance(y - e, k)) / (2 * e.sum()) for e in steps])
        assert np.abs(phi - fd).max() <= 1e-6 * np.abs(fd).max()
        if k > 1:  # the other order of the product is far off
            ms = [fmap.monodromy(p)[1] for p in pts[:k]]
            swapped = np.linalg.multi_dot(ms) if k > 2 else ms[0] @ ms[1]
            assert np.abs(swapped - fd).max() > 1e-3 * np.abs(fd).max()


@pytest.mark.parametrize("y0, scale, message", [
    (np.float64(0.1), np.ones(2), r"y0 shape \(\) is invalid: need \(2,\)"),
    (np.zeros(2), np.ones(1), r"scale shape \(1,\) is invalid: need \(2,\)"),
])
def test_newton_search_with_arrays_of_the_wrong_shape_names_them(rom, y0, scale, message):
    # (the compiled one-mode search does not check its indices: a short scale would be read past)
    with pytest.raises(ValueError, match=message):
        ma.find_periodic_orbit(y0, 1, _fmap(rom), scale, 1e-11)


def _converged(atts, rom, lattice, steps=192):
    """The attractors again by Newton at ``steps`` RK4 steps per period."""
    scale = ml.lattice_scale(lattice, 2)
    return [ma.find_periodic_orbit(a.points[0], a.period, _fmap(rom, steps=steps), scale, 1e-11)
            for a in atts]


def test_fast_labels_agree_with_converged_brute_force(rom):
    """The issue's bar: >= 99 % of 400 random lattice points, Fig. 19a case, 50 x 50.

    The reference is brute force (long integration to the capture disc, no cells) at 192
    RK4 steps per period, where the labels are converged (96 and 192 steps agree on 100 %
    of a sample of the 200 x 200 lattice; 48 steps only on 97.75 %), not the fast
    method's own 64 steps.
    """
    lat = ml.Lattice(np.linspace(-0.3, 0.3, 50), np.linspace(-10.0, 10.0, 50))
    states = ml.lattice_states(lat, slice(None), 2)
    labels, atts, _ = mb.classify_lattice(states, lat, _fmap(rom), mb.Settings())
    assert len(atts) == 2 and all(a.period == 1 for a in atts)
    assert np.all(labels >= 0)
    # the lock-step slots (last batch partly empty) and the general per-trajectory loop
    # (no force table) give the same labels
    general = _fmap(rom)
    general = ForcedMap(rom.__class__(**{**rom.__dict__, "tables": rom.tables._replace(table_max=0.0)}),
                        general.forcing, general.steps)
    assert np.array_equal(mb.classify_lattice(states[:300], lat, general, mb.Settings(), atts)[0],
                          mb.classify_lattice(states[:300], lat, _fmap(rom), mb.Settings(), atts)[0])
    sample = np.random.default_rng(0).choice(labels.size, 400, replace=False)
    brute, atts2, periods = mb.classify_lattice(states[sample], lat, _fmap(rom, steps=192), mb.Settings(),
                                                _converged(atts, rom, lat), use_cells=False,
                                                discover=False)
    assert len(atts2) == 2 and np.all(brute >= 0)
    assert periods.mean() > 200  # brute force really integrates the long transient
    assert np.mean(brute == labels[sample]) >= 0.99


@pytest.mark.slow
@pytest.mark.parametrize("delta, omega", [(1.1, 33.5), (1.5, 46.1), (2.0, 47.35)])
def test_fig19_cases_have_two_attractors_and_a_larger_resonant_basin(delta, omega):
    """Fig. 19 (paper section 4.3): two stable period-1 attractors; the resonant one's
    basin covers most of the window (the paper: "most initial conditions lead to the
    large amplitude resonant response").  Window of jobs/fig19-basins.toml, 30 x 30.
    """
    rom = build_rom(solve_prestretch(Membrane(delta, 0.2), "numeric"), [(1, 0)])
    lat = ml.Lattice(np.linspace(-2.0, 2.0, 30), np.linspace(-50.0, 50.0, 30))
    labels, atts, _ = mb.classify_lattice(ml.lattice_states(lat, slice(None), 2), lat,
                                          _fmap(rom, omega), mb.Settings())
    assert [a.period for a in atts] == [1, 1]
    assert all(np.max(np.abs(a.multipliers)) < 1.0 for a in atts)
    assert np.all(labels >= 0)
    amp = [_fmap(rom, omega).amplitude(a.points[0], a.period) for a in atts]
    resonant = int(np.argmax(amp))
    assert np.mean(labels == resonant) > 0.5


def test_a_failed_search_is_not_repeated_from_the_same_state(rom, monkeypatch):
    """A Newton search that finds nothing explains the recurrences near its start: copies
    of one initial state (advanced in lock-step, recurring in the same period) search
    once per recurrence, as the state alone does."""
    lat = ml.Lattice(np.linspace(-0.3, 0.3, 5), np.linspace(-10.0, 10.0, 5))
    calls = []

    def failing(y0, k, *args, **kwargs):
        calls.append(np.array(y0))
        return None

    monkeypatch.setattr(mb, "find_periodic_orbit", failing)
    settings = mb.Settings(max_periods=300, cooldown=50)
    state = np.array([[0.02, 0.0]])  # near the non-resonant attractor: it recurs
    mb.classify_lattice(state, lat, _fmap(rom), settings, use_cells=False)
    alone = len(calls)
    assert alone >= 1
    calls.clear()
    mb.classify_lattice(np.repeat(state, 5, axis=0), lat, _fmap(rom), settings, use_cells=False)
    assert len(calls) == alone


def test_periods_that_leave_the_force_table_are_integrated_again_by_the_caller(rom):
    """A force table of 1e-6 m: every lock-step period leaves it, and the caller integrates
    it again with rk4_steps (the table, then the quadrature), which is then the general
    loop of a ROM without a table (every state here starts and stays beyond 1e-6 m, so the
    table takes no step).  Brute force (capture only) must give exactly the labels and
    periods of that loop applied period by period, here in Python."""
    lat = ml.Lattice(np.linspace(-0.3, 0.3, 50), np.linspace(-10.0, 10.0, 50))
    fmap = _fmap(rom)
    states = ml.lattice_states(lat, slice(None), 2)
    _, atts, _ = mb.classify_lattice(states[:200], lat, fmap, mb.Settings())
    tiny = ForcedMap(rom.__class__(**{**rom.__dict__, "tables": rom.tables._replace(**_force_table(rom.tables,
                                                                                                    1e-6))}),
                     fmap.forcing, fmap.steps)
    general = ForcedMap(rom.__class__(**{**rom.__dict__, "tables": rom.tables._replace(table_max=0.0)}),
                        fmap.forcing, fmap.steps)
    rng = np.random.default_rng(5)
    starts = np.concatenate([a.points[0] + rng.uniform(-1, 1, (12, 2)) * [0.009, 0.3] for a in atts])
    settings = mb.Settings(max_periods=200)
    labels, _, periods = mb.classify_lattice(starts, lat, tiny, settings, atts, use_cells=False, discover=False)
    scale = ml.lattice_scale(lat, 2)
    for i, y in enumerate(starts):
        for nd in range(settings.max_periods + 1):
            near = [a for a, att in enumerate(atts)
                    if any(np.sum(((y - p) * scale) ** 2) < settings.radius**2 for p in att.points)]
            if near or nd == settings.max_periods:
                break
            y = general.advance(y)
        assert (labels[i], periods[i]) == (near[0] if near else mb.UNCLASSIFIED, nd)
    assert np.any(labels >= 0) and np.any(periods > 0)


def test_unreached_attractor_gives_label_minus_one(rom):
    lat = ml.Lattice(np.linspace(-0.2, 0.2, 3), np.linspace(-6.7, 6.7, 3))
    states = ml.lattice_states(lat, slice(None), 2)
    labels, atts, periods = mb.classify_lattice(states, lat, _fmap(rom), mb.Settings(max_periods=5),
                                                use_cells=False, discover=False)
    assert atts == [] and np.all(labels == mb.UNCLASSIFIED) and np.all(periods == 5)


def _state_cells(n_state, entries, resolution=10.0):
    return mc.StateCells(np.zeros((entries, n_state), np.int16), np.full(entries, mc.EMPTY_CELL, np.int8),
                          np.full(n_state, resolution), np.zeros(1, np.int64), 3 * entries // 4)


def test_state_cells_one_entry_per_cell_until_full():
    """The hash table of the state-space cell map: a state finds the entry of its cell,
    states of distinct cells (many more than the table's slots would hold without
    collisions) get distinct entries, and a full table adds nothing (-1)."""
    sc = _state_cells(4, 64)
    rng = np.random.default_rng(3)
    cells = rng.integers(-40, 40, size=(48, 4))
    cells = cells[np.unique(cells, axis=0, return_index=True)[1]][:40]
    states = (cells + 0.5) / 10.0
    entries = [mc.state_cell(y, sc) for y in states]
    assert len(set(entries)) == len(entries) == sc.count[0] == 40
    assert [mc.state_cell(y + 0.04, sc) for y in states] == entries  # same cells
    np.testing.assert_array_equal(sc.keys[entries], cells)
    more = (rng.integers(100, 200, size=(20, 4)) + 0.5) / 10.0
    added = [mc.state_cell(y, sc) for y in more]
    assert sc.count[0] == sc.limit == 48 and added[8:] == [-1] * 12
    assert [mc.state_cell(y, sc) for y in states] == entries  # still found once full
    assert mc.state_cell(np.array([1e4, 0.0, 0.0, 0.0]), sc) == -1  # beyond the int16 range


def test_state_space_cells_keep_the_labels_and_save_periods():
    """Two modes: the fast method (state-space cells, default settings) labels a lattice
    like brute force of the same map (cells off, same attractors) and integrates fewer
    periods (regression bound 0.8; 0.56 of brute force's periods when written)."""
    rom2 = build_rom(solve_prestretch(Membrane(1.1, 0.2), "analytic"), [(1, 0), (2, 0)])
    fmap = _fmap(rom2, steps=128)
    lat = ml.Lattice(np.linspace(-0.3, 0.3, 7), np.linspace(-10.0, 10.0, 7), 0, 2)
    states = ml.lattice_states(lat, slice(None), 4)
    labels, atts, periods = mb.classify_lattice(states, lat, fmap, mb.default_settings(2))
    brute, _, brute_periods = mb.classify_lattice(states, lat, fmap, mb.Settings(), atts, use_cells=False,
                                                  discover=False)
    assert len(atts) == 2 and np.all(brute >= 0)
    np.testing.assert_array_equal(labels, brute)
    assert periods.sum() < 0.8 * brute_periods.sum()


def _raw(options, subtasks):
    """The runner's raw Dataset from compute() results (dims grid, subtask, ...)."""
    variables = BASINS.variables(options)
    results = [BASINS.compute(POINT, options, s) for s in subtasks]
    order = np.argsort(subtasks)
    data = {}
    for v in variables:
        arr = np.stack([results[i][v.name] for i in order])
        data[v.name] = ((*GRID, "subtask", *v.dims), arr.reshape((1,) * 5 + arr.shape))
    status = np.array([results[i]["status"] for i in order], np.int8)
    data["status"] = ((*GRID, "subtask"), status.reshape((1,) * 5 + status.shape))
    return xr.Dataset(data, coords={k: v for k, v in GRID.items()})


def test_assemble_merges_tiles_whatever_their_order(tmp_path):
    table = {"ic_x": {"start": -0.2, "stop": 0.2, "num": 12},
             "ic_y": {"start": -6.7, "stop": 6.7, "num": 10}, "tiles": 3}
    options = BASINS.parse_options(table, GRID, MEMBRANE)
    assert BASINS.n_subtasks(options) == 3
    a = BASINS.assemble(_raw(options, [0, 1, 2]), options)
    b = BASINS.assemble(_raw(options, [2, 0, 1]), options)
    xr.testing.assert_identical(a, b)
    lab = a["label"].squeeze().values
    assert lab.shape == (12, 10) and a["n_attractors"].values.item() == 2
    amp = a["attractor_amplitude"].squeeze().values
    assert amp[0] > amp[1] > 0  # attractor 0 is the resonant one
    frac = a["basin_fraction"].squeeze().values
    assert frac[0] > 0.5 and frac[0] + frac[1] == pytest.approx(1.0)
    assert np.all((a["integrity_factor"].squeeze().values[:2] > 0))
    paths = basins_figures(a, tmp_path)
    assert len(paths) == 1 and paths[0].exists()


def test_a_brute_force_sample_labels_its_points_as_the_whole_lattice_does():
    # sample = 25 of a 12 x 10 lattice, brute force, 3 tiles: the sampled points carry the
    # labels of a brute-force run of the whole lattice (the attractors merged across tiles
    # and numbered the same way), the others -2; the fractions are over the sample and the
    # integrity factor, which needs the whole lattice, is NaN.
    table = {"ic_x": {"start": -0.2, "stop": 0.2, "num": 12},
             "ic_y": {"start": -6.7, "stop": 6.7, "num": 10}, "tiles": 3, "method": "brute"}
    whole = BASINS.assemble(_raw(BASINS.parse_options(table, GRID, MEMBRANE), [0, 1, 2]),
                            BASINS.parse_options(table, GRID, MEMBRANE)).squeeze()
    options = BASINS.parse_options({**table, "sample": 25}, GRID, MEMBRANE)
    part = BASINS.assemble(_raw(options, [0, 1, 2]), options).squeeze()
    lab, ref = part.label.values, whole.label.values
    chosen = lab != -2
    assert chosen.sum() == 25 and (lab[chosen] >= 0).all()
    np.testing.assert_array_equal(lab[chosen], ref[chosen])
    assert len(set(lab[chosen])) == 2  # both attractors are in the sample
    frac = part.basin_fraction.values[:2]
    assert frac.sum() == pytest.approx(1.0) and frac[0] == pytest.approx(np.mean(lab[chosen] == 0))
    assert np.isnan(part.integrity_factor.values).all()
    # the same points whatever the tiling
    one = BASINS.parse_options({**table, "sample": 25, "tiles": 1}, GRID, MEMBRANE)
    np.testing.assert_array_equal(BASINS.assemble(_raw(one, [0]), one).squeeze().label.values != -2, chosen)


def test_a_perturbation_scales_the_initial_states_the_classifier_gets(monkeypatch):
    # the states handed to the classifier are the lattice's times 1 + perturbation
    import sweep.analyses.basins as analysis

    seen = []

    def classify(states, *args, report, **kwargs):
        seen.append(np.array(states))
        report["state_cells"] = 0
        return np.zeros(len(states), np.int32), [], np.zeros(len(states), np.int32)

    monkeypatch.setattr(analysis.mb, "classify_lattice", classify)
    table = {"ic_x": {"start": -0.2, "stop": 0.2, "num": 3}, "ic_y": {"start": -6.0, "stop": 6.0, "num": 3},
             "tiles": 1}
    for eps in (0.0, 1e-6):
        BASINS.compute(POINT, BASINS.parse_options({**table, "perturbation": eps}, GRID, MEMBRANE), 0)
    lattice = BASINS.parse_options(table, GRID, MEMBRANE).lattice()
    np.testing.assert_array_equal(seen[0], ml.lattice_states(lattice, slice(None), 2))
    np.testing.assert_array_equal(seen[1], seen[0] * (1.0 + 1e-6))


@pytest.mark.parametrize("table, message", [
    ({"method": "slow"}, "basins.method = 'slow' is invalid: must be one of fast, brute"),
    ({"sample": 10}, 'basins.sample = 10 is invalid: needs method = "brute"'),
    ({"sample": 10_001, "method": "brute"}, "basins.sample = 10001 is invalid: must be <= 10000"),
    ({"ic_x": {"start": 1.0, "stop": 0.0, "num": 5}}, "basins.ic_x = {'start': 1.0, "
     "'stop': 0.0, 'num': 5} is invalid: needs stop > start and num >= 2"),
    ({"ic_y": {"start": 0.0, "stop": 1.0, "num": 1}}, "needs stop > start and num >= 2"),
    ({"radius": 0.0}, "basins.radius = 0.0 is invalid: must be > 0.0"),
    ({"lattice_mode": 2}, "basins.lattice_mode = 2 is invalid: must be <= 1"),
    ({"colour": 1}, "basins.colour = 1 is invalid: unknown key"),
    ({"perturbation": -1e-12}, "basins.perturbation = -1e-12 is invalid: must be >= 0.0"),
    ({"perturbation": 0.1}, "basins.perturbation = 0.1 is invalid: must be <= 0.01"),
])
def test_bad_options_are_rejected_with_a_message(table, message):
    with pytest.raises(JobError) as err:
        BASINS.parse_options(table, GRID, MEMBRANE)
    assert message in str(err.value)


def test_merge_attractors_identifies_tiles_attractors_and_orders_by_amplitude():
    scale = np.array([1.0, 1.0])
    small = ma.Attractor(np.array([[0.01, 0.0]]), np.array([0.9]))
    big = ma.Attractor(np.array([[0.2, 0.5]]), np.array([0.9]))
    big_again = ma.Attractor(np.array([[0.2 + 1e-4, 0.5]]), np.array([0.9]))
    two = ma.Attractor(np.array([[0.1, 0.1], [-0.1, -0.1]]), np.array([0.5]))
    one_at_two_points = ma.Attractor(np.array([[0.1, 0.1]]), np.array([0.5]))
    tiles = [[(small, 0.01), (big, 0.07)], [(big_again, 0.07), (two, 0.03)], [(one_at_two_points, 0.02)], []]
    merged, index = ma.merge_attractors(tiles, scale, 1e-3)
    assert [a for _, a in merged] == [0.07, 0.03, 0.02, 0.01]
    assert merged[0][0] is big  # the first finder's points
    assert [list(i) for i in index] == [[3, 0], [0, 1], [2], []]


def test_large_lattices_are_tiled_and_bounded():
    big = {"ic_x": {"start": -0.3, "stop": 0.3, "num": 4096}, "ic_y": {"start": -10.0, "stop": 10.0, "num": 4096}}
    options = BASINS.parse_options(big, GRID, MEMBRANE)
    assert options.tiles == 256 and options.rows * 4096 <= 65_536
    with pytest.raises(JobError, match=r"basins.ic_x.num = 100000 is invalid: must be <= 4096"):
        BASINS.parse_options({"ic_x": {"start": -0.3, "stop": 0.3, "num": 100_000}}, GRID, MEMBRANE)


def test_two_modes_use_the_lean_rule_and_check_it_on_the_attractors():
    """Basins of a two-mode ROM: the fast method records a radial rule below the default
    one and, its attractors checked, status ok; brute force keeps the default rule."""
    from model.rom import default_quadrature

    table = {"modes": [[1, 0], [2, 0]], "ic_x": {"start": -0.3, "stop": 0.3, "num": 4},
             "ic_y": {"start": -10.0, "stop": 10.0, "num": 3}, "tiles": 1, "steps": 64}
    full = default_quadrature([(1, 0), (2, 0)])[0]
    for method, expected in (("fast", "lean"), ("brute", full)):
        options = BASINS.parse_options({**table, "method": method}, GRID, MEMBRANE)
        out = BASINS.compute(POINT, options, 0)
        assert out["status"] == 0 and np.all(out["tile_label"][:4] >= 0)
        points = int(out["tile_radial_points"])
        assert points < full if expected == "lean" else points == full


def test_a_full_state_cell_map_is_reported_and_changes_no_label(monkeypatch):
    """A state-space cell map too small for the tile fills up: the tile records its cell
    count at the limit, keeps status ok, and labels every initial condition as with room
    to spare (a full map only stops adding cells)."""
    table = {"modes": [[1, 0], [2, 0]], "ic_x": {"start": -0.3, "stop": 0.3, "num": 4},
             "ic_y": {"start": -10.0, "stop": 10.0, "num": 3}, "tiles": 1, "steps": 64}
    options = BASINS.parse_options(table, GRID, MEMBRANE)
    roomy = BASINS.compute(POINT, options, 0)
    assert 0 < roomy["tile_state_cells"] < mc.state_cell_limit()
    monkeypatch.setattr(mc, "STATE_CELL_CAPACITY", 64)
    cramped = BASINS.compute(POINT, options, 0)
    assert cramped["status"] == 0 and cramped["tile_state_cells"] == mc.state_cell_limit() == 48
    assert np.array_equal(cramped["tile_label"], roomy["tile_label"])
