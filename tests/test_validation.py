"""The validation report generator: missing result files."""

from sweep import validation


def test_missing_results_name_the_jobs(tmp_path):
    lines = (validation.section_backbone_modes(tmp_path) + validation.section_continuation_bruteforce(tmp_path)
             + validation.section_basins(tmp_path) + validation.section_backbone_limits(tmp_path)
             + validation.section_cusp(tmp_path) + validation.section_basins_modes(tmp_path))
    text = "\n".join(lines)
    for job in ("fig09-modes", "fig15-bifurcation-p0", "fig15-bruteforce", "fig19-basins",
                "fig10-11-backbone", "fig12-inner-radius", "fig17-cusp", "fig16-17-damping",
                "fig19a-basins-modes"):
        assert f"`jobs/{job}.toml`" in text
    assert validation.section_provenance(tmp_path)[-2] == "|---|---|---|---|"
