"""Material laws (model/materials.py): Mooney-Rivlin and Gent through the pre-stretch, the
linear problem and the ROM, each checked by a computation that does not share its code.

* the pre-stretch: the first variation of the total strain energy, by central differences of
  the law's energy alone, vanishes at the solution (the collocation solves the strong form
  with the law's second derivatives and complex-step Jacobians);
* the linear frequencies: converged in the Galerkin basis, and equal to a finite-difference
  solution of the Sturm-Liouville problem whose coefficients are central differences of the
  law's energy;
* the ROM: forces equal the gradient of its energy and the Jacobian the gradient of the
  forces (central differences), and the undamped, unforced ROM conserves its energy to the
  RK4 error (the drift falls 16-fold when the step halves);
* ``C2 = 0`` reproduces the neo-Hookean law to rounding, ``Jm -> inf`` approaches it.
"""

import numpy as np
import pytest
from scipy.linalg import eigh_tridiagonal
from scipy.special import roots_legendre

from model.damping import Viscous
from model.forced import ForcedMap
from model.integrate import rk4_steps
from model.linear import galerkin_frequencies
from model.materials import invariant_energy
from model.params import Membrane, ParameterError
from model.prestretch import solve_prestretch
from model.rom import build_rom, elastic_force, force_jacobian, force_work, total_energy

#: The laws checked, at constants where their departure from neo-Hookean is visible at
#: delta = 1.5 (C2/C1 = 0.25; Jm = 3: I1 - 3 = 0.5 at the rest state, 0.8-1 in motion).
LAWS = {"mooney-rivlin": dict(law="mooney-rivlin", C2=0.25 * 0.17e6), "gent": dict(law="gent", Jm=3.0)}


def membrane(name, **geometry):
    return Membrane(**{"delta": 1.5, "delta_o": 0.2, **geometry, **LAWS[name]})


def invariants(l1, l2):
    """``I1``, ``I2`` of the incompressible planar state, written out by hand."""
    return l1**2 + l2**2 + 1 / (l1 * l2) ** 2, (l1 * l2) ** 2 + 1 / l1**2 + 1 / l2**2


@pytest.mark.parametrize("name", LAWS)
def test_prestretch_makes_the_strain_energy_stationary(name):
    m = membrane(name)
    law = m.material
    x, w = roots_legendre(200)
    rho = 0.5 * (m.Ro + m.Re) + 0.5 * (m.Re - m.Ro) * x
    w = 0.5 * (m.Re - m.Ro) * w

    def first_variation(radius, slope, k):
        # d/de of int W(r' + e eta', (r + e eta)/rho) rho drho, eta = sin(k pi s), central
        # differences with e = 1e-4 (truncation ~1e-8 of the terms); and the sum of the
        # terms' magnitudes, the scale of a variation that does not cancel
        s = (rho - m.Ro) / (m.Re - m.Ro)
        eta, deta = np.sin(k * np.pi * s), k * np.pi / (m.Re - m.Ro) * np.cos(k * np.pi * s)
        e = 1e-4
        plus = invariant_energy(law, *invariants(slope + e * deta, (radius + e * eta) / rho))
        minus = invariant_energy(law, *invariants(slope - e * deta, (radius - e * eta) / rho))
        terms = (plus - minus) / (2 * e) * rho * w
        return abs(terms.sum()), np.abs(terms).sum()

    for k in (1, 2, 5):
        ps = solve_prestretch(m, "numeric")
        var, scale = first_variation(ps.radius(rho), ps.slope(rho), k)
        assert var < 1e-6 * scale  # 100 times the central differences' truncation
        # the linearised (Eq. 21) radius is not in equilibrium at delta = 1.5: the check can fail
        lin = solve_prestretch(m, "analytic")
        var_lin, scale_lin = first_variation(lin.radius(rho), lin.slope(rho), k)
        assert var_lin > 1e-4 * scale_lin


def sturm_liouville_frequencies(m, n, count, points):
    """omega (rad/s) of ``-(rho A1 phi')' + n^2 rho A3 phi = lam rho phi``, ``phi = 0`` at both
    edges, by second-order finite differences on ``points`` intervals; ``A1 = dW/d(w_rho^2)``
    and ``A3 = dW/d(w_theta^2)`` at the pre-stretch by central differences of the law's
    energy (docs/model.md, "Transverse energy": the metric ``T``, ``Delta`` written out)."""
    ps = solve_prestretch(m, "numeric")
    law = m.material
    h = (m.Re - m.Ro) / points
    nodes = m.Ro + h * np.arange(points + 1)
    mid = 0.5 * (nodes[1:] + nodes[:-1])

    def coefficient(rho, radial):
        l1, l2 = ps.slope(rho), ps.radius(rho) / rho
        e = 1e-5

        def energy(s):  # s = w_rho^2 (radial) or w_theta^2 / rho^2
            T = l1**2 + l2**2 + s
            D = (l1 * l2) ** 2 + (l2**2 if radial else l1**2) * s
            return invariant_energy(law, T + 1 / D, D + T / D)
        return (energy(e) - energy(-e)) / (2 * e) / (1.0 if radial else rho**2)

    p = mid * coefficient(mid, True)
    inner = nodes[1:-1]
    q = n**2 * inner * coefficient(inner, False)
    diag = (p[:-1] + p[1:]) / h**2 + q
    off = -p[1:-1] / h**2
    scale = 1 / np.sqrt(inner)
    lam = eigh_tridiagonal(diag * scale**2, off * scale[:-1] * scale[1:], select="i",
                           select_range=(0, count - 1), eigvals_only=True)
    return np.sqrt(m.wave_speed2 * lam)


@pytest.mark.parametrize("name", LAWS)
@pytest.mark.parametrize("n", [0, 2])
def test_linear_frequencies_converge_and_agree_with_finite_differences(name, n):
    m = membrane(name)
    ps = solve_prestretch(m, "numeric")
    omega, _, change = galerkin_frequencies(ps, n, 3, full_output=True)
    assert change < 2e-6  # the adaptive basis converged (model.linear.CHANGE_TOL)
    coarse = galerkin_frequencies(ps, n, 3, basis=16)[0]
    assert np.all(np.abs(coarse - omega) > np.abs(galerkin_frequencies(ps, n, 3, basis=64)[0] - omega))
    # finite differences, second order: Richardson on 2000 and 4000 intervals
    fd = (4 * sturm_liouville_frequencies(m, n, 3, 4000) - sturm_liouville_frequencies(m, n, 3, 2000)) / 3
    np.testing.assert_allclose(omega, fd, rtol=1e-5)  # Galerkin converged to ~1e-6, FD beyond
    # and not the neo-Hookean frequencies: the check sees the law
    nh = galerkin_frequencies(solve_prestretch(Membrane(delta=1.5, delta_o=0.2), "numeric"), n, 3)[0]
    assert np.all(np.abs(omega / nh - 1) > 1e-3)


MODE_SET = [(1, 0), (2, 0), (1, 1), (1, 2)]


@pytest.fixture(scope="module", params=list(LAWS))
def rom(request):
    m = membrane(request.param, delta=1.1)
    return build_rom(solve_prestretch(m, "numeric"), MODE_SET)


def _force(rom, q):
    g = np.empty(rom.dof)
    elastic_force(np.asarray(q, dtype=float), rom.tables, g, force_work(rom.tables))
    return g


def test_forces_are_the_gradient_of_the_energy(rom):
    from model.rom import strain_energy as rom_energy
    q = np.array([0.12, -0.04, 0.05, 0.03])
    h = 1e-6
    eye = np.eye(rom.dof)
    fd = np.array([(rom_energy(q + h * e, rom.tables) - rom_energy(q - h * e, rom.tables)) / (2 * h) for e in eye])
    g = _force(rom, q)
    np.testing.assert_allclose(g, fd, rtol=0, atol=1e-7 * np.abs(g).max())  # FD truncation ~1e-10
    jac = np.empty((rom.dof, rom.dof))
    force_jacobian(q, rom.tables, jac)
    fd = np.column_stack([(_force(rom, q + h * e) - _force(rom, q - h * e)) / (2 * h) for e in eye])
    np.testing.assert_allclose(jac, fd, rtol=0, atol=1e-7 * np.abs(jac).max())


def test_the_undamped_rom_conserves_its_energy(rom):
    y0 = np.array([0.15, -0.03, 0.04, 0.02, 0.0, 0.0, 0.0, 0.0])
    period = 2 * np.pi / 40.0
    drift = []
    for steps in (400, 800, 1600):
        y = y0.copy()
        rk4_steps(y, 0.0, 4 * period / steps, steps, rom.tables, ForcedMap.build(rom, 0.0, 40.0, Viscous()).forcing,
                  np.empty((6, y.size)))
        drift.append(abs(total_energy(rom, y) / total_energy(rom, y0) - 1))
    # RK4 is fourth order: halving the step divides an integration error by 16 or more (the
    # energy error of a conservative system often falls faster before the asymptotic
    # regime); a force that is not the energy's gradient would leave a drift that does not
    # fall
    assert drift[0] / drift[1] > 12 and drift[1] / drift[2] > 12
    assert drift[2] < 1e-8


@pytest.mark.parametrize("fields", [dict(law="mooney-rivlin", C2=0.0), dict(law="gent", Jm=np.inf)])
def test_the_neo_hookean_limits_are_the_neo_hookean_law(fields):
    nh, other = Membrane(delta=1.3), Membrane(delta=1.3, **fields)
    a, b = solve_prestretch(nh, "numeric"), solve_prestretch(other, "numeric")
    rho = np.linspace(nh.Ro, nh.Re, 33)
    np.testing.assert_allclose(b.radius(rho), a.radius(rho), rtol=1e-14)
    np.testing.assert_allclose(np.array(b.stresses(rho)), np.array(a.stresses(rho)), rtol=1e-12)
    np.testing.assert_allclose(galerkin_frequencies(b, 1, 2)[0], galerkin_frequencies(a, 1, 2)[0], rtol=1e-13)
    ra, rb = build_rom(a, MODE_SET), build_rom(b, MODE_SET)
    q = np.array([0.2, 0.03, -0.05, 0.04])
    np.testing.assert_allclose(_force(rb, q), _force(ra, q), rtol=1e-13)
    ya, yb = ForcedMap.build(ra, 1.0, 40.0, Viscous(0.05), 64), ForcedMap.build(rb, 1.0, 40.0, Viscous(0.05), 64)
    y0 = np.concatenate([q, np.zeros(4)])
    np.testing.assert_allclose(yb.advance(y0, 2), ya.advance(y0, 2), rtol=1e-12, atol=1e-15)


def test_mooney_rivlin_frequencies_scale_with_the_small_strain_shear_modulus():
    """At small pre-strain the membrane's tension is proportional to the shear modulus
    ``2 (C1 + C2)`` (linear elasticity), so the frequency ratio to neo-Hookean tends to
    ``sqrt(1 + C2/C1)`` as ``delta -> 1``; the deviation is first order in the strain."""
    ratios = []
    for d in (1.01, 1.001):
        w = [galerkin_frequencies(solve_prestretch(Membrane(delta=d, **kw), "numeric"), 0, 1)[0][0]
             for kw in ({}, dict(law="mooney-rivlin", C2=0.1 * 0.17e6))]
        ratios.append(w[1] / w[0] / np.sqrt(1.1) - 1)
    assert abs(ratios[1]) < 1e-4 and 8 < ratios[0] / ratios[1] < 12  # strain 1e-3; ten times the strain, ten times


def test_gent_approaches_neo_hookean_as_jm_grows():
    nh = galerkin_frequencies(solve_prestretch(Membrane(delta=2.0), "numeric"), 0, 1)[0][0]
    diffs = [abs(galerkin_frequencies(solve_prestretch(Membrane(delta=2.0, law="gent", Jm=jm), "numeric"),
                                      0, 1)[0][0] / nh - 1) for jm in (100.0, 1000.0, 10000.0)]
    # first order in 1/Jm: ten times Jm, a tenth of the difference
    assert 8 < diffs[0] / diffs[1] < 12 and 8 < diffs[1] / diffs[2] < 12


def test_a_membrane_refuses_a_constant_of_another_law():
    with pytest.raises(ParameterError, match="C2 = 1000.0 is invalid: must be left at 0 with law = 'neo-hookean'"):
        Membrane(C2=1e3)
    with pytest.raises(ParameterError, match="Jm = 5.0 is invalid: must be left at inf with law = 'mooney-rivlin'"):
        Membrane(law="mooney-rivlin", Jm=5.0)
    with pytest.raises(ParameterError, match='law = .rubber. is invalid: must be one of "neo-hookean"'):
        Membrane(law="rubber")


#: One small job of every analysis, ``{membrane}`` the material table under test.
ANALYSIS_JOBS = {
    "static": """
[grid]
delta = [1.1, 1.5]
delta_o = 0.2
[static]
rho = {start = 0.2, stop = 1.0, num = 9}
""",
    "linear": """
[grid]
delta = [1.1, 1.5]
delta_o = 0.2
[linear]
modes = [[1, 0], [2, 0], [1, 2]]
""",
    "backbone": """
[grid]
delta = 1.1
delta_o = 0.2
[backbone]
modes = [[1, 0], [2, 0]]
prestretch = "analytic"
amplitude = {start = 0.01, stop = 0.2, num = 4}
""",
    "response": """
[grid]
delta = 1.1
delta_o = 0.2
P0 = 5.0
c = 5.0
[response]
parameter = "Omega"
values = {start = 32.0, stop = 35.0, num = 4}
prestretch = "analytic"
steps = 64
max_periods = 3000
""",
    "continuation": """
[grid]
delta = 1.1
delta_o = 0.2
P0 = 1.0
c = 0.05
[continuation]
parameter = "Omega"
start = 30.0
stop = 36.0
prestretch = "analytic"
steps = 64
max_points = 300
families = {n = [1], radial = 2}
""",
    "basins": """
[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
P0 = 5.0
c = 5.0
[basins]
prestretch = "analytic"
ic_x = {start = -0.3, stop = 0.3, num = 6}
ic_y = {start = -10.0, stop = 10.0, num = 6}
tiles = 1
max_periods = 3000
""",
    # the features of the continuation on their own: branch switching, a codim-2 fold curve
    "continuation:switching": """
[grid]
delta = 1.1
delta_o = 0.2
P0 = 1.0
c = 0.05
[continuation]
parameter = "Omega"
start = 25.0
stop = 44.0
prestretch = "analytic"
steps = 64
ds_max = 0.3
max_points = 300
families = {n = [1], radial = 2}
branch_switching = {max_points = 6, n = 1}
""",
    "continuation:fold_curve": """
[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
c = 0.05
[continuation]
parameter = "P0"
start = 0.0
stop = 3.0
prestretch = "analytic"
steps = 64
max_points = 200
fold_curve = {parameter = "c", start = 0.05, stop = 0.1}
""",
    # a mode-set sweep
    "basins:mode_sets": """
[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
P0 = 5.0
c = 5.0
[basins]
modes = [[[1, 0]], [[1, 0], [2, 0]]]
prestretch = "analytic"
ic_x = {start = -0.3, stop = 0.3, num = 4}
ic_y = {start = -10.0, stop = 10.0, num = 4}
tiles = 1
max_periods = 3000
""",
}


def _run_in_process(case: str, membrane: str) -> list[dict]:
    from sweep.jobspec import parse_job

    analysis = case.split(":")[0]
    job = parse_job(f'[job]\nname = "law"\nanalysis = "{analysis}"\n{membrane}\n{ANALYSIS_JOBS[case]}')
    return [job.analysis.compute(*job.point(t)[:1], job.options, job.point(t)[1]) for t in range(job.layout.n_tasks)]


@pytest.mark.parametrize("analysis", ANALYSIS_JOBS)
def test_mooney_rivlin_without_c2_is_the_neo_hookean_law_in_every_analysis(analysis):
    # (and in the continuation's branch switching and fold curves, and a mode-set sweep)
    """Every analysis of a job with ``law = "mooney-rivlin"``, ``C2 = 0`` gives the
    neo-Hookean job's arrays: the law's extra terms are exact zeros, so the arithmetic
    differs only where the compiler orders the two specialisations' sums differently
    (rounding, amplified by Newton solves and adaptive steps to at most 1e-9 here)."""
    nh = _run_in_process(analysis, "")
    mr = _run_in_process(analysis, '[membrane]\nlaw = "mooney-rivlin"\nC2 = 0.0')
    reached = {"continuation:switching": "switched_Omega", "continuation:fold_curve": "fold_curve_c"}
    if analysis in reached:  # the feature did follow its branch or curve
        assert np.isfinite(nh[0][reached[analysis]]).sum() >= 3
    for a, b in zip(nh, mr):
        assert a["status"] == b["status"] == 0, (a.get("message"), b.get("message"))
        for name in a:
            if name in ("status", "message"):
                continue
            np.testing.assert_allclose(np.asarray(b[name], dtype=float), np.asarray(a[name], dtype=float),
                                       rtol=1e-9, atol=1e-12, equal_nan=True, err_msg=f"{analysis}: {name}")


def test_a_material_law_changes_the_results_and_its_constant_is_a_grid_key():
    """The same linear job with Mooney-Rivlin constants on the grid: C2 = 0 is the
    neo-Hookean job, C2 > 0 stiffens (small-strain shear modulus 2 (C1 + C2): the
    frequencies rise by nearly sqrt(1 + C2/C1))."""
    from sweep.jobspec import parse_job

    text = ANALYSIS_JOBS["linear"].replace("delta_o = 0.2", "delta_o = 0.2\nC2 = [0.0, 17000.0]")
    job = parse_job(f'[job]\nname = "law"\nanalysis = "linear"\n[membrane]\nlaw = "mooney-rivlin"\n{text}')
    assert job.layout.dims == ("delta", "delta_o", "C2")
    omega = {}
    for t in range(job.layout.n_tasks):
        point, subtask = job.point(t)
        omega[(point.membrane.delta, point.membrane.C2)] = job.analysis.compute(point, job.options, subtask)["omega"]
    nh = _run_in_process("linear", "")
    np.testing.assert_allclose(omega[(1.1, 0.0)], nh[0]["omega"], rtol=1e-13)
    ratio = omega[(1.1, 17000.0)] / omega[(1.1, 0.0)]
    assert np.all(np.abs(ratio / np.sqrt(1.1) - 1) < 0.01)


def test_gent_beyond_its_limit_of_extensibility_is_refused_or_not_finite():
    """No planar state of the outer edge (hoop stretch delta) has ``I1 - 3`` below
    ``delta^2 + 2/delta - 3``: such a membrane is refused in one line; a motion that reaches
    the limit gives a force that is not finite (never a number marked ok); the one-mode
    table stops short of the limit."""
    with pytest.raises(ValueError, match=r"Jm = 0.5 is invalid at delta = 2.0: must exceed delta\^2 \+ 2/delta - 3 = 2"):
        solve_prestretch(Membrane(delta=2.0, law="gent", Jm=0.5), "numeric")
    m = Membrane(delta=1.1, law="gent", Jm=3.0)
    rom = build_rom(solve_prestretch(m, "numeric"), [(1, 0)])
    inside, beyond = _force(rom, [0.9 * rom.tables.table_max]), _force(rom, [5.0 * rom.tables.table_max])
    assert np.all(np.isfinite(inside)) and not np.any(np.isfinite(beyond))
    assert rom.tables.table_max < build_rom(solve_prestretch(Membrane(delta=1.1), "numeric"), [(1, 0)]).tables.table_max


_WARMUP_LAW = """
import sys, numba
from sweep.jobspec import parse_job
job = parse_job(sys.stdin.read())
for call in job.analysis.warmups(job.options):
    call()
print(any("MooneyRivlin" in str(sig) for name, module in list(sys.modules.items()) if name.startswith("model.")
          for f in vars(module).values() if isinstance(f, numba.core.registry.CPUDispatcher) for sig in f.signatures))
"""


@pytest.mark.parametrize("analysis", ["backbone", "response", "continuation", "basins"])
def test_the_warmups_compile_the_kernels_of_the_jobs_law(analysis):
    """The runner compiles an analysis' kernels once per node before the tasks
    (Analysis.warmups); for a Mooney-Rivlin job they must be its own specialisations, or every
    rank would compile them at its first task, concurrently.  In a fresh process, so that no
    other test's kernels count."""
    import subprocess
    import sys

    text = (f'[job]\nname = "law"\nanalysis = "{analysis}"\n[membrane]\nlaw = "mooney-rivlin"\nC2 = 1000.0\n'
            f'{ANALYSIS_JOBS[analysis]}')
    proc = subprocess.run([sys.executable, "-c", _WARMUP_LAW], input=text, capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split()[-1] == "True"
