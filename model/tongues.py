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
(integrated with the map's RK4 steps along the orbit's recorded stages): the family is
unstable at the point when it is below 1.

The **averaged threshold** (:func:`averaged_thresholds`) is first-order averaging
(Nayfeh and Mook, *Nonlinear Oscillations*, Sec. 5.7).  In the modes ``x`` of the mean
stiffness (``S_bar`` made symmetric by ``diag(k_force)^(-1/2)``: frequencies ``omega_j``,
decay rates ``alpha_j`` the diagonal of the damping in those modes over two), the modulation
is a Fourier series ``sum_p k_ij^(p) cos(p Omega t + phi_ij^(p))``.  A resonance
``p Omega ~ omega_i + omega_j`` (``i = j``: the principal tongue of one mode; ``i != j``:
a combination tongue) is unstable, by averaging, when::

    (s k_ij)^2 / (16 omega_i omega_j) > alpha_i alpha_j (1 + sigma^2 / (alpha_i + alpha_j)^2),
    sigma = p Omega - omega_i - omega_j.

At exact tuning and equal rates this is ``s eps_ij > 4 alpha / sqrt(omega_i omega_j)`` with the
modulation depth ``eps_ij = k_ij / (omega_i omega_j)``; for one mode the textbook
``eps > 4 alpha / omega`` of ``q'' + 2 alpha q' + omega^2 (1 + eps cos 2 omega t) q = 0``.
Under the viscous pressure every ``alpha_j`` is the same ``c / (2 Gamma h)``, so the
threshold falls as ``1 / omega``: each radial mode added to a family can bring a tongue easier
to reach.  Under a constant modal ratio ``alpha_j = zeta omega_j`` and the threshold is
``4 zeta`` whatever the frequency.

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
#: Smallest modulation scale searched; the scan grows it by :data:`SCALE_GROWTH` per step.
SCALE_MIN = 1e-3
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
        ``alpha_i``, ``alpha_j`` (s-1).
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
    """The family block's stiffness ``S = diag(k_force) J(q)`` (s-2) at the four RK4 stages
    of every step of one period from the axisymmetric state ``y`` of ``fmap``
    (:class:`model.forced.ForcedMap`): ``(steps, 4, M, M)``, the matrices
    :func:`model.families.family_monodromy` meets."""
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
    """Monodromy ``(2M, 2M)`` of ``u'' + (rate + matrix) u' + S_s(t) u = 0`` with
    ``S_s = mean + scale (S - mean)``, ``S`` at the RK4 stages ``stiffness`` ``(steps, 4, M, M)``
    and step ``h`` (s).  ``matrix`` ``(M, M)`` (s-1) or a ``(0, 0)`` array for none.  At
    ``scale = 1`` it is :func:`model.families.family_monodromy`'s block."""
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
    """Mean of ``S`` over the period from its values at the start of each step (``(M, M)``,
    s-2): exact for the harmonics below half the number of steps."""
    return stiffness[:, 0].mean(axis=0)


def _largest_modulus(stiffness, mean, scale, h, rate, matrix) -> float:
    return float(np.abs(np.linalg.eigvals(scaled_monodromy(stiffness, mean, scale, h, rate, matrix))).max())


def measured_threshold(stiffness, h: float, rate: float, matrix, rtol: float = 1e-6) -> float:
    """Smallest modulation scale ``s`` (``S_bar + s (S - S_bar)``) at which the largest
    Floquet multiplier modulus of the block reaches 1: a geometric scan from
    :data:`SCALE_MIN` by :data:`SCALE_GROWTH` up to :data:`SCALE_MAX`, then bisection of the
    first bracket to ``rtol``.  NaN when the block stays inside the unit circle up to
    :data:`SCALE_MAX`; :data:`SCALE_MIN` when it is already outside there.

    Parameters
    ----------
    stiffness : (steps, 4, M, M) array
        :func:`stage_stiffness` (s-2).
    h : float
        RK4 step (s).
    rate, matrix
        The damping's scalar rate (s-1) and matrix part (``(M, M)``, s-1, or None).
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
        ``omega_j`` (rad s-1) and ``alpha_j`` (s-1) of the mean stiffness' modes.
    """

    scale: np.ndarray
    amplitude: np.ndarray
    frequencies: np.ndarray
    rates: np.ndarray


def averaged_thresholds(stiffness, Omega: float, k_force, rate: float, matrix) -> Resonances:
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
    """
    samples = stiffness[:, 0]
    N, M = samples.shape[0], samples.shape[1]
    root = np.sqrt(np.asarray(k_force, dtype=float))
    to_sym = lambda a: a * (1.0 / root)[:, None] * root[None, :]  # K^-1/2 A K^1/2
    mean = samples.mean(axis=0)
    sym_mean = to_sym(mean)
    omega2, V = np.linalg.eigh(0.5 * (sym_mean + sym_mean.T))
    if omega2.min() <= 0.0:
        raise ValueError(f"the mean stiffness of the family has a non-positive eigenvalue {omega2.min():.3g} s-2: "
                         "no oscillating modes to average over")
    omega = np.sqrt(omega2)
    damping = rate * np.eye(M) + (0.0 if matrix is None else to_sym(np.asarray(matrix, dtype=float)))
    alpha = 0.5 * np.einsum("ji,jk,ki->i", V, damping, V)
    modal = np.einsum("ji,njk,kl->nil", V, to_sym(samples - mean), V)  # (N, M, M), symmetric in i, l
    harmonics = np.fft.rfft(modal, axis=0)[1:N // 2] / N  # p = 1 .. N/2 - 1
    amplitude = 2.0 * np.abs(harmonics).transpose(1, 2, 0)  # (M, M, P)
    p = np.arange(1, N // 2)
    sigma = p[None, None, :] * Omega - omega[:, None, None] - omega[None, :, None]
    ai, aj = alpha[:, None, None], alpha[None, :, None]
    need = ai * aj * (1.0 + sigma**2 / (ai + aj)**2)
    kappa2 = amplitude**2 / (16.0 * omega[:, None, None] * omega[None, :, None])
    with np.errstate(divide="ignore"):
        scale = np.sqrt(need / kappa2)
    scale[np.tril_indices(M, -1)] = np.nan
    return Resonances(scale, amplitude, omega, alpha)


def family_tongue(fmap, y, fam) -> Tongue:
    """The lowest tongue of family ``fam`` (:class:`model.families.Family`) on the orbit of
    ``fmap`` (:class:`model.forced.ForcedMap`) through ``y``: measured and averaged
    thresholds and the resonance the averaging finds lowest."""
    stiffness = stage_stiffness(fmap, y, fam)
    rate, matrix = fmap.family_damping_terms(fam)
    matrix = None if matrix.size == 0 else matrix
    res = averaged_thresholds(stiffness, fmap.forcing.Omega, fam.tables.k_force, rate, matrix)
    i, j, p = np.unravel_index(np.nanargmin(res.scale), res.scale.shape)
    w = res.frequencies
    return Tongue(measured=measured_threshold(stiffness, fmap.period / fmap.steps, rate, matrix),
                  averaged=float(res.scale[i, j, p]), modes=np.array([i + 1, j + 1]), harmonic=int(p + 1),
                  frequencies=w[[i, j]], rates=res.rates[[i, j]],
                  depth=float(res.amplitude[i, j, p] / (w[i] * w[j])),
                  detuning=float((p + 1) * fmap.forcing.Omega - w[i] - w[j]))
