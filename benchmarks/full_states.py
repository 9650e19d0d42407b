"""States of the full model that its benchmarks start from."""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigh

from model.full.axisymmetric import AxisymmetricFull
from model.full.linear import stiffness_mass


def first_mode_coordinates(model: AxisymmetricFull, deflection: float) -> np.ndarray:
    """The coordinates ``(U, W)`` (over ``Re``) of a deflection ``deflection`` (m) at
    ``rho = 0.5 Re`` along the first transverse mode, with the in-plane displacement it carries
    quasi-statically (:meth:`AxisymmetricFull.relaxed`)."""
    K, M = stiffness_mass(model.state, 0, "W")
    mode = eigh(K, M)[1][:, 0]
    mode /= model.state.basis.evaluate(mode, np.array([0.5]))[0][0]
    return model.relaxed(deflection / model.membrane.Re * mode)
