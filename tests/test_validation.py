"""The validation report generator: missing result files and the branch interpolation."""

import numpy as np

from sweep import validation


def test_missing_results_name_the_jobs(tmp_path):
    lines = (validation.section_backbone_modes(tmp_path) + validation.section_continuation_bruteforce(tmp_path)
             + validation.section_basins(tmp_path) + validation.section_backbone_limits(tmp_path))
    text = "\n".join(lines)
    for job in ("fig09-modes", "fig15-bifurcation-p0", "fig15-bruteforce", "fig19-basins",
                "fig10-11-backbone", "fig12-inner-radius"):
        assert f"`jobs/{job}.toml`" in text
    assert validation.section_provenance(tmp_path)[-2] == "|---|---|---|---|"


def test_stable_amplitudes_on_an_s_curve():
    # x = a^3 - a: stable where dx/da > 0 (|a| > 1/sqrt(3)); at x = 0 the stable roots are +-1.
    a = np.linspace(-1.5, 1.5, 3000)
    x = a**3 - a
    stable = (3 * a**2 - 1 > 0).astype(np.int8)
    found = np.sort(validation._stable_amplitudes(np.append(x, np.nan), np.append(a, np.nan),
                                                  np.append(stable, -1), 0.0))
    assert np.allclose(found, [-1.0, 1.0], atol=1e-6)
