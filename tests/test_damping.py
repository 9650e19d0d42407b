"""Damping laws (model/damping.py) through the kernels, the families and the job files.

References: the closed-form damping ratios of each law (Rayleigh ``zeta_j = alpha / (2
omega_j) + beta omega_j / 2``, modal ``zeta_j`` as given), the Floquet multipliers of the
damped linear free vibration at rest (``|mu| = exp(-zeta_j omega_j T)`` for each mode),
the frequencies of an independent ROM for the families, and the paper's viscous law
itself (a modal ratio ``c / (2 Gamma h omega_1)`` on one mode is the viscous law).
"""

import numpy as np
import pytest

from model.damping import Modal, Rayleigh, Viscous, match_modes
from model.families import build_family
from model.forced import ForcedMap
from model.params import Loading, Membrane, ParameterError
from model.prestretch import solve_prestretch
from model.rom import build_rom, linear_frequencies, linear_system
from sweep.analyses.base import JobError
from sweep.jobspec import parse_job

AXI3 = [(1, 0), (2, 0), (3, 0)]


@pytest.fixture(scope="module")
def prestretch():
    return solve_prestretch(Membrane(delta=1.1, delta_o=0.2), "numeric")


@pytest.fixture(scope="module")
def axi3(prestretch):
    return build_rom(prestretch, AXI3)


def _decay_rates(phi, period):
    """``zeta_j omega_j`` (s-1) of each mode from the monodromy matrix of the free linear
    vibration: the multipliers come in conjugate pairs of modulus ``exp(-zeta omega T)``."""
    mu = np.linalg.eigvals(phi)
    return np.sort(-np.log(np.abs(mu)) / period)[::2]


def test_law_terms_have_the_closed_form_ratios_on_a_random_system():
    rng = np.random.default_rng(7)
    a = rng.normal(size=(4, 4))
    mass = a @ a.T + 4 * np.eye(4)
    b = rng.normal(size=(4, 4))
    stiffness = b @ b.T + np.eye(4)
    lam = np.linalg.eigvals(np.linalg.solve(mass, stiffness)).real
    omega = np.sqrt(np.sort(lam))
    for law, zeta in ((Rayleigh(alpha=0.2, beta=0.03), 0.2 / (2 * omega) + 0.03 * omega / 2),
                      (Modal(zeta=(0.01, 0.02, 0.03, 0.04)), np.array([0.01, 0.02, 0.03, 0.04])),
                      (Modal(zeta=0.05), np.full(4, 0.05))):
        rate, matrix = law.terms(mass, stiffness, 2.2)
        # D = rate I + matrix has the eigenvectors of M^-1 K0 and the eigenvalues 2 zeta_j omega_j
        d = rate * np.eye(4) + matrix
        w, v = np.linalg.eig(np.linalg.solve(mass, stiffness))
        order = np.argsort(w.real)
        v = v[:, order].real
        np.testing.assert_allclose(np.linalg.solve(v, d @ v), np.diag(2 * zeta * omega), atol=1e-12)
    assert Viscous(c=0.05).terms(mass, stiffness, 2.2)[0] == 0.05 / 2.2
    assert Viscous(c=0.05).terms(mass, stiffness, 2.2)[1].shape == (0, 0)
    assert Rayleigh(alpha=0.3).terms(mass, stiffness, 2.2)[1].shape == (0, 0)  # beta = 0: a scalar rate


def test_per_mode_ratios_follow_the_coordinate_that_dominates_each_mode():
    # a diagonal system whose second coordinate is the slowest: its ratio goes to the lowest mode
    mass = np.eye(3)
    stiffness = np.diag([4.0, 1.0, 9.0])
    _, matrix = Modal(zeta=(0.1, 0.2, 0.3)).terms(mass, stiffness, 1.0, order=np.arange(3))
    np.testing.assert_allclose(np.diag(matrix), [2 * 0.1 * 2, 2 * 0.2 * 1, 2 * 0.3 * 3], rtol=1e-14)
    with pytest.raises(ValueError, match="zeta per mode is ambiguous here"):
        match_modes(np.array([[1.0, 1.0], [0.0, 0.1]]), np.eye(2), np.arange(2))


@pytest.mark.parametrize("make, message", [
    (lambda: Modal(zeta=-0.1), "zeta = -0.1 is invalid: must be a finite number >= 0"),
    (lambda: Modal(zeta=[]), r"zeta = \[\] is invalid: must be a number >= 0 or a non-empty list of them"),
    (lambda: Rayleigh(beta=float("nan")), r"beta = nan is invalid: must be a finite number >= 0 \(s\)"),
    (lambda: Viscous(c="x"), r"c = 'x' is invalid: must be a finite number >= 0 \(N s m-3\)"),
    (lambda: Modal(zeta=(0.1, 0.2)).ratios(3),
     r"zeta = \[0.1, 0.2\] is invalid: must be one ratio for every mode or exactly 3"),
    (lambda: Viscous(0.1).replaced("zeta", 0.1), "parameter = 'zeta' is invalid: the viscous damping law has c"),
])
def test_bad_constants_are_refused_with_their_name(make, message):
    with pytest.raises((ParameterError, ValueError), match=message):
        make()


@pytest.mark.parametrize("law", [Modal(zeta=(0.01, 0.03, 0.02)), Rayleigh(alpha=0.4, beta=3e-4)],
                         ids=["modal", "rayleigh"])
def test_every_mode_of_a_free_decay_decays_at_its_own_rate(axi3, law):
    """Free linear vibration at rest, three axisymmetric modes: each mode decays at
    ``zeta_j omega_j``, by the variational equations (the monodromy at rest) and by the
    state integration alone (the map's finite-difference Jacobian at 1e-7 m, linear to
    ~1e-10).  RK4 at h omega_3 = 0.04 errs by ~(h omega)^6 / 144 per step: 1e-8 relative
    in ``log |mu|`` over the 512 steps."""
    omega, _ = linear_frequencies(axi3)
    if isinstance(law, Modal):
        expected = np.array(law.zeta) * omega
    else:
        expected = 0.5 * law.alpha + 0.5 * law.beta * omega**2
    fmap = ForcedMap.build(axi3, 0.0, float(omega[0]), law, steps=512)
    rest = np.zeros(6)
    _, phi = fmap.monodromy(rest)
    np.testing.assert_allclose(np.sort(_decay_rates(phi, fmap.period)), np.sort(expected), rtol=1e-6)
    eps = 1e-7
    fd = np.column_stack([fmap.advance(eps * e) / eps for e in np.eye(6)])
    np.testing.assert_allclose(np.sort(_decay_rates(fd, fmap.period)), np.sort(expected), rtol=1e-6)


def test_a_modal_ratio_on_one_mode_is_the_viscous_law(prestretch):
    rom = build_rom(prestretch, [(1, 0)])
    c = 0.05
    m = prestretch.membrane
    zeta = c / (2 * m.Gamma * m.h * linear_frequencies(rom)[0][0])
    viscous = ForcedMap.from_loading(rom, Loading(Omega=33.5, P0=1.0, c=c))
    modal = ForcedMap.build(rom, 1.0, 33.5, Modal(zeta=zeta))
    np.testing.assert_allclose(modal.forcing.damping_rate, viscous.forcing.damping_rate, rtol=4e-16)
    assert modal.forcing.damping_matrix.shape == (0, 0)
    y = np.array([0.3, -2.0])
    np.testing.assert_allclose(modal.advance(y, 5), viscous.advance(y, 5), rtol=1e-13)


@pytest.mark.parametrize("law", [Modal(zeta=0.02), Rayleigh(alpha=0.1, beta=2e-4)], ids=["modal", "rayleigh"])
def test_family_perturbations_are_damped_by_the_law_on_the_family_modes(prestretch, law):
    """The family block at rest decays at the law's rates on the family's own linear modes,
    whose frequencies come from an independent ROM of the family's modes (the general
    quadrature of model.rom, not the family's radial tables)."""
    rom = build_rom(prestretch, [(1, 0)])
    fam = build_family(prestretch, rom, 1, 2)
    omega = linear_frequencies(build_rom(prestretch, list(fam.modes)))[0]
    expected = law.zeta * omega if isinstance(law, Modal) else 0.5 * law.alpha + 0.5 * law.beta * omega**2
    fmap = ForcedMap.build(rom, 0.0, float(omega[0]), law, steps=512)
    block = fmap.family_monodromy(np.zeros(2), fam)
    np.testing.assert_allclose(np.sort(_decay_rates(block, fmap.period)), np.sort(expected), rtol=1e-6)


def test_linear_system_gives_the_rom_frequencies(axi3):
    mass, stiffness = linear_system(axi3)
    lam = np.sort(np.linalg.eigvals(np.linalg.solve(mass, stiffness)).real)
    np.testing.assert_allclose(np.sqrt(lam), linear_frequencies(axi3)[0], rtol=1e-12)


def _continuation_job(damping: str, grid_c: str = "c = 0.05") -> str:
    return f"""
[job]
name = "damped"
analysis = "continuation"
{damping}
[grid]
delta = 1.1
delta_o = 0.2
Omega = 33.5
{grid_c}
[continuation]
parameter = "P0"
start = 0.0
stop = 2.0
prestretch = "analytic"
steps = 64
max_points = 200
"""


def test_a_modal_job_at_the_viscous_ratio_gives_the_viscous_results(prestretch):
    """The same continuation (Fig. 15a case, one mode) with the paper's viscous c and with
    the modal ratio ``c / (2 Gamma h omega_1)``: the rates differ by rounding (4e-16), the
    branches agree to the Newton tolerance's amplification of it (1e-9 relative)."""
    viscous = parse_job(_continuation_job(""))
    rom = build_rom(solve_prestretch(Membrane(), "analytic"), [(1, 0)])
    zeta = 0.05 / (2 * 2200.0 * 1e-3 * linear_frequencies(rom)[0][0])
    modal = parse_job(_continuation_job(f"[damping]\nlaw = \"modal\"\nzeta = {float(zeta)!r}", grid_c=""))
    results = []
    for job in (viscous, modal):
        point, subtask = job.point(0)
        results.append(job.analysis.compute(point, job.options, subtask))
    a, b = results
    assert a["status"] == b["status"] == 0
    n = int(np.sum(np.isfinite(a["amplitude"])))
    assert n > 10 and int(np.sum(np.isfinite(b["amplitude"]))) == n
    for name in ("P0", "amplitude", "modal_coordinate", "multiplier_modulus", "fold_value", "fold_amplitude"):
        np.testing.assert_allclose(b[name], a[name], rtol=1e-9, equal_nan=True, err_msg=name)
    assert modal.point(0)[0].damping == Modal(zeta=zeta)


@pytest.mark.parametrize("damping, grid_c, message", [
    ('[damping]\nlaw = "coulomb"', "", 'damping.law = \'coulomb\' is invalid: one of "viscous", "rayleigh", "modal"'),
    ('[damping]\nlaw = "rayleigh"\nzeta = 0.1', "",
     "damping.zeta = 0.1 is invalid: unknown key; the keys of [damping] are law, alpha, beta"),
    ('[damping]\nlaw = "modal"\nzeta = -1', "", "damping.zeta = -1 is invalid: a finite number >= 0"),
    ('[damping]\nlaw = "modal"\nzeta = "x"', "",
     "damping.zeta = 'x' is invalid: a number or a list of numbers (one per mode)"),
    ('[damping]\nlaw = "modal"\nzeta = 0.01', "c = 0.05",
     "grid.c = [0.05] is invalid: a constant of another damping law; this job's law is modal ([damping] law), "
     "whose constants are zeta"),
    ('[damping]\nc = 0.05', "c = 0.05", "grid.c = [0.05] is invalid: set in [damping] already (one place for c)"),
    ('[damping]\nlaw = "rayleigh"\nalpha = 0.1', "",
     "grid.beta = <missing> is invalid: continuation in P0 needs beta (s) in [grid] or [damping]"),
    ("", "", "grid.c = <missing> is invalid: continuation in P0 needs c (N s m-3) in [grid] or [damping]"),
    ('[damping]\nlaw = "modal"\nzeta = [0.01, 0.02]', "",
     "damping.zeta = [0.01, 0.02] is invalid: one ratio, or one per mode of continuation.modes (1)"),
    ('[damping]\nlaw = "modal"\nzeta = [0.01]', "", None),
])
def test_bad_damping_tables_are_refused_naming_the_key(damping, grid_c, message):
    if message is None:  # the valid neighbour of the case before: one ratio for the one mode
        assert parse_job(_continuation_job(damping, grid_c)).damping.law == Modal(zeta=0.01)
        return
    with pytest.raises(JobError) as info:
        parse_job(_continuation_job(damping, grid_c))
    assert message in str(info.value)


def test_a_list_of_ratios_is_refused_with_families():
    text = _continuation_job('[damping]\nlaw = "modal"\nzeta = [0.01, 0.02]', "").replace(
        'stop = 2.0', 'stop = 2.0\nmodes = [[1, 0], [2, 0]]\nfamilies = {n = [1], radial = 2}')
    with pytest.raises(JobError, match=r"damping.zeta = \[0.01, 0.02\] is invalid: one ratio for every mode with "
                                       "asymmetric families in continuation"):
        parse_job(text)


def test_damping_constants_are_grid_keys_and_curve_parameters():
    job = parse_job(_continuation_job('[damping]\nlaw = "rayleigh"\nalpha = 0.1', grid_c="beta = [1e-4, 2e-4]")
                    + 'fold_curve = {parameter = "alpha", start = 0.1, stop = 0.5}\n')
    assert job.layout.dims == ("delta", "delta_o", "Omega", "beta")
    point, _ = job.point(1)
    assert point.damping == Rayleigh(alpha=0.1, beta=2e-4) and point.loading.c == 0.0
    assert point.value("beta") == 2e-4 and job.options.fold_curve == ("alpha", 0.1, 0.5)
    with pytest.raises(JobError, match="continuation.fold_curve.parameter = 'c' is invalid: must be one of "
                                       "alpha, beta, Omega"):
        parse_job(_continuation_job('[damping]\nlaw = "rayleigh"\nalpha = 0.1', grid_c="beta = 1e-4")
                  + 'fold_curve = {parameter = "c", start = 0.1, stop = 0.5}\n')
