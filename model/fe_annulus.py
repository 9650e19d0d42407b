"""The membrane on a two-dimensional finite-element mesh of the annulus: an independent check of
the full model (docs/model.md, "The two-dimensional finite-element check").

Cartesian displacement components on a mesh of the undeformed annulus (scikit-fem): the
deformation gradient's columns are ``a1 = dx/dX``, ``a2 = dx/dY`` in Cartesian components, the
energy ``h int W dA`` with the law's ``W`` of :mod:`model.full.surface` (its functions use only
dot products of the columns, so any orthonormal frame serves), and nothing of the full model's
polar reduction (no Fourier harmonics, no frame terms) is used.  Two element families:

* ``"P2"`` -- quadratic triangles on a quadratic (isoparametric) mesh whose edges follow the
  polar grid ``(r, theta)``, so that both edges are circles to O(h^3): eigenvalues converge
  as ``h^4``;
* ``"Q1"`` -- bilinear quadrilaterals with straight edges, the kind of element of the paper's
  FEM (Abaqus S4R), with a consistent or a lumped (row-sum) mass matrix.

The mesh is structured, ``radial`` elements across and ``circumferential`` around (two
triangles per cell for ``"P2"``).  :func:`solve_fe_prestretch` solves the planar pre-stretch
by Newton on the residual of the energy; :func:`fe_frequencies` the transverse and in-plane
natural frequencies about it, each eigenvector labelled with its wave number ``n`` by the
Fourier content of its displacement on two circles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import (Basis, BilinearForm, ElementQuad1, ElementTriP2, ElementVector, LinearForm,
                   MeshQuad, MeshTri, MeshTri2)
from skfem.helpers import dot

from model.full import surface
from model.params import Membrane
from model.prestretch import _analytic_coef, check_extensibility

ELEMENTS = ("P2", "Q1")
MASSES = ("consistent", "lumped")
GRADINGS = ("logarithmic", "uniform")


@dataclass(frozen=True, eq=False)
class AnnulusMesh:
    """A structured mesh of the undeformed annulus (scaled: ``Re = 1``) and its element."""

    membrane: Membrane
    radial: int
    circumferential: int
    element: str
    grading: str
    mesh: object

    @classmethod
    def build(cls, membrane: Membrane, radial: int, circumferential: int, element: str = "P2",
              grading: str = "logarithmic") -> AnnulusMesh:
        """The mesh; ``grading`` spaces the circles ``"logarithmic"``-ally (finer at the inner
        edge, where the pre-stretch varies fastest) or ``"uniform"``-ly."""
        if grading not in GRADINGS:
            raise ValueError(f"grading = {grading!r} is invalid: must be one of {', '.join(GRADINGS)}")
        if element not in ELEMENTS:
            raise ValueError(f"element = {element!r} is invalid: must be one of {', '.join(ELEMENTS)}")
        if radial < 1 or circumferential < 8:
            raise ValueError(f"(radial, circumferential) = ({radial}, {circumferential}) is invalid: need radial >= 1 "
                             "and circumferential >= 8")
        if grading == "logarithmic":
            r = membrane.delta_o ** np.linspace(1.0, 0.0, radial + 1)
        else:
            r = np.linspace(membrane.delta_o, 1.0, radial + 1)
        theta = 2 * np.pi * np.arange(circumferential) / circumferential
        R, T = np.meshgrid(r, theta, indexing="ij")
        points = np.vstack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel()])
        i, j = np.meshgrid(np.arange(radial), np.arange(circumferential), indexing="ij")
        at = lambda a, b: (a * circumferential + b % circumferential).ravel()  # noqa: E731
        corners = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]
        if element == "Q1":
            return cls(membrane, radial, circumferential, element, grading, MeshQuad(points, np.array(corners)))
        a, b, c, d = corners
        linear = MeshTri(points, np.hstack([np.array([a, b, c]), np.array([a, c, d])]))
        quadratic = MeshTri2.from_mesh(linear)
        # every edge midpoint at the midpoint of its ends in (r, theta): circles stay circles
        ends = linear.p[:, linear.facets]  # (2, 2, facets)
        rad = np.hypot(ends[0], ends[1]).mean(axis=0)
        start = np.arctan2(ends[1, 0], ends[0, 0])
        turn = np.angle(np.exp(1j * (np.arctan2(ends[1, 1], ends[0, 1]) - start)))  # wrapped to (-pi, pi]
        ang = start + 0.5 * turn
        doflocs = quadratic.doflocs.copy()
        doflocs[:, linear.p.shape[1]:] = rad * np.array([np.cos(ang), np.sin(ang)])
        return cls(membrane, radial, circumferential, element, grading, MeshTri2(doflocs, quadratic.t))

    def scalar_element(self):
        return ElementTriP2() if self.element == "P2" else ElementQuad1()

    def basis(self, components: int):
        """The scalar (``components = 1``) or vector basis of the mesh's element."""
        e = self.scalar_element()
        return Basis(self.mesh, e if components == 1 else ElementVector(e, components), intorder=6)


def _columns(grad):
    """``a1``, ``a2`` (``(..., 3)``) of ``x = X + d`` for a planar displacement ``d`` with the
    gradient ``grad[i, j] = d d_i / d X_j`` (shape ``(2, 2, elements, points)``)."""
    zero = np.zeros(grad.shape[2:])
    return (np.stack([1.0 + grad[0, 0], grad[1, 0], zero], axis=-1),
            np.stack([grad[0, 1], 1.0 + grad[1, 1], zero], axis=-1))


@dataclass(frozen=True, eq=False)
class FePrestretch:
    """The pre-stretched state on a mesh: the in-plane displacement ``d`` (scaled) of its vector basis."""

    mesh: AnnulusMesh
    basis: object
    d: np.ndarray
    newton_steps: int

    def nodal_radius(self):
        """``(rho, r)`` (m): the deformed radius at the mesh's nodes on the ray ``theta = 0``."""
        re = self.mesh.membrane.Re
        dofs = self.basis.split_indices()[0]
        on_ray = ray_nodes(self.basis.doflocs[:, dofs])
        rho = self.basis.doflocs[0, dofs[on_ray]]
        return re * rho, re * (rho + self.d[dofs[on_ray]])


def ray_nodes(X) -> np.ndarray:
    """The indices of the nodes ``X`` (``(2, nodes)``, scaled) on the ray ``theta = 0``, by
    increasing radius."""
    on_ray = np.flatnonzero((np.abs(X[1]) < 1e-12) & (X[0] > 0))
    return on_ray[np.argsort(X[0, on_ray])]


def solve_fe_prestretch(mesh: AnnulusMesh) -> FePrestretch:
    """The planar pre-stretch on ``mesh``: ``d = 0`` on the inner edge, ``d = (delta - 1) X`` on
    the outer one, Newton from Eq. (21) on the residual ``int P : grad(delta d) dA``.

    Raises
    ------
    ArithmeticError
        When Newton does not reach a relative step of 1e-12 in 30 steps.
    """
    m = mesh.membrane
    check_extensibility(m)
    law = m.material
    basis = mesh.basis(2)

    at = {}  # P and A at the quadrature points of the current iterate, shared by the forms

    @LinearForm
    def residual(v, w):
        p1, p2 = at["P"]
        return sum(p1[..., i] * v.grad[i, 0] + p2[..., i] * v.grad[i, 1] for i in range(2))

    @BilinearForm
    def tangent(u, v, w):
        return _inplane_tangent(at["A"], u, v)

    X = basis.doflocs
    r = np.hypot(X[0], X[1])
    a, b = _analytic_coef(m.delta, m.delta_o)
    component = np.empty(basis.N, int)
    for c, dofs in enumerate(basis.split_indices()):
        component[dofs] = c
    position = X[component, np.arange(basis.N)]
    d = ((a * r + b / r) / r - 1.0) * position  # Eq. (21) as a displacement: exact on both edges
    boundary = basis.get_dofs().all()
    free = np.setdiff1d(np.arange(basis.N), boundary)
    for step in range(1, 31):
        columns = _columns(basis.interpolate(d).grad)
        at["P"], at["A"] = surface.gradient(law, *columns), surface.hessian(law, *columns)
        K, f = tangent.assemble(basis), residual.assemble(basis)
        delta_d = np.zeros_like(d)
        delta_d[free] = spla.spsolve(K[free][:, free].tocsc(), -f[free])
        d = d + delta_d
        if np.abs(delta_d).max() < 1e-12 * np.abs(d).max():
            return FePrestretch(mesh, basis, d, step)
    raise ArithmeticError(f"FE pre-stretch did not converge at delta = {m.delta}, delta_o = {m.delta_o} on "
                          f"{mesh.radial} x {mesh.circumferential} {mesh.element} elements")


def _inplane_tangent(A, u, v):
    """``grad v : A : grad u`` for planar vector fields (``A`` from :func:`model.full.surface.hessian`,
    component ``3 j + i`` for ``F_ij = dx_i/dX_j``)."""
    return sum(A[..., 3 * j + i, 3 * l + k] * u.grad[k, l] * v.grad[i, j]
               for i in range(2) for j in range(2) for k in range(2) for l in range(2))


def _tangent_moduli(state: FePrestretch):
    """``A`` (``(elements, points, 6, 6)``) at the quadrature points of the state's mesh."""
    return surface.hessian(state.mesh.membrane.material, *_columns(state.basis.interpolate(state.d).grad))


def _wave_numbers(basis, vectors, mesh: AnnulusMesh):
    """The dominant circumferential wave number of each column of ``vectors`` (a field of
    ``basis``, 1 or 2 components) and, for in-plane fields, whether its ``n = 0`` content is
    torsional (tangential) rather than radial: the largest Fourier coefficient of its values
    (the radial and tangential components for a vector field) at the equally spaced vertices
    of two circles of the mesh, their powers summed."""
    nodal = basis.nodal_dofs  # (components, vertices)
    X = mesh.mesh.doflocs[:, :nodal.shape[1]]  # the vertices come first
    radius = np.hypot(X[0], X[1])
    rings = np.unique(np.round(radius, 12))
    radial_power = tangential_power = 0.0
    for target in (0.4, 0.7):  # two circles: a mode with a nodal circle on one shows on the other
        ring = rings[np.argmin(np.abs(rings - (mesh.membrane.delta_o + target * (1 - mesh.membrane.delta_o))))]
        on = np.nonzero(np.abs(radius - ring) < 1e-9)[0]
        angle = np.arctan2(X[1, on], X[0, on])
        on, angle = on[np.argsort(angle)], np.sort(angle)[:, None]
        values = [vectors[nodal[c, on]] for c in range(nodal.shape[0])]
        if len(values) == 2:  # radial and tangential components
            values = [np.cos(angle) * values[0] + np.sin(angle) * values[1],
                      -np.sin(angle) * values[0] + np.cos(angle) * values[1]]
            tangential_power = tangential_power + np.abs(np.fft.rfft(values[1], axis=0)) ** 2
        radial_power = radial_power + np.abs(np.fft.rfft(values[0], axis=0)) ** 2
    n = np.argmax(radial_power + tangential_power, axis=0)
    torsional = (n == 0) & (np.broadcast_to(tangential_power, radial_power.shape)[0] > radial_power[0])
    return n, torsional


def fe_modes(state: FePrestretch, fields: str, count: int, n_max: int = 3, mass: str = "consistent"):
    """Natural frequencies (rad s-1) and mode shapes about the pre-stretched state: ``fields``
    ``"W"`` (transverse) or ``"UV"`` (in-plane).

    Returns
    -------
    dict of int to (numpy.ndarray, numpy.ndarray)
        For each wave number ``n <= n_max`` the ``count`` lowest frequencies whose
        eigenvectors have that wave number (a pair of cos/sin modes counted once; for in-plane
        fields and ``n = 0`` the radial modes, the torsional ones left out), and those
        eigenvectors as columns on the dofs of the basis of ``fields`` (``M``-normalised,
        zero on the edges).

    Raises
    ------
    ValueError
        On a lumped mass with quadratic elements (row sums give no positive mass there), a
        wave number the mesh does not resolve (``2 n_max >= circumferential``), or when the
        mesh has fewer than ``count`` frequencies of some ``n <= n_max``.
    """
    mesh = state.mesh
    if mass not in MASSES:
        raise ValueError(f"mass = {mass!r} is invalid: must be one of {', '.join(MASSES)}")
    if mass == "lumped" and mesh.element != "Q1":
        raise ValueError(f"mass = 'lumped' is invalid for element = {mesh.element!r}: row-sum lumping needs "
                         "linear elements (Q1)")
    if 2 * n_max >= mesh.circumferential:
        raise ValueError(f"n = {n_max} is invalid on {mesh.circumferential} elements around: the mesh resolves "
                         f"wave numbers below {mesh.circumferential / 2:g}")
    basis, K, M = linear_operators(state, fields)
    if mass == "lumped":
        M = sp.diags(np.asarray(M.sum(axis=1)).ravel()).tocsr()
    free = np.setdiff1d(np.arange(basis.N), basis.get_dofs().all())
    Kf, Mf = K[free][:, free].tocsc(), M[free][:, free].tocsc()
    k = (2 * n_max + 2) * count + 8
    while True:  # more eigenpairs until every n <= n_max has its count (higher n interleave)
        k = min(k, free.size - 2)
        found = _by_wave_number(Kf, Mf, k, free, basis, mesh, n_max)
        short = [n for n in range(n_max + 1) if found[n][0].size < count]
        if not short:
            return {n: (found[n][0][:count], found[n][1][:, :count]) for n in range(n_max + 1)}
        if k == free.size - 2:
            raise ValueError(f"count = {count} is invalid: only {found[short[0]][0].size} frequencies of n = "
                             f"{short[0]} on this mesh ({fields})")
        k *= 2


def linear_operators(state: FePrestretch, fields: str):
    """The basis of ``fields`` (``"W"``: scalar, ``"UV"``: in-plane vector), the stiffness
    ``int grad(dx) : A : grad(dx) dA`` about the pre-stretch and the consistent mass
    ``int dx . dx dA`` on it (all dofs, edges included)."""
    A = _tangent_moduli(state)
    if fields == "W":
        basis = state.mesh.basis(1)

        @BilinearForm
        def stiffness(u, v, w):
            return sum(A[..., 3 * j + 2, 3 * l + 2] * u.grad[l] * v.grad[j] for j in range(2) for l in range(2))

        @BilinearForm
        def inertia(u, v, w):
            return u * v
    elif fields == "UV":
        basis = state.mesh.basis(2)

        @BilinearForm
        def stiffness(u, v, w):
            return _inplane_tangent(A, u, v)

        @BilinearForm
        def inertia(u, v, w):
            return dot(u, v)
    else:
        raise ValueError(f"fields = {fields!r} is invalid: must be 'W' or 'UV'")
    return basis, stiffness.assemble(basis), inertia.assemble(basis)


def fe_frequencies(state: FePrestretch, fields: str, count: int, n_max: int = 3, mass: str = "consistent"):
    """Natural frequencies (rad s-1) about the pre-stretched state: ``fields`` ``"W"`` (transverse)
    or ``"UV"`` (in-plane); for each wave number ``n <= n_max`` the ``count`` lowest
    (:func:`fe_modes` without the shapes)."""
    return {n: omega for n, (omega, _) in fe_modes(state, fields, count, n_max, mass).items()}


def _by_wave_number(K, M, k, free, basis, mesh, n_max):
    lam, vec = spla.eigsh(K, k=k, M=M, sigma=0.0, which="LM")
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    full = np.zeros((basis.N, vec.shape[1]))
    full[free] = vec
    n_of, torsional = _wave_numbers(basis, full, mesh)
    omega = np.sqrt(mesh.membrane.C1 / (mesh.membrane.Gamma * mesh.membrane.Re**2) * lam)
    out = {}
    for n in range(n_max + 1):
        at = np.flatnonzero((n_of == n) & ~torsional)  # n = 0: the radial modes (torsional ones apart)
        if n > 0 and at.size:  # the cos/sin pair of a mode: equal to round-off on the symmetric mesh
            at = at[np.concatenate([[True], np.diff(omega[at]) > 1e-7 * omega[at][1:]])]
        out[n] = (omega[at], full[:, at])
    return out
