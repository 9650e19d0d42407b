"""The Fig. 14a resonance with two axisymmetric modes loses its half-period symmetry.

The ROM is odd in q, so the response to P0 cos(Omega t) can be symmetric in time,
q(t + T/2) = -q(t); its monodromy matrix is then the square of the half-period map
H(y) = -P_{T/2}(y), and a real multiplier of H through -1 is a real multiplier of the
monodromy through +1 without a fold: a branch point of the axisymmetric block, where
responses without that symmetry bifurcate (docs/model.md, "Bifurcation test functions").
With the modes (1,0), (2,0) at the paper's damping the resonant branch of Fig. 14a passes
one on its way up.  Checked: the located point has a multiplier +1 and stability changes
across it; beyond it, the Floquet multiplier against the growth of a perturbation
integrated by scipy's DOP853 on a plain numpy right-hand side (an independent integrator
and force), and the half-period map's derivative by central differences of that
integration, whose eigenvalue -sqrt(mu) says the growing perturbation breaks the symmetry.
Switching at the point (model.switching.follow_time_symmetry_breaking) gives the responses
without the symmetry: DOP853 finds one periodic, not symmetric, and attracting, and its image
under the symmetry is a response too.
"""

import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp

from plain_rom import plain_rhs
from model.continuation import BRANCH_POINT, continue_orbits, unstable_intervals
from model.damping import Viscous
from model.families import build_family
from model.forced import ForcedMap, steps_per_period
from model.params import Membrane
from model.prestretch import solve_prestretch
from model.rom import build_rom
from model.switching import follow_time_symmetry_breaking
from sweep import cli

#: Where the branch is followed to (rad/s): past the branch point, on the resonant stretch
#: (its upper saddle-node with these modes lies near 45.8 rad/s).
TOP = 42.0


@pytest.fixture(scope="module")
def branch():
    rom = build_rom(solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric"), [(1, 0), (2, 0)])
    fmap = ForcedMap.build(rom, 1.0, 25.0, Viscous(0.05), steps_per_period(rom, 128))
    br = continue_orbits(fmap, "Omega", 25.0, TOP, ds_max=0.3, max_points=400)
    assert br.complete
    return rom, fmap, br


def test_the_axisymmetric_branch_point_is_located_where_a_multiplier_is_plus_one(branch):
    _, _, br = branch
    points = np.flatnonzero((br.kind == BRANCH_POINT) & (br.family == 0))
    assert points.size == 1
    i = int(points[0])
    # a multiplier +1 there: far closer to it than at the points that bracket the crossing
    # (Illinois narrowed the bracket by three orders of magnitude or more before the
    # correctors failed at the singular point: a regression bound, observed 2e-4)
    distance = [np.min(np.abs(br.multipliers[k] - 1.0)) for k in (i - 1, i, i + 1)]
    assert distance[1] < 1e-3 * min(distance[0], distance[2])
    assert br.stable[i - 1] and not br.stable[i + 1]
    # the unstable interval starts at the located point, a bound though not exactly on the circle
    located = (br.kind > 0) & (br.family == 0)
    modulus = np.abs(br.multipliers).max(axis=1)
    assert unstable_intervals(br.value, modulus, located)[0][0] == br.value[i]
    after = br.multipliers[i + 1]
    outside = after[np.abs(after) > 1.0]
    assert outside.size == 1 and abs(outside[0].imag) < 1e-12 and outside[0].real > 1.0
    # no fold nearby: the branch goes on up in Omega through the point
    assert br.value[i - 1] < br.value[i] < br.value[i + 1]


def _dop853(rom, fmap, Omega):
    """The flow of the forced, damped ROM at ``Omega`` by DOP853 on the plain numpy force."""
    K = rom.dof
    elastic = plain_rhs(rom)
    rate = fmap.forcing.damping_rate
    load = np.concatenate([np.zeros(K), rom.tables.load])

    def f(t, y):
        return elastic(t, y) + np.concatenate([np.zeros(K), -rate * y[K:]]) + np.cos(Omega * t) * load

    def flow(y, duration, **kw):
        return solve_ivp(f, (0.0, duration), y, method="DOP853", rtol=1e-12, atol=1e-15, **kw)

    return flow


def test_beyond_it_a_perturbation_grows_at_the_floquet_rate_and_breaks_the_symmetry(branch):
    rom, fmap, br = branch
    y0 = br.state[-1]
    mu = br.multipliers[-1]
    Omega = br.value[-1]
    assert Omega == pytest.approx(TOP)
    K, T = rom.dof, 2.0 * np.pi / Omega
    flow = _dop853(rom, fmap, Omega)

    # the RK4 orbit is periodic for DOP853 to its discretisation error; take DOP853's point
    y0 = flow(y0, T).y[:, -1]
    # the response is symmetric in time: y(T/2) = -y(0)
    assert np.abs(flow(y0, T / 2).y[:, -1] + y0).max() < 1e-6 * np.abs(y0).max()
    unstable = mu[np.abs(mu) > 1.0]
    assert unstable.size == 1
    growth_floquet = abs(unstable[0])
    # a perturbation of 1e-7 m grows by the largest multiplier per period (the next one,
    # inside the circle or barely out, decays relative to it by (|mu_2| / |mu_1|)^k)
    periods = np.arange(26)
    dy = np.random.default_rng(1).standard_normal(2 * K)
    dy *= 1e-7 / np.abs(dy).max()
    kw = {"t_eval": periods * T}
    deviation = np.abs(flow(y0 + dy, periods[-1] * T, **kw).y - flow(y0, periods[-1] * T, **kw).y).max(axis=0)
    growth = np.exp(np.polyfit(periods[5:], np.log(deviation[5:]), 1)[0])
    assert growth == pytest.approx(growth_floquet, rel=1e-2)
    # the half-period map H(y) = -y(T/2) has the orbit as a fixed point; its derivative's
    # eigenvalues square to the multipliers, and the unstable one is negative: the growing
    # perturbation changes sign under the symmetry, q(t + T/2) = -q(t) is broken
    steps = 1e-6 * np.maximum(np.abs(y0), 1e-3)
    jac = np.column_stack([(flow(y0 - h * e, T / 2).y[:, -1] - flow(y0 + h * e, T / 2).y[:, -1]) / (2 * h)
                           for e, h in zip(np.eye(2 * K), steps)])
    half = np.linalg.eigvals(jac)
    largest = half[np.argmax(np.abs(half))]
    assert abs(largest.imag) < 1e-6 and largest.real < -1.0
    assert largest.real ** 2 == pytest.approx(growth_floquet, rel=1e-4)


def test_the_responses_without_the_symmetry_are_periodic_attracting_and_come_in_pairs(branch):
    rom, fmap, br = branch
    i = int(np.flatnonzero((br.kind == BRANCH_POINT) & (br.family == 0))[0])
    sw = follow_time_symmetry_breaking(fmap, "Omega", 25.0, TOP, br.state[i], br.value[i], ds_max=0.3,
                                       max_points=60)
    # the first regular point past 40 rad/s on the new branch, which the continuation finds stable
    j = int(np.flatnonzero((sw.value > 40.0) & (sw.kind == 0))[0])
    assert sw.stable[j]
    y0, Omega = sw.state[j], sw.value[j]
    K, T = rom.dof, 2.0 * np.pi / Omega
    flow = _dop853(rom, fmap, Omega)
    scale = np.abs(y0).max()
    # periodic for an independent integrator (to RK4's discretisation error of the orbit)
    assert np.abs(flow(y0, T).y[:, -1] - y0).max() < 1e-6 * scale
    # not symmetric in time: the half-period image differs from the state by a finite amount
    image = -flow(y0, T / 2).y[:, -1]
    assert np.abs(image - y0).max() > 1e-2 * scale
    # and that image is a periodic response too (the pair the pitchfork gives)
    assert np.abs(flow(image, T).y[:, -1] - image).max() < 1e-6 * scale
    # attracting: the monodromy of the DOP853 flow (central differences, steps of 1e-6 of the
    # state: errors of order 1e-10 to 1e-8) has every multiplier inside the unit circle and
    # equals the continuation's RK4 monodromy (312 steps per period) to well within 1e-6
    steps = 1e-6 * np.maximum(np.abs(y0), 1e-3)
    jac = np.column_stack([(flow(y0 + h * e, T).y[:, -1] - flow(y0 - h * e, T).y[:, -1]) / (2 * h)
                           for e, h in zip(np.eye(2 * K), steps)])
    mu = np.sort(np.abs(np.linalg.eigvals(jac)))
    assert mu.max() < 1.0
    np.testing.assert_allclose(mu, np.sort(np.abs(sw.multipliers[j])), atol=1e-6)


def test_a_continuation_job_reports_the_branch_without_the_symmetry(tmp_path, branch):
    """``symmetry_breaking`` through the analysis: the ``broken_*`` outputs are the branch the
    model function follows from the job's located point, NaN padded after it."""
    rom, fmap, br = branch
    job = tmp_path / "broken.toml"
    job.write_text(f"""[job]
name = "broken"
analysis = "continuation"

[grid]
delta = [1.1]
delta_o = [0.2]
P0 = [1.0]
c = [0.05]

[continuation]
parameter = "Omega"
start = 25.0
stop = {TOP}
modes = [[1, 0], [2, 0]]
prestretch = "numeric"
ds_max = 0.3
max_points = 400
families = {{n = [1], radial = 2}}
symmetry_breaking = {{max_points = 30}}
""")
    out = tmp_path / "broken.nc"
    assert cli.main(["run", str(job), "-o", str(out)]) == 0
    with xr.open_dataset(out) as ds:
        p = ds.isel(delta=0, delta_o=0, P0=0, c=0)
        assert int(p.status) == 0 and p.sizes["broken_point"] == 30
        n = int(p.n_points)
        kind, fam = p.point_type.values[:n], p.point_family.values[:n]
        i = int(np.flatnonzero((kind == BRANCH_POINT) & (fam == 0))[0])
        assert float(p.broken_Omega[0]) == pytest.approx(float(p.Omega[i]), rel=1e-12)
        # the model function from the branch point of the job's own branch (its states are
        # the section's modal coordinates: the ROM's map state is (q, q'))
        families = (build_family(rom.prestretch, rom, 1, (1, 2)),)
        y = np.concatenate([p.modal_coordinate.values[i], p.modal_velocity.values[i]])
        sw = follow_time_symmetry_breaking(fmap, "Omega", 25.0, TOP, y, float(p.Omega[i]), families=families,
                                           ds_max=0.3, max_points=30)
        m = sw.value.size
        np.testing.assert_allclose(p.broken_Omega.values[:m], sw.value, rtol=1e-9)
        np.testing.assert_allclose(p.broken_modal_coordinate.values[:m], sw.state[:, :2], rtol=1e-7, atol=1e-12)
        np.testing.assert_allclose(p.broken_family_multiplier_modulus.values[:m, 0],
                                   np.abs(sw.family_multipliers[:, 0]).max(axis=1), rtol=1e-7)
        assert np.isnan(p.broken_Omega.values[m:]).all() and (p.broken_point_type.values[m:] == -1).all()
    # the bifurcation diagram draws them too (thin lines)
    assert cli.main(["figures", str(out), "-o", str(tmp_path / "figures")]) == 0
    assert (tmp_path / "figures" / "bifurcation_Omega.png").exists()


def test_the_report_compares_an_omega_sweep_with_both_branches(tmp_path):
    """docs/validation.md's sweep table from small runs of its two jobs: a row per Omega, and
    for two modes the branch point and the stable responses without the symmetry, which the
    sweep's period-one responses are checked against."""
    from sweep import validation

    jobs = Path(__file__).resolve().parents[1] / "jobs" / "validation"
    runs = tmp_path / "validation"
    sets = "[[[1, 0]], [[1, 0], [2, 0]]]"
    sweep = (jobs / "fig14a-bruteforce-axi.toml").read_text()
    sweep = re.sub(r"values = \{.*\}", "values = {start = 40.0, stop = 40.4, num = 2}", sweep)
    sweep = re.sub(r"modes = .*", f"modes = {sets}", sweep)
    sweep = sweep.replace("max_periods = 1500", "max_periods = 60").replace("poincare_points = 200",
                                                                          "poincare_points = 10")
    branches = (jobs / "fig14a-broken-rom.toml").read_text()
    branches = re.sub(r"modes = \[.*?\]\]\]\n", f"modes = {sets}\n", branches, flags=re.S)
    branches = branches.replace("stop = 55.0", f"stop = {TOP}")
    branches = re.sub(r"symmetry_breaking = \{.*\}", "symmetry_breaking = {max_points = 200}", branches)
    for name, text in (("fig14a-bruteforce-axi", sweep), ("fig14a-broken-rom", branches)):
        (tmp_path / f"{name}.toml").write_text(text)
        assert cli.main(["run", str(tmp_path / f"{name}.toml"), "-o", str(runs / f"{name}.nc")]) == 0
    text = "\n".join(validation.section_time_symmetry(tmp_path))
    assert "| 40.0 | " in text and "| 40.4 | " in text
    # one mode: no such point; two: the point of test_the_axisymmetric_branch_point_is_located...
    assert "K = 1: the symmetry breaks" not in text
    assert re.search(r"K = 2: the symmetry breaks at 38\.6\d rad/s", text)
    row = next(line for line in text.splitlines() if line.startswith("| 40.0 | "))
    assert " b 0." in row.split("|")[5]  # K = 2's stable branches at 40 rad/s: one without the symmetry
    # the table against the resolution, from the same branches (the held runs absent)
    assert "| ROM, K = 1 | none | - | - |" in text
    assert re.search(r"\| ROM, K = 2 \| 38\.6\d\d \| no saddle-node up to where it stopped \(the range's end, "
                     r"or the message\) \(last: 42\.000, ", text)
    assert "`jobs/validation/fig14a-broken-viscous-axi-order16.toml`" in text
