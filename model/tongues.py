"""Parametric tongues of the asymmetric families: how much modulation destabilises a family,
measured and by first-order averaging.

Along an axisymmetric orbit of period ``T = 2 pi / Omega`` the perturbations of family ``n``
obey (:mod:`model.families`)::

    u'' + (r + D) u' + S(t) u = 0,      S(t) = diag(k_force) J(q(t))       (s-2)

a linear system with periodic stiffness: a parametrically excited one.  Write
``S(t) = S_bar + (S(t) - S_bar)`` with ``S_bar`` its mean over the period, and scale the
modulation::

    S_s(t) = S_bar + s (S(t) - S_bar).

``s = 1`` is the family's own block.  The **measured threshold** :func:`measured_threshold`
is the smallest ``s`` at which the block's largest Floquet multiplier reaches the unit circle
(integrated with the map's RK4 steps along the orbit's recorded stages).  A family unstable at
the point has ``s* <= 1``; the converse fails where the growing modulation enters a tongue and
leaves it again before ``s = 1``.

The **averaged threshold** (:func:`averaged_thresholds`) is first-order averaging
(Nayfeh and Mook, *Nonlinear Oscillations*, Sec. 5.7).  In the modes ``x`` of the mean
stiffness (``S_bar`` made symmetric by ``diag(k_force)^(-1/2)``: frequencies ``omega_j``,
decay rates ``alpha_j`` the diagonal of the damping in those modes over two, plus the decay
RK4 itself adds at the map's step ``h``, ``-ln|R(i omega_j h)| / h``, so that the averaging
describes the discrete map the measured threshold is taken on), the modulation
is a Fourier series ``sum_p k_ij^(p) cos(p Omega t + phi_ij^(p))``.  A resonance
``p Omega ~ omega_i + omega_j`` (``i = j``: the principal tongue of one mode; ``i != j``:
a combination tongue) is unstable, by averaging, when::

    (s k_ij)^2 / (16 omega_i omega_j) > alpha_i alpha_j (1 + sigma^2 / (alpha_i + alpha_j)^2),
    sigma = p Omega - omega_i - omega_j.

At exact tuning and equal rates this is ``s eps_ij > 4 alpha / sqrt(omega_i omega_j)`` with the
modulation depth ``eps_ij = k_ij / (omega_i omega_j)``; for one mode the textbook
``eps > 4 alpha / omega`` of ``q'' + 2 alpha q' + omega^2 (1 + eps cos 2 omega t) q = 0``.
Under the viscous pressure every ``alpha_j`` is the same ``c / (2 Gamma h)``, so the
depth threshold falls as ``1 / omega``: each radial mode added to a family can bring a tongue
easier to reach.  Under a constant modal ratio ``alpha_j = zeta omega_j`` (``omega_j`` the
family's frequencies at rest) and the depth threshold is about ``4 zeta`` whatever the
frequency.

The averaged threshold is the smallest over every ``i <= j`` and harmonic ``p``; first-order
averaging is exact as the modulation, damping and detuning go to zero together, and its
error grows with ``s eps``.
"""

from __future__ import annotations

from typing import NamedTuple

import numba as nb
import numpy as np

from . import rk4
from .families import block_slope, family_jacobian, stage_coordinates

#: Largest modulation scale searched by :func:`measured_threshold`.
SCALE_MAX = 8.0
#: Smallest modulation scale searched.
SCALE_MIN = 1e-3
#: Factor between the scales of the scan of :func:`measured_threshold`.
SCALE_GROWTH = 1.25


class Tongue(NamedTuple):
    """The lowest tongue of a family at one point of a branch.

    Attributes
    ----------
    measured : float
        Smallest modulation scale ``s`` at which the block's largest multiplier modulus
        reaches 1 (:func:`measured_threshold`); NaN if none up to :data:`SCALE_MAX`.
    averaged : float
        Smallest ``s`` of the averaged thresholds over every resonance.
    modes : (2,) int
        ``i <= j`` of the resonance with the smallest averaged threshold (1-based, the mean
        stiffness' modes by increasing frequency).
    harmonic : int
        ``p``: the resonance is ``p Omega ~ omega_i + omega_j``.
    frequencies : (2,) float
        ``omega_i``, ``omega_j`` (rad s-1).
    rates : (2,) float
        ``alpha_i``, ``alpha_j`` (s-1): the damping law's and RK4's at the map's step.
    depth : float
        ``eps_ij = k_ij / (omega_i omega_j)`` of the orbit's own modulation (1).
    detuning : float
        ``sigma = p Omega - omega_i - omega_j`` (rad s-1).
    """

    measured: float
    averaged: float
    modes: np.ndarray
    harmonic: int
    frequencies: np.ndarray
    rates: np.ndarray
    depth: float
    detuning: float


@nb.njit(cache=True)
def _stage_stiffness(stages, fam, out):
    # S = diag(k_force) J(q) at every RK4 stage of the recorded orbit: out (steps, 4, M, M)
    M = fam.k_force.size
    P = fam.weight.size
    iaa, ibb, jac = np.empty(P), np.empty(P), np.empty((M, M))
    for i in range(stages.shape[0]):
        for s in range(4):
            family_jacobian(stages[i, s], fam, iaa, ibb, jac)
            for r in range(M):
                for c in range(M):
                    out[i, s, r, c] = fam.k_force[r] * jac[r, c]


def stage_stiffness(fmap, y, fam) -> np.ndarray:
    """The family block's stiffness at every RK4 stage of one period.

    Parameters
    ----------
    fmap : model.forced.ForcedMap
        The ROM's map (its steps, period, tables and forcing).
    y : (2K,) array
        Axisymmetric state ``(q, q')`` (m, m s-1) at ``t = 0``.
    fam : model.families.Family

    Returns
    -------
    (steps, 4, M, M) array
        ``S = diag(k_force) J(q)`` (s-2) at the stages, the matrices
        :func:`model.families.family_monodromy` meets.
    """
    steps = fmap.steps
    stages = np.empty((steps, 4, fmap.dof))
    stage_coordinates(np.asarray(y, dtype=float), 0.0, fmap.period / steps, steps, fmap.rom.tables,
                      fmap.forcing, stages)
    M = fam.tables.k_force.size
    out = np.empty((steps, 4, M, M))
    _stage_stiffness(stages, fam.tables, out)
    return out


@nb.njit(cache=True, fastmath=True, error_model="numpy")
def scaled_monodromy(stiffness, mean, scale, h, rate, matrix):
    """Monodromy of the block with its modulation scaled, by RK4 along the recorded stages.

    Parameters
    ----------
    stiffness : (steps, 4, M, M) array
        ``S`` at the RK4 stages (:func:`stage_stiffness`, s-2).
    mean : (M, M) array
        ``S_bar`` (:func:`mean_stiffness`, s-2).
    scale : float
        ``s``: the block integrated is ``u'' + (rate + matrix) u' + (S_bar + s (S - S_bar)) u = 0``.
    h : float
        RK4 step (s).
    rate : float
        Scalar damping rate (s-1).
    matrix : (M, M) array
        Damping matrix (s-1), or a ``(0, 0)`` array for none.

    Returns
    -------
    (2M, 2M) array
        ``d (u, u')(T) / d (u, u')(0)``; at ``scale = 1``
        :func:`model.families.family_monodromy`'s block.
    """
    steps = stiffness.shape[0]
    M = mean.shape[0]
    m = 2 * M
    phi = np.eye(m)
    kp = np.empty((4, m, m))
    ps = np.empty((m, m))
    sm = np.empty((M, M))
    ones = np.ones(M)
    for i in range(steps):
        for s in range(4):
            rk4.stage_matrix(phi, kp, s, h, ps)
            for r in range(M):
                for l in range(M):
                    sm[r, l] = mean[r, l] + scale * (stiffness[i, s, r, l] - mean[r, l])
            block_slope(ps, sm, ones, rate, matrix, kp, s)
        rk4.step_matrix(phi, kp, h)
    return phi


def mean_stiffness(stiffness: np.ndarray) -> np.ndarray:
    """``S_bar`` ``(M, M)`` (s-2): the mean of ``S`` over the period from its values at the
    start of each step (``stiffness[:, 0]``), exact for every harmonic that is not a multiple
    of the number of steps."""
    return stiffness[:, 0].mean(axis=0)


def _largest_modulus(stiffness, mean, scale, h, rate, matrix) -> float:
    return float(np.abs(np.linalg.eigvals(scaled_monodromy(stiffness, mean, scale, h, rate, matrix))).max())


def measured_threshold(stiffness, h: float, rate: float, matrix, rtol: float = 1e-6) -> float:
    """Smallest modulation scale ``s`` (``S_bar + s (S - S_bar)``) at which the largest
    Floquet multiplier modulus of the block reaches 1: a geometric scan from
    :data:`SCALE_MIN` by :data:`SCALE_GROWTH` up to :data:`SCALE_MAX`, then bisection of the
    first bracket to ``rtol``.  A window of instability narrower than one step of the scan
    can be missed.

    Parameters
    ----------
    stiffness : (steps, 4, M, M) array
        :func:`stage_stiffness` (s-2).
    h : float
        RK4 step (s).
    rate, matrix
        The damping's scalar rate (s-1) and matrix part (``(M, M)``, s-1, or None).
    rtol : float
        Relative width of the final bracket.

    Returns
    -------
    float
        The threshold scale (1); NaN when the block stays inside the unit circle up to
        :data:`SCALE_MAX`; :data:`SCALE_MIN` when it is already outside there.
    """
    mean = mean_stiffness(stiffness)
    matrix = np.zeros((0, 0)) if matrix is None else np.ascontiguousarray(matrix, dtype=float)
    low = SCALE_MIN
    if _largest_modulus(stiffness, mean, low, h, rate, matrix) >= 1.0:
        return low
    high = low
    while True:
        if high >= SCALE_MAX:
            return float("nan")
        low, high = high, min(high * SCALE_GROWTH, SCALE_MAX)
        if _largest_modulus(stiffness, mean, high, h, rate, matrix) >= 1.0:
            break
    while high - low > rtol * high:
        mid = 0.5 * (low + high)
        if _largest_modulus(stiffness, mean, mid, h, rate, matrix) >= 1.0:
            high = mid
        else:
            low = mid
    return 0.5 * (low + high)


class Resonances(NamedTuple):
    """Averaged thresholds of every resonance ``(i, j, p)``, ``i <= j``, ``p = 1 .. steps/2 - 1``.

    Attributes
    ----------
    scale : (M, M, P) array
        Averaged threshold ``s`` (``inf`` where the harmonic does not couple the pair; NaN
        below the diagonal); index ``[i, j, p - 1]``.
    amplitude : (M, M, P) array
        ``k_ij^(p)``: the cosine amplitude of the modulation (s-2).
    frequencies, rates : (M,) arrays
        ``omega_j`` (rad s-1) and ``alpha_j`` (s-1, RK4's decay included when a step is given)
        of the mean stiffness' modes.
    """

    scale: np.ndarray
    amplitude: np.ndarray
    frequencies: np.ndarray
    rates: np.ndarray


def rk4_decay_rate(omega, h: float):
    """``-ln|R(i omega h)| / h`` (s-1): the decay rate RK4 with step ``h`` (s) adds to an
    undamped oscillation of frequency ``omega`` (rad s-1), ``R(z) = 1 + z + z^2/2 + z^3/6 +
    z^4/24`` (about ``omega^6 h^5 / 144``)."""
    z = 1j * np.asarray(omega, dtype=float) * h
    return -np.log(np.abs(1.0 + z + z**2 / 2 + z**3 / 6 + z**4 / 24)) / h


def averaged_thresholds(stiffness, Omega: float, k_force, rate: float, matrix, h: float = 0.0) -> Resonances:
    """First-order averaging of the block (module docstring) for every resonance.

    Parameters
    ----------
    stiffness : (steps, 4, M, M) array
        :func:`stage_stiffness` (s-2); its values at the start of each step are the samples
        of one period the harmonics are taken from.
    Omega : float
        Forcing frequency (rad s-1).
    k_force : (M,) array
        The family's ``C1 / (Gamma M_j)``: ``S = diag(k_force) J`` with ``J`` symmetric.
    rate, matrix
        The damping's scalar rate and matrix part (None for none), s-1.
    h : float
        RK4 step (s) of the map whose block is described: its numerical decay
        (:func:`rk4_decay_rate`) is added to every mode's rate; 0 for the exact flow.

    Returns
    -------
    Resonances
        Raises ValueError when the mean stiffness has a non-positive eigenvalue.
    """
    samples = stiffness[:, 0]
    N, M = samples.shape[0], samples.shape[1]
    root = np.sqrt(np.asarray(k_force, dtype=float))

    def symmetric(a):  # K^-1/2 a K^1/2, K = diag(k_force): S = K J becomes K^1/2 J K^1/2
        return a * (1.0 / root)[:, None] * root[None, :]

    mean = samples.mean(axis=0)
    sym_mean = symmetric(mean)
    omega2, V = np.linalg.eigh(0.5 * (sym_mean + sym_mean.T))
    if omega2.min() <= 0.0:
        raise ValueError(f"the mean stiffness of the family has a non-positive eigenvalue {omega2.min():.3g} s-2: "
                         "no oscillating modes to average over")
    omega = np.sqrt(omega2)
    damping = rate * np.eye(M) + (0.0 if matrix is None else symmetric(np.asarray(matrix, dtype=float)))
    alpha = 0.5 * np.einsum("ji,jk,ki->i", V, damping, V) + (rk4_decay_rate(omega, h) if h > 0.0 else 0.0)
    modal = np.einsum("ji,njk,kl->nil", V, symmetric(samples - mean), V)  # (N, M, M), symmetric in i, l
    harmonics = np.fft.rfft(modal, axis=0)[1:N // 2] / N  # p = 1 .. N/2 - 1
    amplitude = 2.0 * np.abs(harmonics).transpose(1, 2, 0)  # (M, M, P)
    p = np.arange(1, N // 2)
    sigma = p[None, None, :] * Omega - omega[:, None, None] - omega[None, :, None]
    ai, aj = alpha[:, None, None], alpha[None, :, None]
    total = ai + aj
    with np.errstate(divide="ignore", invalid="ignore"):
        # alpha_i alpha_j (1 + sigma^2 / (alpha_i + alpha_j)^2); without damping its limit sigma^2 / 4
        need = np.where(total > 0.0, ai * aj * (1.0 + sigma**2 / total**2), 0.25 * sigma**2)
        kappa2 = amplitude**2 / (16.0 * omega[:, None, None] * omega[None, :, None])
        scale = np.where(kappa2 > 0.0, np.sqrt(need / kappa2), np.inf)
    scale[np.tril_indices(M, -1)] = np.nan
    return Resonances(scale, amplitude, omega, alpha)


def family_tongue(fmap, y, fam) -> Tongue:
    """The lowest tongue of a family on an orbit: measured and averaged thresholds and the
    resonance the averaging finds lowest.

    Parameters
    ----------
    fmap : model.forced.ForcedMap
    y : (2K,) array
        Axisymmetric state ``(q, q')`` (m, m s-1) on the orbit at ``t = 0``.
    fam : model.families.Family

    Returns
    -------
    Tongue
        Raises ValueError when the family's mean stiffness has a non-positive eigenvalue.
    """
    stiffness = stage_stiffness(fmap, y, fam)
    rate, matrix = fmap.family_damping_terms(fam)
    matrix = None if matrix.size == 0 else matrix
    h = fmap.period / fmap.steps
    res = averaged_thresholds(stiffness, fmap.forcing.Omega, fam.tables.k_force, rate, matrix, h)
    i, j, p = np.unravel_index(np.nanargmin(res.scale), res.scale.shape)
    w = res.frequencies
    return Tongue(measured=measured_threshold(stiffness, h, rate, matrix),
                  averaged=float(res.scale[i, j, p]), modes=np.array([i + 1, j + 1]), harmonic=int(p + 1),
                  frequencies=w[[i, j]], rates=res.rates[[i, j]],
                  depth=float(res.amplitude[i, j, p] / (w[i] * w[j])),
                  detuning=float((p + 1) * fmap.forcing.Omega - w[i] - w[j]))
