"""Damping laws: how a model's velocities are damped (docs/model.md, "Damping laws").

A law is a small frozen record of its constants.  Given a model's linearisation about its
rest state, the mass matrix ``M`` and the tangent stiffness ``K0`` of the pre-stretched
membrane in the model's coordinates (``M q'' + K0 q = 0``), it yields the damping of the
equations of motion in acceleration form, ``q'' = ... - D q'``, split as

    D = rate I + matrix

so that the paper's mass-proportional damping stays a scalar in every kernel (``matrix``
empty: the kernels skip it, bit for bit the arithmetic of a scalar rate) and any other law
adds one matrix-vector product per stage (:mod:`model.damping_kernels`, the one home of
that term in the kernels).

Laws (constants per unit undeformed area where they are pressures):

* :class:`Viscous` -- the paper's viscous pressure ``-c w_t``: ``C = (c / (Gamma h)) M``,
  every mode decays at ``c / (2 Gamma h)`` whatever its frequency (damping ratio
  ``zeta_j = c / (2 Gamma h omega_j)``);
* :class:`Rayleigh` -- ``C = alpha M + beta K0``: ``zeta_j = alpha / (2 omega_j) + beta
  omega_j / 2``;
* :class:`Modal` -- the ratio ``zeta_j`` of each linear mode given (one for every mode or
  one per mode): ``C = M V diag(2 zeta_j omega_j) V^T M`` with ``K0 V = M V Omega^2``,
  ``V^T M V = I``.

A one-coordinate model folds its whole damping into the scalar rate (its one-mode fast
paths take a scalar).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field, fields

import numpy as np

from .params import ParameterError

#: The empty damping matrix: a law that is a scalar rate (the kernels test its size).
NO_MATRIX = np.zeros((0, 0))


def _constant(units: str, long_name: str):
    return field(default=0.0, metadata={"units": units, "long_name": long_name})


def _check(record, name: str, value) -> float:
    if isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if not isinstance(value, float) or not math.isfinite(value) or value < 0.0:
        units = next(f.metadata["units"] for f in fields(record) if f.name == name)
        raise ParameterError(name, value, "a finite number >= 0" + ("" if units == "1" else f" ({units})"))
    return value


@dataclass(frozen=True)
class DampingLaw:
    """Base of the damping laws: constants as float fields with ``units`` and ``long_name``
    metadata (the job files' grid keys and the result files' attributes come from them)."""

    #: The job files' name of the law (``[damping] law``).
    name = ""

    def __post_init__(self):
        for f in fields(self):
            object.__setattr__(self, f.name, _check(self, f.name, getattr(self, f.name)))

    def replaced(self, name: str, value: float) -> DampingLaw:
        """The same law with constant ``name`` set to ``value``, not validated: a
        continuation corrector may step slightly outside the physical range (job files
        validate what users give, through the constructor)."""
        if name not in self.parameters():
            raise ValueError(f"parameter = {name!r} is invalid: the {self.name} damping law has "
                             + ", ".join(self.parameters()))
        new = copy.copy(self)
        object.__setattr__(new, name, float(value))
        return new

    @classmethod
    def parameters(cls) -> tuple[str, ...]:
        """Names of the law's constants."""
        return tuple(f.name for f in fields(cls))

    def terms(self, mass: np.ndarray, stiffness: np.ndarray, mass_per_area: float,
              order: np.ndarray | None = None) -> tuple[float, np.ndarray]:
        """``(rate, matrix)`` of ``D = rate I + matrix`` for a model with mass matrix ``mass``
        and tangent stiffness ``stiffness`` (both ``(K, K)``, symmetric, ``mass`` positive).

        Parameters
        ----------
        mass, stiffness : (K, K) arrays
            ``M`` and ``K0`` in any common scale (only ``M^-1 K0`` and ``M``-orthonormal
            modes enter).
        mass_per_area : float
            ``Gamma h`` (kg m-2), the scale of a viscous pressure.
        order : (K,) int array, optional
            For per-mode constants: ``order[i]`` is the coordinate whose mode takes the
            ``i``-th constant (default: by increasing frequency).

        Returns
        -------
        rate : float
            The mass-proportional part (s-1).
        matrix : (K, K) array
            The rest (s-1), :data:`NO_MATRIX` when zero or when ``K == 1`` (folded into
            ``rate``).
        """
        rate, matrix = self._terms(np.asarray(mass, float), np.asarray(stiffness, float), mass_per_area, order)
        if matrix.shape[0] == 1:
            rate, matrix = rate + float(matrix[0, 0]), NO_MATRIX
        elif not np.any(matrix):
            matrix = NO_MATRIX
        return float(rate), np.ascontiguousarray(matrix)

    def _terms(self, mass, stiffness, mass_per_area, order):
        raise NotImplementedError


@dataclass(frozen=True)
class Viscous(DampingLaw):
    """The paper's viscous pressure ``-c w_t`` per unit undeformed area (mass-proportional).

    Parameters
    ----------
    c : float
        N s m-3, >= 0; the equations of motion see the rate ``c / (Gamma h)`` (s-1).
    """

    name = "viscous"
    c: float = _constant("N s m-3", "viscous damping coefficient per unit undeformed area")

    def _terms(self, mass, stiffness, mass_per_area, order):
        return self.c / mass_per_area, NO_MATRIX


@dataclass(frozen=True)
class Rayleigh(DampingLaw):
    """Rayleigh damping ``C = alpha M + beta K0`` (``K0``: tangent stiffness of the
    pre-stretched rest state).

    Parameters
    ----------
    alpha : float
        Mass-proportional coefficient (s-1), >= 0.
    beta : float
        Stiffness-proportional coefficient (s), >= 0.
    """

    name = "rayleigh"
    alpha: float = _constant("s-1", "mass-proportional Rayleigh damping coefficient")
    beta: float = _constant("s", "stiffness-proportional Rayleigh damping coefficient")

    def _terms(self, mass, stiffness, mass_per_area, order):
        return self.alpha, self.beta * np.linalg.solve(mass, stiffness)


@dataclass(frozen=True)
class Modal(DampingLaw):
    """A damping ratio per linear mode.

    Parameters
    ----------
    zeta : float or tuple of float
        Ratio (1) of every mode, or one per mode, >= 0.  Per mode: in the order of the
        model's coordinates (a ROM's mode set: the linear mode dominated by each basis
        function), or of increasing frequency where a model gives no order.
    """

    name = "modal"
    zeta: float | tuple[float, ...] = _constant("1", "modal damping ratio")

    def __post_init__(self):
        value = self.zeta
        if isinstance(value, (list, tuple, np.ndarray)):
            if len(value) == 0:
                raise ParameterError("zeta", list(value), "a number >= 0 or a non-empty list of them")
            value = tuple(_check(self, "zeta", v) for v in value)
            object.__setattr__(self, "zeta", value[0] if len(value) == 1 else value)
        else:
            object.__setattr__(self, "zeta", _check(self, "zeta", value))

    def ratios(self, count: int) -> np.ndarray:
        """The ratio of each of ``count`` modes."""
        if isinstance(self.zeta, tuple):
            if len(self.zeta) != count:
                raise ParameterError("zeta", list(self.zeta), f"one ratio for every mode or exactly {count} "
                                     f"(one per mode of this model)")
            return np.array(self.zeta)
        return np.full(count, self.zeta)

    def _terms(self, mass, stiffness, mass_per_area, order):
        import scipy.linalg  # here: the job files' validation imports this module, not scipy

        lam, vec = scipy.linalg.eigh(stiffness, mass)  # V^T M V = I, ascending
        K = lam.size
        zeta = np.empty(K)
        if order is None:
            zeta[:] = self.ratios(K)
        else:
            zeta[match_modes(vec, mass, order)] = self.ratios(K)
        omega = np.sqrt(np.maximum(lam, 0.0))
        return 0.0, (vec * (2.0 * zeta * omega)) @ (vec.T @ mass)


def match_modes(vectors: np.ndarray, mass: np.ndarray, order: np.ndarray) -> np.ndarray:
    """Index of the eigenvector (column of ``vectors``) dominated by each coordinate of
    ``order``: ``out[i]`` is the mode whose largest ``M``-weighted component is coordinate
    ``order[i]``.

    Raises
    ------
    ValueError
        If two coordinates dominate the same mode (the basis is too far from the modes
        for per-mode ratios in basis order).
    """
    weight = np.abs(vectors) * np.sqrt(np.abs(np.diag(mass)))[:, None]
    dominant = np.argmax(weight, axis=0)  # coordinate of each mode
    mode_of = {int(c): j for j, c in enumerate(dominant)}
    if len(mode_of) != vectors.shape[1]:
        raise ValueError("zeta per mode is ambiguous here: two linear modes are dominated by the same basis "
                         "function; give one ratio for every mode")
    return np.array([mode_of[int(c)] for c in order])


#: Laws by their job-file names.
LAWS: dict[str, type[DampingLaw]] = {law.name: law for law in (Viscous, Rayleigh, Modal)}


def parameter_info(name: str) -> tuple[type[DampingLaw], str, str]:
    """The law holding constant ``name`` and the constant's units and long name.

    Raises
    ------
    KeyError
        If no law has a constant ``name``.
    """
    for law in LAWS.values():
        for f in fields(law):
            if f.name == name:
                return law, f.metadata["units"], f.metadata["long_name"]
    raise KeyError(name)
