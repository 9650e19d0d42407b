"""The neo-Hookean ROM of Eq. (31) written plainly in numpy, for scipy's integrators: an
independent right-hand side against the compiled kernels of :mod:`model.rom`."""

import numpy as np


def plain_rhs(rom):
    """``f(t, y) = (q', -k_force g(q))``: the undamped, unforced ROM (``y = (q, q')``)."""
    t, K = rom.tables, rom.dof

    def f(_, y):
        q = y[:K]
        a, b = q @ t.b_rho, q @ t.b_theta
        delta = t.hoop2 * (t.radial2 + a * a) + t.radial2 * b * b * t.inv_rho2  # det of the metric
        g = (t.b_rho @ (2 * a * (1 - t.hoop2 / delta**2) * t.weight)
             + t.b_theta @ (2 * b * t.inv_rho2 * (1 - t.radial2 / delta**2) * t.weight))
        return np.concatenate([y[K:], -t.k_force * g])

    return f
