"""The membrane's free motion on the two-dimensional finite-element mesh (model/fe_motion.py,
``backbone.fe_check``): its force, its linear oscillation against the mesh's eigenvalue
problem, and its nonlinear motion against the full model's free orbits, converging at the
element's order."""

import numpy as np
import pytest

from model.backbone import continue_free_orbits
from model.fe_annulus import AnnulusMesh, fe_modes, ray_nodes, solve_fe_prestretch
from model.fe_motion import (REFERENCE_STEP, STABILITY_FRACTION, FeMotion, asymmetric_start, check_free_orbit,
                              check_harmonic_motion, extremum_times, harmonic_reference, reference_error,
                              turned_nodes)
from model.full import surface
from model.full.axisymmetric import AxisymmetricFull
from model.full.free import FreeFull
from model.full.harmonic import HarmonicFull
from model.full.static import solve_full_prestretch
from model.params import Membrane
from sweep import cli
from sweep.analyses.backbone import FE_HARMONICS
from tests.test_full_jobs import JOBS, _run

MEMBRANE = Membrane(delta=1.5, delta_o=0.2)


@pytest.fixture(scope="module")
def coarse():
    return FeMotion.build(solve_fe_prestretch(AnnulusMesh.build(MEMBRANE, 4, 16)))


def test_the_force_is_the_gradient_of_the_energy_and_vanishes_at_rest(coarse):
    rng = np.random.default_rng(1)
    D = coarse.rest.copy()
    D[:, coarse.free] += 0.01 * rng.standard_normal((3, coarse.free.size))
    dD = np.zeros_like(D)
    dD[:, coarse.free] = rng.standard_normal((3, coarse.free.size))
    h = 1e-20  # complex step: exact to rounding
    complex_step = (surface.energy(MEMBRANE.material, *coarse.columns(D + 1j * h * dD)) @ coarse.weights).imag / h
    assert complex_step == pytest.approx(float((coarse.force(D) * dD).sum()), rel=1e-12)
    # the pre-stretch solves the in-plane residual to Newton's 1e-12 step
    assert np.abs(coarse.acceleration(coarse.rest)).max() < 1e-8


@pytest.mark.parametrize("law, C2", [("neo-hookean", 0.0), ("mooney-rivlin", 0.1 * MEMBRANE.C1)])
def test_the_compiled_force_is_the_sparse_product_force(law, C2):
    membrane = Membrane(delta=1.5, delta_o=0.2, law=law, C2=C2)
    motion = FeMotion.build(solve_fe_prestretch(AnnulusMesh.build(membrane, 2, 8)))
    D = motion.rest.copy()
    D[:, motion.free] += 0.01 * np.random.default_rng(2).standard_normal((3, motion.free.size))
    reference = motion.force(D)
    assert np.abs(motion.compiled_force(D) - reference).max() <= 1e-12 * np.abs(reference).max()


def test_the_probe_is_the_quadratic_through_its_edges_nodes(coarse):
    """At radii in the inner and the outer half of every edge of the ray theta = 0 (and at
    its ends), the probe of a field with random nodal values is the quadratic through the
    values at that edge's vertex, midpoint and vertex -- the P2 field along the edge."""
    values = np.random.default_rng(3).standard_normal(coarse.basis.N)
    on_ray = ray_nodes(coarse.basis.doflocs)
    r = coarse.basis.doflocs[0, on_ray]
    for first in range(0, r.size - 2, 2):
        x, f = r[first:first + 3], values[on_ray[first:first + 3]]
        for rho in (x[0], 0.7 * x[0] + 0.3 * x[1], 0.4 * x[1] + 0.6 * x[2], x[2]):
            expected = sum(f[i] * np.prod([(rho - x[k]) / (x[i] - x[k]) for k in range(3) if k != i])
                           for i in range(3))
            assert (coarse.probe(rho) @ values)[0] == pytest.approx(expected, rel=1e-12, abs=1e-12)
    # an end computed through Re and delta_o that rounds just outside the mesh is the end
    assert (coarse.probe(r[0] * (1 - 1e-15)) @ values)[0] == pytest.approx(values[on_ray[0]])
    with pytest.raises(ValueError, match="rho = 0.1 is invalid"):
        coarse.probe(0.1)


def test_the_motion_conserves_its_energy(coarse):
    """Two periods at 5 cm in the lowest transverse shape: RK4 at half its stability limit
    loses energy only through its damping of the fastest modes (about ``(omega dt)^6 / 144``
    per step, which the smooth start hardly excites) and its phase error; the total energy
    stays within 1e-6 of its value (the kinetic energy's swing is of the energy's size)."""
    omega, shapes = fe_modes(coarse.state, "W", 1, n_max=0)[0]
    D0 = coarse.rest.copy()
    D0[2] = 0.05 * shapes[:, 0] / np.abs(shapes[:, 0]).max()
    rest = coarse.energy(coarse.rest)
    energies = []
    steps = int(np.ceil(4 * np.pi / omega[0] / coarse.time_step()))
    coarse.motion(D0, 4 * np.pi / omega[0] / steps, steps,
                  lambda step, D, V: energies.append(coarse.energy(D) - rest + coarse.kinetic(V)))
    energies = np.array(energies)
    assert energies[0] > 0
    assert np.abs(energies / energies[0] - 1).max() < 1e-6


def test_a_small_oscillation_has_the_frequency_of_the_lowest_mode(coarse):
    """The mesh's lowest transverse n = 0 eigenpair (:func:`fe_modes`, an independent eigenvalue
    solve of the same forms), a 1 um deflection: the motion's frequency is the eigenvalue's.
    RK4's phase error at its step (``(omega dt)^4 / 120``, 1e-8) and the nonlinearity (1e-12)
    are far below the parabolic extrema's, less than ``(omega dt)^2 / 8`` of half a step over
    the two periods' span: 1e-6."""
    omega, shapes = fe_modes(coarse.state, "W", 1, n_max=0)[0]
    shape = shapes[:, 0] / np.abs(shapes[:, 0]).max()
    D0 = coarse.rest.copy()
    D0[2] = 1e-6 * shape
    k = int(np.argmax(np.abs(shape)))
    trace = []
    steps = int(np.ceil(4 * np.pi / omega[0] / coarse.time_step()))
    dt = 4 * np.pi / omega[0] / steps
    coarse.motion(D0, dt, steps, lambda step, D, V: trace.append(D[2, k]))
    times = extremum_times(np.array(trace), dt)
    assert times.size == 3
    measured = np.pi * np.arange(1, 4) @ times / (times @ times)
    assert measured == pytest.approx(omega[0], rel=1e-6)


@pytest.fixture(scope="module")
def orbit():
    free = FreeFull(AxisymmetricFull(solve_full_prestretch(MEMBRANE, 16)))
    orbits, _ = continue_free_orbits(free, np.array([0.05]))
    assert orbits.converged.all()
    return free, orbits.modal[0], 2.0 * np.pi / orbits.omega[0]


def test_the_mesh_follows_the_full_models_orbit_converging_at_the_elements_order(orbit, coarse):
    """From rest at a 5 cm orbit of the full model (16 functions: spectrally converged), two
    periods on 4 x 16, 8 x 32 and 16 x 64 P2 elements: quadratic elements approximate
    displacements to O(h^3), so halving h divides the deviations by about 8; the measured
    orders must exceed 2.5 (u, second order in the deflection and driven by the square of
    w's slope, enters its asymptotic range later: 2.4 between 4 and 8 elements, so its order is
    taken between 8 and 16).  The frequency from the extrema is bounded by the deviation: the
    other modes in the motion shift an extremum of ``A cos(omega t)`` by about their share of
    ``w`` times ``omega_c / (pi omega)``, which is of order one for the lowest of them.  A
    smaller time step (at most 0.7 of it: the rule that puts a whole number of steps between
    the samples rounds half of the limit) changes the frequency and the deviation by less than
    1 % of the mesh's (the time error is negligible)."""
    free, q0, period = orbit
    rho = np.linspace(MEMBRANE.Ro, MEMBRANE.Re, 41)
    meshes = [coarse] + [FeMotion.build(solve_fe_prestretch(AnnulusMesh.build(MEMBRANE, r, 4 * r))) for r in (8, 16)]
    checks = [check_free_orbit(m, free, q0, period, 2, rho) for m in meshes]
    omega = 2.0 * np.pi / period
    for a, b in zip(checks, checks[1:]):
        assert np.log2(a.w_deviation / b.w_deviation) > 2.5
    assert np.log2(checks[1].u_deviation / checks[2].u_deviation) > 2.5
    assert all(abs(c.omega / omega - 1) < c.w_deviation for c in checks)

    class HalfStep:  # the coarse mesh at half its time step
        def __getattr__(self, name):
            return getattr(coarse, name)

        def time_step(self):
            return 0.5 * coarse.time_step()

    halved = check_free_orbit(HalfStep(), free, q0, period, 2, rho)
    assert halved.dt < 0.7 * checks[0].dt
    assert abs(halved.omega - checks[0].omega) < 0.01 * abs(checks[0].omega - omega)
    assert abs(halved.w_deviation - checks[0].w_deviation) < 0.01 * checks[0].w_deviation


def test_the_mesh_follows_the_harmonics_asymmetric_motion_converging_at_the_elements_order(orbit, coarse):
    """The 5 cm orbit's deflection plus 1 cm of the lowest n = 1 transverse mode, the in-plane
    fields relaxed to it (the job's start), on the full model's harmonics FE_HARMONICS
    (model/full/harmonic.py) and on the 4 x 16 and 8 x 32 meshes (Cartesian components, no
    harmonics), two periods, compared at the mesh's nodes: w, its odd part (the asymmetric
    motion) and v fall at the element's order (measured 3.8, 3.7 and 2.9; the bound of the
    axisymmetric check above, 2.5), u as the axisymmetric check's u does between these meshes
    (measured 2.6; bound 2).  From the orbit's own in-plane state, not relaxed, v fell at order
    1.9 (and 1.7 from 8 to 16 elements): the start's in-plane imbalance rings the fast in-plane
    modes, which neither discretisation resolves.  Neither time step is a source: halving both
    moves every deviation of the coarse mesh by less than 1 % of itself.  Nor are the
    harmonics: with the harmonics 4 and 5 the odd part moves by less than a hundredth of the
    finer mesh's deviation of it (the job measures both against the finest mesh:
    reference_error)."""
    free, q, period = orbit
    harmonic = HarmonicFull(free.model, FE_HARMONICS)
    reference = harmonic_reference(harmonic, harmonic.relaxed(asymmetric_start(harmonic, q, 0.01)), period, 2)
    fine = FeMotion.build(solve_fe_prestretch(AnnulusMesh.build(MEMBRANE, 8, 32)))
    checks = [check_harmonic_motion(m, reference) for m in (coarse, fine)]
    assert np.log2(checks[0].w_deviation / checks[1].w_deviation) > 2.5
    assert np.log2(checks[0].odd_deviation / checks[1].odd_deviation) > 2.5
    assert np.log2(checks[0].u_deviation / checks[1].u_deviation) > 2.0
    assert np.log2(checks[0].v_deviation / checks[1].v_deviation) > 2.5
    halved = check_harmonic_motion(coarse, harmonic_reference(harmonic, reference.coordinates[0], period, 2,
                                                              step=REFERENCE_STEP / 2),
                                   step_fraction=STABILITY_FRACTION / 2)
    assert halved.dt < 0.7 * checks[0].dt and reference.dt * harmonic.highest_frequency() > REFERENCE_STEP / 2
    for a, b in zip(halved[:4], checks[0][:4]):
        assert abs(a - b) < 0.01 * b
    more = HarmonicFull(free.model, FE_HARMONICS + (4, 5))
    rho, theta = fine.polar_nodes()
    odd = [np.array([h.fields(c, rho, theta)[2] - h.fields(c, rho, theta + np.pi)[2] for c in r.coordinates])
           for h, r in ((harmonic, reference),
                        (more, harmonic_reference(more, more.relaxed(asymmetric_start(more, q, 0.01)), period, 2)))]
    assert np.abs(odd[0] - odd[1]).max() / np.abs(odd[1]).max() < 0.01 * checks[1].odd_deviation


def test_the_harmonics_reference_converges_at_rk4s_order_in_u_and_v(orbit):
    """The harmonics' reference motion from the job's start (the in-plane fields relaxed): its
    change when the step is halved falls at RK4's order 4 (asserted above 3; measured 3.7 and
    3.6 for u and v) from omega_max dt = 0.5 to 0.25 and 0.125, and at REFERENCE_STEP it is
    below 9e-5 of u's and v's largest values (measured 6.6e-8 and 1.2e-8): a tenth of the
    smallest deviation of u or v the finest mesh of the fe-free-vibration jobs shows (9.2e-4,
    docs/validation.md), so those deviations are not the step's."""
    free, q, period = orbit
    harmonic = HarmonicFull(free.model, FE_HARMONICS)
    start = harmonic.relaxed(asymmetric_start(harmonic, q, 0.01))
    runs = [harmonic_reference(harmonic, start, period, 2, step=step) for step in (0.5, 0.25, 0.125)]
    assert runs[1].dt * harmonic.highest_frequency() <= REFERENCE_STEP == 0.25
    coarse_change, fine_change = reference_error(runs[0], runs[1]), reference_error(runs[1], runs[2])
    for field in ("u", "v"):
        assert np.log2(getattr(coarse_change, field) / getattr(fine_change, field)) > 3.0, field
        assert getattr(fine_change, field) < 9e-5, field


@pytest.mark.parametrize("n", [1, 2, 4])
def test_the_odd_part_of_wave_number_n_keeps_the_odd_multiples_of_n(coarse, n):
    """On the 4 x 16 mesh a nodal field on the harmonics 0, n, 2n, 3n: w - w at the nodes
    turned by pi / n is twice its part on n and 3n (to rounding: the turned nodes are the
    mesh's own, found to 1e-9), and a wave number whose half turn is not a whole number of
    elements is refused."""
    rho, theta = coarse.polar_nodes()
    f = [np.sin(np.pi * (rho - rho.min()) / np.ptp(rho)) ** (k + 1) for k in range(4)]
    parts = [f[k] * np.cos(k * n * theta + 0.3 * k) for k in range(4)]
    w = sum(parts)
    assert np.abs(w - w[turned_nodes(coarse, n)] - 2 * (parts[1] + parts[3])).max() < 1e-12
    with pytest.raises(ValueError, match="n = 3 is invalid here"):
        turned_nodes(coarse, 3)


@pytest.mark.parametrize("n", [1, 2, 4])
def test_the_asymmetric_start_has_the_size_asked_in_metres(n):
    """On a membrane of Re = 2 m, on the harmonics 0, n, 2n: the harmonic n of the start has
    its largest |w| (m) equal to the size asked (to 2e-5, the error of a maximum on this grid of
    401 radii: its spacing squared times the shape's curvature), and the axisymmetric state's
    fields are the state's; harmonics that are not 0 and multiples of one n are refused."""
    membrane = Membrane(delta=1.5, delta_o=0.2, Re=2.0)
    model = AxisymmetricFull(solve_full_prestretch(membrane, 8))
    harmonic = HarmonicFull(model, (0, n, 2 * n))
    q = np.linspace(0.01, 0.02, 2 * model.order)
    start = asymmetric_start(harmonic, q, 0.03)
    rho = np.linspace(membrane.Ro, membrane.Re, 401) / membrane.Re
    u0, _, w0 = harmonic.fields(start, rho, 0.0 * rho)
    u_pi, _, w_pi = harmonic.fields(start, rho, np.pi / n + 0.0 * rho)
    assert membrane.Re * np.abs(w0 - w_pi).max() / 2 == pytest.approx(0.03, rel=2e-5)
    b = model.state.basis
    assert (w0 + w_pi) / 2 == pytest.approx(b.evaluate(q[model.order:], rho)[0], abs=1e-15)
    assert (u0 + u_pi) / 2 == pytest.approx(b.evaluate(q[:model.order], rho)[0], abs=1e-15)
    with pytest.raises(ValueError, match="0 and multiples of a wave number"):
        asymmetric_start(HarmonicFull(model, (0, 2 * n, 3 * n)), q, 0.03)


def test_the_asymmetric_start_takes_a_lower_orders_state_on_more_radial_functions():
    """The start of the reference on 8 more radial functions per field (the check's measure of
    the radial truncation): the axisymmetric state of order 8 has the same fields there (the
    Legendre-Galerkin functions do not depend on the order; to rounding); the mode part,
    computed on each order, is the same analytic mode shape, so the difference between orders
    falls spectrally (asserted: by more than 10 from 8 -> 16 to 16 -> 24 functions); a state of
    more functions than the model is refused."""
    membrane = Membrane(delta=1.5, delta_o=0.2)
    models = [AxisymmetricFull(solve_full_prestretch(membrane, order)) for order in (8, 16, 24)]
    q = np.linspace(0.01, 0.02, 2 * models[0].order)
    rho = np.linspace(membrane.Ro, membrane.Re, 401) / membrane.Re
    harmonics = [HarmonicFull(model, (0, 1, 2)) for model in models]
    fields = [h.fields(asymmetric_start(h, q, 0.0), rho, 0.0 * rho) for h in harmonics[:2]]
    np.testing.assert_allclose(fields[1], fields[0], rtol=0, atol=1e-14)
    modes = [h.fields(asymmetric_start(h, 0.0 * q, 0.03), rho, 0.0 * rho)[2] for h in harmonics]
    changes = [np.abs(b - a).max() for a, b in zip(modes, modes[1:])]
    assert changes[1] < changes[0] / 10
    with pytest.raises(ValueError, match="more than the model's 8"):
        asymmetric_start(harmonics[0], np.zeros(2 * models[1].order), 0.03)


@pytest.mark.parametrize("job, harmonics, half_wave", [("fe-free-vibration", "0, 1, 2, 3", "theta + pi)"),
                                                     ("fe-free-vibration-n2", "0, 2, 4, 6", "theta + pi / 2)")])
def test_the_backbone_fe_check_option_writes_the_mesh_study(tmp_path, job, harmonics, half_wave):
    text = (JOBS / f"validation/{job}.toml").read_text()
    text = (text.replace("order = 24", "order = 12").replace("delta = [1.1, 1.5, 2.0]", "delta = [1.5]")
            .replace("start = 0.02, stop = 0.1, num = 3", "start = 0.02, stop = 0.04, num = 2")
            .replace("radial = [4, 8, 16]", "radial = [2, 4]"))
    ds = _run(tmp_path, "fe", text).squeeze()
    assert list(ds.fe_radial.values) == [2, 4]
    assert f"harmonics {harmonics}" in ds.fe_harmonic_w_deviation.long_name
    assert half_wave in ds.fe_harmonic_odd_deviation.long_name
    assert ds.fe_omega.dims == ("point", "fe_radial") and np.isfinite(ds.fe_omega).all()
    assert (ds.fe_omega_spread >= 0).all()
    # the finer mesh is closer to the full model's orbit in both fields; the frequencies are
    # finite (one extremum per half period) with a finite range
    for name in ("fe_w_deviation", "fe_u_deviation", "fe_harmonic_w_deviation", "fe_harmonic_odd_deviation",
                 "fe_harmonic_u_deviation", "fe_harmonic_v_deviation"):
        assert (ds[name].isel(fe_radial=1) < ds[name].isel(fe_radial=0)).all()
    # the harmonics' own error (more harmonics, 8 more radial functions, half the step) against
    # the finer mesh's deviations; regression bounds over the measured ratios (w, odd part up
    # to 1.4e-3; u, v up to 3.6e-3 from the relaxed start; from the orbit's own in-plane state,
    # not relaxed, u and v reached 0.052 and 0.114, which fail the bound of 0.02)
    for field, bound in (("w", 0.01), ("odd", 0.01), ("u", 0.02), ("v", 0.02)):
        assert (ds[f"fe_harmonic_reference_{field}_error"] < bound * ds[f"fe_harmonic_{field}_deviation"].isel(
            fe_radial=1)).all()
    assert np.isfinite(ds.fe_omega_spread).all()


def test_an_orbit_whose_start_does_not_relax_keeps_nan_and_says_so(monkeypatch, orbit):
    # HarmonicFull.relaxed raising (Newton not converging) at the one orbit: its fe_harmonic_*
    # stay NaN, the axisymmetric check is still made, and the problem names the orbit
    from types import SimpleNamespace

    from sweep.analyses.backbone import _fe_check

    def no_relaxation(self, q):
        raise ArithmeticError("the in-plane displacement at the given deflection did not converge")

    monkeypatch.setattr(HarmonicFull, "relaxed", no_relaxation)
    free, q, period = orbit
    orbits = SimpleNamespace(amplitude=np.array([0.05]), omega=np.array([2.0 * np.pi / period]), modal=q[None],
                             converged=np.array([True]))
    out, problem = _fe_check(SimpleNamespace(membrane=MEMBRANE), free, orbits, (2,), 4, 1, 0.01, 1)
    assert np.isfinite(out["fe_w_deviation"]).all()
    assert np.isnan(out["fe_harmonic_v_deviation"]).all() and np.isnan(out["fe_harmonic_reference_v_error"]).all()
    assert problem == ("fe_check.asymmetric: the in-plane fields did not relax to the start's deflection at 0.05 m "
                       "(fe_harmonic_* NaN there)")


def test_an_axisymmetric_check_takes_any_mesh_around(tmp_path):
    # 9 and 15 elements around, no multiple of 2: accepted, the wave number's rule binds only
    # an asymmetric start
    path = tmp_path / "axi.toml"
    path.write_text((JOBS / "validation/fe-free-vibration.toml").read_text().replace(
        "radial = [4, 8, 16], around = 4, periods = 2, asymmetric = 0.01", "radial = [3, 5], around = 3, periods = 2"))
    assert cli.main(["plan", str(path)]) == 0


@pytest.mark.parametrize("job, change, message", [
    ("fig10-11-backbone.toml", ("[backbone]", "[backbone]\nfe_check = {radial = [4]}"),
     "backbone.fe_check = {'radial': [4]} is invalid: a check of the full model's orbits"),
    ("validation/fe-free-vibration.toml", ("radial = [4, 8, 16]", "radial = [8, 4]"),
     "backbone.fe_check.radial = [8, 4] is invalid: a non-empty list of distinct increasing"),
    ("validation/fe-free-vibration.toml", ("around = 4", "around = 1"),
     "backbone.fe_check.around = 1 is invalid: at least 2"),
    ("validation/fe-free-vibration.toml", ("asymmetric = 0.01", "asymmetric = -0.01"),
     "backbone.fe_check.asymmetric = -0.01 is invalid"),
    ("validation/fe-free-vibration.toml", ('kind = "full"', 'kind = "full"\ninplane = false'),
     "a check of the full model's orbits with in-plane motion"),
    ("validation/fe-free-vibration-n2.toml", ("wave_number = 2", "wave_number = 3"),
     "backbone.fe_check.wave_number = 3 is invalid: one of 1, 2, 4, 8 with these meshes: 2 n must divide the "
     "elements around of every mesh (16, 32, 64)"),
    ("validation/fe-free-vibration-n2.toml", ("asymmetric = 0.01", "asymmetric = 0"),
     "backbone.fe_check.wave_number = 2 is invalid: 1 without an asymmetric start"),
])
def test_bad_fe_checks_are_refused_in_one_line(tmp_path, capsys, job, change, message):
    path = tmp_path / "bad.toml"
    path.write_text((JOBS / job).read_text().replace(*change))
    assert cli.main(["run", str(path), "-o", str(tmp_path / "bad.nc")]) != 0
    assert message in capsys.readouterr().err

