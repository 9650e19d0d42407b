"""The full model of the membrane: the mid-surface displacement ``(u, v, w)`` with in-plane
inertia (docs/model.md, "The full model").

Unlike the ROM it drops nothing: the material point ``(rho, theta)`` of the undeformed
annulus moves to ``r e_r + v e_theta + w e_z`` and the energy is the law's ``W`` of the
mid-surface metric, exact.  Its radial discretisation is a Legendre-Galerkin basis
(:mod:`model.full.radial`), complete and converging spectrally with its order; the
circumferential dependence is one Fourier harmonic per field for the linear problems.

* :mod:`model.full.surface` -- the energy density of the deformed mid-surface and its first
  and second derivatives in the surface's deformation gradient, for any law;
* :mod:`model.full.radial` -- the radial basis and its quadrature;
* :mod:`model.full.static` -- the pre-stretch as the minimum of the axisymmetric energy;
* :mod:`model.full.linear` -- transverse and in-plane natural frequencies per wave number;
* :mod:`model.full.axisymmetric` (compiled loops in :mod:`model.full.axisymmetric_kernels`) --
  axisymmetric motion ``(u, w)``: energy, force, tangent, free motion.
"""
