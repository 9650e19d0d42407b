"""Branch switching at a symmetry-breaking branch point onto the asymmetric branch.

At a branch point of family ``n`` (:mod:`model.families`; a real multiplier of the family's
block is 1) asymmetric periodic responses bifurcate from the axisymmetric branch.  They live
in the mixed model the map's ``perturbed_family`` gives (:class:`model.protocol.PerturbedFamily`):
the ROM of the axisymmetric modes plus the family's cosine modes (2-D quadrature,
:func:`model.rom.build_rom`), or the full model on the circumferential harmonics ``0, n, 2n``
(:mod:`model.full.harmonic`); the sine companions give their rotated copies, by the O(2)
symmetry.  The new branch is followed in that mixed model by
:func:`model.continuation.continue_orbits`, started at the branch point with a first step
along the null vector of the family's block ``Phi_n - I`` at fixed parameter (the standard
switching at a pitchfork: the tangent of the bifurcating branch has no parameter component
there).

Its stability is that of the mixed model: within the reflection-symmetric subspace of the
cosine modes (harmonics).  The multiplier 1 of rotations along the orbit family and the
instabilities toward travelling waves need the sine companions (the ROM's ``n < 0`` in
:func:`model.rom.build_rom`, :mod:`model.waves`).

The axisymmetric block has branch points of its own: a response symmetric in time,
``q(t + T/2) = -q(t)`` (the transverse force is odd in ``w``), gives way to a pair of responses
without that symmetry where a real multiplier of ``Phi`` passes +1 without a fold (docs/model.md,
"Bifurcation test functions").  They stay axisymmetric and in the same map:
:func:`follow_time_symmetry_breaking` switches onto them along the null vector of ``Phi - I``,
with any map of the protocol (the ROM's or the full model's) and its families.
"""

from __future__ import annotations

import numpy as np

from .continuation import Branch, continue_orbits
from .families import Family, embedded


def null_vector(phi) -> np.ndarray:
    """The unit null vector of ``phi - I`` at a branch point: the (real) eigenvector of the
    monodromy block ``phi``'s multiplier closest to 1."""
    mu, vec = np.linalg.eig(phi)
    v = np.real(vec[:, np.argmin(np.abs(mu - 1.0))])
    return v / np.linalg.norm(v)


def null_direction(fmap, state, family) -> np.ndarray:
    """The unit null vector ``(u, u')`` of ``Phi_n - I`` at the orbit ``state`` (``fmap``: a map
    with the capability ``family_monodromy``, :mod:`model.protocol`)."""
    return null_vector(fmap.family_monodromy(state, family))


def follow_bifurcated_branch(fmap, family, parameter: str, start: float, stop: float, state, value: float,
                             **options) -> tuple[Branch, object, np.ndarray]:
    """The asymmetric branch bifurcating at the branch point ``(state, value)`` of ``family``.

    Parameters
    ----------
    fmap : StroboscopicMap
        The map of the axisymmetric model (its continued parameter is overridden), with the
        capabilities ``family_monodromy`` and ``perturbed_family`` (:mod:`model.protocol`):
        the ROM's :class:`model.forced.ForcedMap` or the full model's
        :class:`model.full.forced.ForcedFull`.
    family
        The family whose multiplier is 1 at the point.
    parameter, start, stop
        As for :func:`model.continuation.continue_orbits`; ``value`` must lie in the range.
    state : (2Ka,) array
        The axisymmetric orbit at the branch point.
    options
        Step and size arguments of :func:`model.continuation.continue_orbits`.

    Returns
    -------
    branch : Branch
        In the mixed model's coordinates (:attr:`model.protocol.PerturbedFamily.fmap`: the
        ROM's axisymmetric modes then the family's cosine modes; the full model's harmonics
        ``0, n, 2n``).
    fmap_mixed
        The map of the mixed model (at ``value``).
    asymmetric_amplitude : (N,) array
        ``max_t |w_asym(rho_probe, 0, t)|`` (m) along the branch: the family's part of the
        displacement at the probe.
    """
    at = fmap.varied(parameter, value)
    v = null_direction(at, state, family)
    mixed = at.perturbed_family(family)
    K, A = mixed.fmap.dof, len(mixed.asymmetric)
    y0 = embedded(state, K)
    direction = np.zeros(2 * K)
    direction[list(mixed.asymmetric)] = v[:A]
    direction[[K + i for i in mixed.asymmetric]] = v[A:]
    branch = continue_orbits(mixed.fmap, parameter, start, stop, switch=(y0, value, direction), **options)
    branch.family[0] = family.n  # the first point is the branch point of this family
    amp = np.array([mixed.asymmetric_map.varied(parameter, lam).amplitude(y)
                    for lam, y in zip(branch.value, branch.state)])
    return branch, mixed.fmap, amp


def follow_time_symmetry_breaking(fmap, parameter: str, start: float, stop: float, state, value: float,
                                  families=(), **options) -> Branch:
    """The axisymmetric responses without the half-period symmetry that bifurcate at the
    branch point ``(state, value)`` of the axisymmetric block of ``fmap``'s branch.

    Parameters
    ----------
    fmap : StroboscopicMap
        The map the branch was continued with (its continued parameter is overridden).
    parameter, start, stop
        As for :func:`model.continuation.continue_orbits`; ``value`` must lie in the range.
    state : (n,) array
        The orbit at the branch point (the map's state).
    families : sequence
        The families whose multipliers are followed along the new branch, as on the old one.
    options
        Step and size arguments of :func:`model.continuation.continue_orbits`.

    Returns
    -------
    Branch
        In ``fmap``'s coordinates, from the branch point (its first point) along the null
        vector of ``Phi - I`` (the eigenvector of the multiplier closest to 1) at fixed
        parameter, until the parameter leaves ``[start, stop]`` or ``max_points``.
    """
    _, phi = fmap.varied(parameter, value).monodromy(np.asarray(state, dtype=float))
    return continue_orbits(fmap, parameter, start, stop, families=families,
                           switch=(state, value, null_vector(phi)), **options)
