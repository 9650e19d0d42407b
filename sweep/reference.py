"""Reference values printed in the paper (Goncalves, Soares & Pamplona, IJSS 2011).

Typed from the paper's Tables 1-2 (rad/s, ``Re = 1 m``); used by the validation report
and by the tests.  Nothing here is computed.
"""

#: Table 1, lowest frequency (m = 1, n = 0): (delta, delta_o) -> (FEM, AN, App.1, App.2).
TABLE1 = {
    (1.1, 0.2): (32.512, 32.307, 32.497, 32.499),
    (1.5, 0.2): (45.716, 45.561, 45.768, 45.686),
    (2.0, 0.2): (47.431, 47.113, 47.149, 47.150),
    (1.1, 0.3): (38.827, 38.200, 38.608, 38.591),
    (1.5, 0.3): (53.465, 53.390, 53.132, 53.129),
    (2.0, 0.3): (54.926, 54.423, 54.585, 54.585),
}

#: Table 2, higher modes (m = 1): (delta_o, n, delta) -> (AN, FEM).
TABLE2 = {
    (0.2, 1, 1.1): (34.751, 35.725), (0.2, 1, 1.5): (50.293, 50.788), (0.2, 1, 2.0): (52.244, 52.513),
    (0.2, 2, 1.1): (42.840, 43.491), (0.2, 2, 1.5): (62.000, 62.349), (0.2, 2, 2.0): (64.406, 64.615),
    (0.3, 1, 1.1): (40.607, 40.984), (0.3, 1, 1.5): (55.873, 56.795), (0.3, 1, 2.0): (58.042, 58.440),
    (0.3, 2, 1.1): (46.879, 46.796), (0.3, 2, 1.5): (64.950, 65.629), (0.3, 2, 2.0): (67.471, 67.725),
}

#: Tolerances (docs/model.md, "Reference values"): Galerkin vs App.1/App.2, vs FEM, and
#: Eq. (28) vs AN (relative).
TOL_APP, TOL_FEM, TOL_AN = 1e-3, 8e-3, 2.5e-2
