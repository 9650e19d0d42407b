"""The validation report generator: missing result files, and the jobs it reads."""

import ast
from pathlib import Path

import numpy as np
import pytest

from sweep import paper, validation
from sweep.jobspec import load_job

JOBS = Path(__file__).resolve().parents[1] / "jobs"


def test_missing_results_name_the_jobs(tmp_path):
    lines = (validation.section_backbone_modes(tmp_path) + validation.section_continuation_bruteforce(tmp_path)
             + validation.section_basins(tmp_path) + validation.section_backbone_limits(tmp_path)
             + validation.section_cusp(tmp_path) + validation.section_basins_modes(tmp_path)
             + validation.section_linear_convergence(tmp_path) + validation.section_forced_modes(tmp_path)
             + validation._family_convergence(tmp_path) + validation.section_family_check(tmp_path)
             + validation.section_full_model(tmp_path) + validation.section_fe_check(tmp_path)
             + validation.section_full_backbone(tmp_path) + validation.section_bruteforce_diagram(tmp_path)
             + validation.section_full_forced(tmp_path) + validation.section_full_families(tmp_path)
             + validation.section_full_fig14a(tmp_path) + validation.section_full_fig14a_light(tmp_path)
             + validation.section_full_fig14a_damping(tmp_path)
             + validation.section_tongues(tmp_path) + validation.section_family_orbit(tmp_path)
             + validation.section_waves(tmp_path) + validation.section_fig08(tmp_path)
             + validation.section_fe_motion(tmp_path) + validation.section_full_basins(tmp_path)
             + validation.section_held_families(tmp_path) + validation.section_time_symmetry(tmp_path)
             + validation.section_full_family_check(tmp_path) + validation.section_full_switching(tmp_path)
             + validation.section_full_rotating(tmp_path))
    text = "\n".join(lines)
    for job in ("fig09-modes", "fig15-bifurcation-p0", "fig15-bruteforce", "fig19-basins",
                "fig10-11-backbone", "fig12-inner-radius", "fig17-cusp", "fig16-17-damping",
                "fig19a-basins-modes", "fig19a-full-basins",  # (their brute-force checks are read only when they are there)
                *(name for name in paper.VALIDATION_JOBS if not name.startswith(("validation/fig19a-basins-brute",
                                                                               "validation/fig19a-full-basins-brute")))):
        assert f"`jobs/{job}.toml`" in text
    assert validation.section_provenance(tmp_path)[-2] == "|---|---|---|---|"


def test_a_section_regenerated_alone_lands_where_the_whole_report_puts_it(tmp_path):
    whole = validation.build_report(tmp_path)
    blocks = validation._blocks(whole)
    title = validation.section_full_backbone(tmp_path)[0]
    without = "\n".join(line for b in blocks if b[0] != title for line in b) + "\n"
    assert without != whole
    assert validation.update_report(without, tmp_path, ["full_backbone"]) == whole
    assert validation.update_report(whole, tmp_path, ["table1", "linear_convergence"]) == whole
    # a result file of the old table that the results directory does not hold stays listed,
    # unless its job file is gone
    row = "| `table2.nc` | as committed | 1 / 1 | 0.1.0 |"
    gone = "| `validation/renamed.nc` | as committed | 1 / 1 | 0.1.0 |"
    kept = validation.update_report(whole.replace("|---|---|---|---|\n", f"|---|---|---|---|\n{row}\n{gone}\n"),
                                    tmp_path, ["table2"])
    assert row in kept.split("\n")
    assert gone not in kept  # its job file does not exist: a renamed job's stale row


def test_the_report_computes_nothing_from_the_model():
    # every number of docs/validation.md comes from a result file: of the model the report
    # imports only functions of arrays (branch bookkeeping, the attractor matching of the
    # brute-force check), no model, map or solver
    tree = ast.parse(Path(validation.__file__).read_text())
    imported = {(node.module, alias.name) for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
                and (node.module or "").startswith("model") for alias in node.names}
    imported |= {(alias.name, "") for node in ast.walk(tree) if isinstance(node, ast.Import)
                 for alias in node.names if alias.name.startswith("model")}
    # and of the sweep, only constants, selections and the result files' attributes
    through_sweep = {(node.module, alias.name) for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
                     and (node.module or "").startswith("sweep.") for alias in node.names}
    assert through_sweep <= {("sweep.analyses.branch_features", "CURVE_DS_MAX"), ("sweep.analyses.mode_sets", "select"),
                             ("sweep.analyses.backbone", "FE_AROUND"), ("sweep.analyses.backbone", "FE_PERIODS"),
                             ("sweep.analyses.backbone", "FE_HARMONICS"), ("sweep.analyses.backbone", "FE_SAMPLES"),
                             ("sweep.analyses.backbone", "FE_MORE_HARMONICS"), ("sweep.analyses.backbone", "FE_MORE_RADIAL"),
                             ("sweep.analyses.branch_features", "CHECK_MAX_PERIOD"),
                             ("sweep.analyses.branch_features", "CHECK_SIGMAS"),
                             ("sweep.analyses.branch_features", "GROWTH_LIMIT"),
                             ("sweep.errors", "RunError"), ("sweep.storage.netcdf", "run_attributes")}
    assert imported <= {("model.continuation", name) for name in (
        "KIND_LABELS", "BRANCH_POINT", "NEIMARK_SACKER", "FOLD", "resonant_end", "stable_amplitudes_at",
        "unstable_intervals", "unstable_points")} | {("model", "attractors"), ("model", "lattice"),
                                                     ("model.basins", "default_settings")}


@pytest.mark.parametrize("name", paper.PAPER_JOBS + paper.VALIDATION_JOBS)
def test_every_job_of_the_paper_runner_is_valid(name):
    job = load_job(JOBS / f"{name}.toml")
    assert job.name == Path(name).name


def test_the_paper_runner_runs_every_validation_job():
    found = {f"validation/{p.stem}" for p in (JOBS / "validation").glob("*.toml")}
    assert found == set(paper.VALIDATION_JOBS)


def _backbone_result(turns, order=16, branch=None):
    """A backbone result at delta = 1.1, 1.5 (delta_o = 0.2) with the given first turns."""
    import xarray as xr

    data = {"turn_amplitude": (("delta", "delta_o"), np.array(turns, float)[:, None])}
    if branch is not None:
        data["branch_amplitude"] = (("delta", "delta_o", "branch_point"), np.array(branch, float)[:, None, :])
        data["branch_omega"] = (("delta", "delta_o", "branch_point"), 30.0 + np.array(branch, float)[:, None, :])
    return xr.Dataset(data, coords={"delta": [1.1, 1.5], "delta_o": [0.2]}, attrs={"model_order": order})


def test_what_the_branch_does_beyond_its_first_turn():
    """Three turns along the followed branch (up to 0.30, down to 0.25, up to 0.28, down), the
    range after the first; nothing for a branch that does not turn or a result without one."""
    nan = np.nan
    branch = [[0.1, 0.2, 0.3, 0.25, 0.28, 0.26, nan, nan], [0.1, 0.2, 0.3, 0.4, nan, nan, nan, nan]]
    ds = _backbone_result([0.3, nan], branch=branch)
    text = validation._beyond_turn(validation._point(ds, delta=1.1, delta_o=0.2))
    assert "(6 points) has 3 turns in amplitude in all, between 0.2500 and 0.3000 m" in text
    assert validation._beyond_turn(validation._point(ds, delta=1.5, delta_o=0.2)) == ""
    assert validation._beyond_turn(validation._point(_backbone_result([0.3, nan]), delta=1.1)) == ""


def test_a_turn_that_moves_with_the_targets_is_reported(tmp_path):
    """fig08-inplane turning elsewhere than the full backbone at the same resolution is said,
    with both amplitudes; the same turn, or another resolution, says nothing."""
    full = _backbone_result([0.126, np.nan])
    _backbone_result([0.136, np.nan]).to_netcdf(tmp_path / "fig08-inplane.nc")
    lines = validation._turn_against_fig08(tmp_path, full)
    assert len(lines) == 2 and "turns back at 0.1360 m instead of 0.1260 m" in lines[0]
    _backbone_result([0.126, np.nan]).to_netcdf(tmp_path / "fig08-inplane.nc")
    assert validation._turn_against_fig08(tmp_path, full) == []
    _backbone_result([0.136, np.nan], order=12).to_netcdf(tmp_path / "fig08-inplane.nc")
    assert validation._turn_against_fig08(tmp_path, full) == []


def test_a_coarse_lattice_is_found_in_a_fine_one():
    import xarray as xr

    def lattice(nx, ny):
        return xr.Dataset(coords={"ic_x": np.linspace(-0.3, 0.3, nx), "ic_y": np.linspace(-10.0, 10.0, ny)})

    rows = validation._lattice_rows(lattice(100, 100), lattice(12, 34))
    assert rows is not None
    np.testing.assert_array_equal(rows[0], np.arange(0, 100, 9))
    np.testing.assert_array_equal(rows[1], np.arange(0, 100, 3))
    assert validation._lattice_rows(lattice(100, 100), lattice(20, 12)) is None  # 99 / 19 is no integer step


def test_the_o2_summary_of_standing_waves():
    """Past the branch point: the companions' multipliers, how many above 1, the group orbit's
    multiplier's distance from 1 and the stable stretch; "not computed" (with the run's message)
    when no companion multiplier was."""
    import xarray as xr

    nan = np.nan
    ds = xr.Dataset({"switched_odd_multiplier_modulus": ("switched_point", [nan, 0.99, 1.02, 0.98]),
                     "switched_neutral_multiplier": ("switched_point", [nan, 1 + 1e-9, 1 - 3e-9, 1.0]),
                     "switched_stable_o2": ("switched_point", [0, 1, 0, 1]), "message": ((), ""),
                     "status": ((), 0)})
    omega = np.array([33.0, 33.1, 33.2, 33.3])
    text = validation._o2_summary(ds, omega, 4)
    assert "0.98000-1.02000, above 1 at 1 of the 3 points" in text and "1 within 3.0e-09" in text
    assert "stable in O(2) 33.1000-33.1000 rad/s, 33.3000-33.3000 rad/s" in text
    blank = ds.assign(switched_odd_multiplier_modulus=("switched_point", [nan] * 4),
                      message=((), "standing waves in O(2): ValueError: steps"), status=((), 1))
    assert validation._o2_summary(blank, omega, 4) == (" With the sine companions: not computed (standing waves "
                                                        "in O(2): ValueError: steps).")
    # an ok run's message (bifurcations it could not locate) is a note beside the default reason
    noted = blank.assign(message=((), "not located (...): saddle-node between Omega = 34 and 34.1"), status=((), 0))
    assert validation._o2_summary(noted, omega, 4) == (" With the sine companions: not computed (no standing wave "
                                                        "past the point; the run notes: not located (...): "
                                                        "saddle-node between Omega = 34 and 34.1).")


def test_what_the_rotating_waves_inherit():
    """At the Neimark-Sacker point of n = 2 the response is unstable to n = 1 and n = 4 (moduli
    over the damping factor); the waves' own largest multiplier at their second point is n = 4's
    (the harmonic 2n they carry): named as inherited; not when it differs."""
    import xarray as xr

    omega = np.array([33.0, 33.5, 34.0])
    decay = np.exp(-0.05 / 2 * 2 * np.pi / omega)  # c / (2 Gamma h) with Gamma h = 1
    modulus = np.array([[0.9, 0.9, 0.9], [1.01, 1.0, 1.03], [0.9, 0.9, 0.9]]) * decay[:, None]
    ds = xr.Dataset({"Omega": ("point", omega), "point_type": ("point", [0, 3, 0]),
                     "family_multiplier_modulus": (("point", "family"), modulus),
                     "rotating_Omega": ("rotating_point", [33.5, 33.49]),
                     "rotating_multiplier_modulus": ("rotating_point",
                                                     [np.nan, 1.03 * np.exp(-0.05 / 2 * 2 * np.pi / 33.49)]),
                     "n_points": ((), 3), "c": ((), 0.05)},
                    coords={"family": [1, 2, 4]}, attrs={"membrane_Gamma": 1.0, "membrane_h": 1.0})
    text = " ".join(validation._inherited(ds, ds, 2))
    assert "unstable to n = 1 (1.010000), n = 4 (1.030000, the harmonic 2n the waves carry)" in text
    assert "second point is 1.030000: the n = 4 instability, which they inherit through their harmonic 4" in text
    other = ds.assign(rotating_multiplier_modulus=("rotating_point", [np.nan, 1.2]))
    assert "inherit" not in " ".join(validation._inherited(other, other, 2))


def test_the_lyapunov_columns_of_a_family_check():
    """A classified family check: each row's kind (with its period or rotation number) and
    lambda_1 T +- its error per forcing period; the text gives the viscous damping's -alpha T
    and the exponents' sum against the flow's -2 alpha T per coordinate pair, saying which
    way it lies; an unclassified check has neither."""
    import xarray as xr

    from model.lyapunov import KIND_NAMES

    omega = 2 * np.pi  # T = 1 s
    flags = {"flag_values": np.arange(-1, len(KIND_NAMES), dtype=np.int8),
             "flag_meanings": " ".join(("not_computed",) + KIND_NAMES)}
    cf = ("check", "family")
    # alpha T = c T / (2 Gamma h) = 0.025; 128 coordinates: the flow's sum is -3.2 per period
    ds = xr.Dataset({"Omega": ("point", [omega]), "amplitude": ("point", [0.1]), "multiplier_modulus": ("point", [0.9]),
                     "check_Omega": ("check", [omega]), "check_floquet_modulus": (cf, [[1.05, 0.99]]),
                     "check_growth": (cf, [[1.05, 0.99]]), "check_asymmetric_amplitude": (cf, [[0.02, 1e-9]]),
                     "check_asymmetric_spread": (cf, [[0.03, 1e-9]]),
                     "check_kind": (cf, np.array([[2, 1]], dtype=np.int8), flags),
                     "check_kind_period": (cf, [[0, 1]]), "check_rotation_number": (cf, [[0.0712, np.nan]]),
                     "check_lyapunov_exponent": (cf, [[1e-4, -2e-3]]), "check_lyapunov_error": (cf, [[3e-4, 1e-4]]),
                     "check_lyapunov_sum": (cf, [[-32.0, -35.2]]), "check_state_size": ("family", [128, 128]),
                     "c": ((), 0.05)},
                    coords={"family": [1, 4]},
                    attrs={"membrane_Gamma": 1.0, "membrane_h": 1.0, "damping_law": "viscous"})
    rows, _ = validation._check_rows(ds, orbit=True)
    assert rows[0].endswith("| Lyapunov: kind | lambda_1 T |") and rows[1].count("---") == 12
    assert rows[2].endswith("| quasi-periodic, rotation number 0.0712 | +1.00e-04 +- 3.0e-04 |")
    no_circle = validation._check_rows(ds.assign(check_rotation_number=(cf, [[np.nan, np.nan]])), orbit=True)[0]
    assert no_circle[2].endswith("| lambda_1 ~ 0, no invariant circle found | +1.00e-04 +- 3.0e-04 |")
    assert rows[3].endswith("| periodic, period 1 | -2.00e-03 +- 1.0e-04 |")
    text = " ".join(validation._check_classification(ds))
    assert "-alpha T = -c T / (2 Gamma h) = -2.50e-02 .. -2.50e-02" in text
    assert "is 10 to 11 times the flow's" in text and "faster than the flow" in text
    # the periodic row decayed back to the orbit (1e-9 m, family stable): exact lambda_1 T = log 0.99
    # (the family's multiplier, above the orbit's 0.9); the estimate -2e-3 lies 8.05e-3 above it,
    # 80 standard errors
    assert "back to the axisymmetric orbit (1 checks)" in text and "+8.1e-03 to +8.1e-03 from it" in text
    assert "+80.5 to +80.5 standard errors: the block error does not cover" in text
    liouville = " ".join(validation._check_classification(ds.assign(check_lyapunov_sum=(cf, [[-3.2, -3.2]]))))
    assert "is 1 to 1 times the flow's" in liouville and "Liouville's contraction" in liouville
    modal = " ".join(validation._check_classification(ds.assign_attrs(damping_law="modal")))
    assert "alpha" not in modal and "periodic of period k <= 16" in modal
    plain = ds.drop_vars([v for v in ds.data_vars if v.startswith(("check_kind", "check_lyap", "check_rot",
                                                                   "check_state"))])
    assert "Lyapunov" not in validation._check_rows(plain)[0][0] and validation._check_classification(plain) == []


def test_the_states_reached_on_more_harmonics(tmp_path):
    """The checks on 0, n, 2n against those on 0, n, 2n, 3n (one file per family), matched by
    family and response (to rounding): both kinds and exponents per row, and what became of
    every chaotic verdict: still chaotic, no longer chaotic (labelled as the rows are), ended
    otherwise, or not checked; missing files are named; no chaotic verdict, no comparison."""
    import xarray as xr

    from model.lyapunov import KIND_NAMES

    omega = 2 * np.pi * np.array([1.0, 1.1, 1.2, 1.3])
    flags = {"flag_values": np.arange(-1, len(KIND_NAMES), dtype=np.int8),
             "flag_meanings": " ".join(("not_computed",) + KIND_NAMES)}
    code = {name: i for i, name in enumerate(KIND_NAMES)}
    cf = ("check", "family")

    def run(families, values, kinds, highest):
        shape = (len(values), len(families))
        return xr.Dataset({"check_Omega": ("check", values),
                           "check_kind": (cf, np.array([[code[k] for k in row] for row in kinds], np.int8), flags),
                           "check_kind_period": (cf, np.ones(shape, int)),
                           "check_rotation_number": (cf, np.full(shape, np.nan)),
                           "check_lyapunov_exponent": (cf, np.full(shape, 0.05)),
                           "check_lyapunov_error": (cf, np.full(shape, 0.005)),
                           "check_asymmetric_amplitude": (cf, np.full(shape, 0.01)),
                           "check_highest_harmonic": ("family", np.array(highest, np.int32))},
                          coords={"family": families})

    base = run([1, 4], omega, [["chaotic", "quasi_periodic"], ["periodic", "chaotic"], ["periodic", "chaotic"],
                               ["chaotic", "periodic"]], [2, 8])
    assert "*Not available: run `jobs/validation/family-check-full-3n-n1.toml`, `jobs/validation/family-check-full-3n-n4" \
           in " ".join(validation._harmonic_convergence(tmp_path, base))
    (tmp_path / "validation").mkdir()
    # the n = 1 run has the first response to rounding, not the fourth
    n1 = run([1], [omega[0] * (1 + 1e-15), omega[1], omega[2]], [["chaotic"], ["periodic"], ["chaotic"]], [3])
    n1.to_netcdf(tmp_path / "validation" / "family-check-full-3n-n1.nc")
    run([4], omega[1:3], [["quasi_periodic"], ["unsettled"]], [12]).to_netcdf(
        tmp_path / "validation" / "family-check-full-3n-n4.nc")
    lines = validation._harmonic_convergence(tmp_path, base)
    # lambda_1 T = 0.05 s-1 times T = 1, 1 / 1.1, 1 / 1.2 s
    rows = [line for line in lines if line.startswith("| 1 |") or line.startswith("| 4 |")]
    assert rows == ["| 1 | 6.283 | chaotic | +5.00e-02 +- 5.0e-03 | 1.00e-02 | chaotic | +5.00e-02 +- 5.0e-03 | 1.00e-02 |",
                    "| 1 | 6.912 | periodic, period 1 | +4.55e-02 +- 4.5e-03 | 1.00e-02 | periodic, period 1 | "
                    "+4.55e-02 +- 4.5e-03 | 1.00e-02 |",
                    "| 4 | 6.912 | chaotic | +4.55e-02 +- 4.5e-03 | 1.00e-02 | lambda_1 ~ 0, no invariant circle found | "
                    "+4.55e-02 +- 4.5e-03 | 1.00e-02 |",
                    "| 1 | 7.540 | periodic, period 1 | +4.17e-02 +- 4.2e-03 | 1.00e-02 | chaotic | "
                    "+4.17e-02 +- 4.2e-03 | 1.00e-02 |",
                    "| 4 | 7.540 | chaotic | +4.17e-02 +- 4.2e-03 | 1.00e-02 | unsettled | +4.17e-02 +- 4.2e-03 | "
                    "1.00e-02 |"]
    text = " ".join(lines)
    assert ("Of the 4 states called chaotic on the harmonics 0, n, 2n: 1 still chaotic with the harmonic 3n: 6.28 "
            "rad/s (n = 1); 1 no longer chaotic: 6.91 rad/s (n = 4: lambda_1 ~ 0, no invariant circle found); 1 ended "
            "otherwise (not computed, diverged or unsettled): 7.54 rad/s (n = 4: unsettled); 1 not checked on 0, n, "
            "2n, 3n: 8.17 rad/s (n = 1). The other way: 1 state not chaotic on 0, n, 2n is chaotic with the "
            "harmonic 3n: 7.54 rad/s (n = 1: periodic, period 1 on 0, n, 2n). The kind of these states is not "
            "converged") in text
    # every chaotic verdict compared and still chaotic
    kinds = n1.check_kind.copy(data=np.array([[code["chaotic"]], [code["periodic"]], [code["periodic"]]], np.int8))
    n1.assign(check_Omega=("check", omega[[0, 1, 3]]), check_kind=kinds).to_netcdf(tmp_path / "validation" / "family-check-full-3n-n1.nc")
    run([4], omega[1:3], [["chaotic"], ["chaotic"]], [12]).to_netcdf(tmp_path / "validation" /
                                                                      "family-check-full-3n-n4.nc")
    text = " ".join(validation._harmonic_convergence(tmp_path, base.assign(
        check_kind=base.check_kind.where(base.check_Omega != omega[3], code["periodic"]))))
    assert "Of the 3 states called chaotic on the harmonics 0, n, 2n: 3 still chaotic" in text
    assert "Their kind holds with one harmonic more" in text
    # no chaotic verdict on 0, n, 2n; with 3n two periodic states are chaotic (6.28 rad/s in the
    # n = 1 file as last written; an unsettled one that is chaotic with 3n is not counted: it had
    # no kind to lose)
    kinds = np.full((4, 2), code["periodic"], np.int8)
    kinds[2, 1] = code["unsettled"]
    none = base.assign(check_kind=base.check_kind.copy(data=kinds))
    text = " ".join(validation._harmonic_convergence(tmp_path, none))
    assert ("No state is called chaotic on the harmonics 0, n, 2n. The other way: 2 states not chaotic on 0, n, 2n "
            "are chaotic with the harmonic 3n: 6.28 rad/s (n = 1: periodic, period 1 on 0, n, 2n), 6.91 rad/s (n = 4: "
            "periodic, period 1 on 0, n, 2n). The kind of these states is not converged") in text
    run([4], omega[1:3], [["periodic"], ["periodic"]], [12]).to_netcdf(tmp_path / "validation" /
                                                                        "family-check-full-3n-n4.nc")
    run([1], omega[[0, 1, 3]], [["periodic"]] * 3, [3]).to_netcdf(tmp_path / "validation" / "family-check-full-3n-n1.nc")
    assert "No state is called chaotic on the harmonics 0, n, 2n. Nothing to compare." in \
           " ".join(validation._harmonic_convergence(tmp_path, none))


def test_the_asymmetric_finite_element_check():
    """Each orbit's deviations per mesh and the harmonics' own error, the measured orders
    between meshes (log of the ratio over log 2 for doubled meshes), the finest mesh's
    largest, and what they allow one to say; orbits without a frequency are left out."""
    import xarray as xr

    fr = ("delta", "delta_o", "point", "fe_radial")
    pt = ("delta", "delta_o", "point")
    w = np.array([[[[8e-3, 1e-3], [1.6e-2, 2e-3]]]])  # order 3 for both orbits
    ds = xr.Dataset({"omega_nl": (pt, [[[30.0, 31.0]]]),
                     "amplitude": ("point", [0.02, 0.06]), "fe_harmonic_w_deviation": (fr, w),
                     "fe_harmonic_odd_deviation": (fr, 2 * w), "fe_harmonic_u_deviation": (fr, w ** (2 / 3)),
                     "fe_harmonic_v_deviation": (fr, np.sqrt(w)),
                     "fe_harmonic_reference_w_error": (pt, [[[1e-6, 2e-6]]]),
                     "fe_harmonic_reference_odd_error": (pt, [[[4e-6, 8e-5]]])},
                    coords={"delta": [1.1], "delta_o": [0.2], "fe_radial": [4, 8]})
    text = "\n".join(validation._fe_asymmetric(ds, [4, 8], 2, 0.01))
    assert ("| 1.1 | 0.020 | 8.0e-03 / 1.0e-03 | 1.6e-02 / 2.0e-03 | 4.0e-02 / 1.0e-02 | 8.9e-02 / 3.2e-02 | "
            "1.0e-06 / 4.0e-06 |") in text
    assert "* w: 4 -> 8: 3.0 to 3.0" in text and "* u: 4 -> 8: 2.0 to 2.0" in text and "* v: 4 -> 8: 1.5 to 1.5" in text
    # the harmonics' own error: 8e-5 of the second orbit's odd part, 4e-3, is 2e-2 of it
    assert "at most 2.0e-02 of the finest mesh's deviations of w and odd part (the deviations are the mesh's)." in text
    assert "w deviates by at most 2.0e-03 of its largest value and its odd part by 4.0e-03: the full model's" in text
    assert "0.01 m of the lowest n = 1 transverse mode" in text and "v converges more slowly than w" in text
    # a start of wave number 2: its harmonics, its half turn, its refinement
    text = "\n".join(validation._fe_asymmetric(ds, [4, 8], 2, 0.01, 2, "validation/fe-free-vibration-n2", "### n2"))
    assert text.startswith("### n2") and "the lowest n = 2 transverse mode" in text
    assert "harmonics 0, 2, 4, 6 (" in text and "w(rho, theta + pi / 2), twice its part on the odd multiples of 2" in text
    assert "harmonics 8, 10 added, 8 more radial functions per field" in text and "integrate the n = 2 transverse motion" in text
    # an order of 2.5 or less between the finest meshes is said so, and a large own error
    slow = ds.assign(fe_harmonic_odd_deviation=(fr, 2 * np.sqrt(w)),
                     fe_harmonic_reference_odd_error=(pt, [[[4e-6, 2e-2]]]))
    text = "\n".join(validation._fe_asymmetric(slow, [4, 8], 2, 0.01))
    assert "not yet at the element's order there" in text and "not negligible against them" in text
    assert "2.5 or less at delta 1.1, 0.02 m (odd part 1.5); delta 1.1, 0.06 m (odd part 1.5)" in text
    missing = ds.assign(omega_nl=(pt, [[[30.0, np.nan]]]))
    assert "| 0.060 |" not in "\n".join(validation._fe_asymmetric(missing, [4, 8], 2, 0.01))
    # u and v at the element's order too (3 and 2.6 at both orbits), and at every orbit while w's
    # odd part is not
    fast = ds.assign(fe_harmonic_u_deviation=(fr, w), fe_harmonic_v_deviation=(fr, w ** 0.86))
    text = "\n".join(validation._fe_asymmetric(fast, [4, 8], 2, 0.01))
    assert "(orders 2.6 to 2.6): both at the element's order too." in text and "more slowly" not in text
    text = "\n".join(validation._fe_asymmetric(fast.assign(fe_harmonic_odd_deviation=(fr, 2 * np.sqrt(w))),
                                                [4, 8], 2, 0.01))
    assert "not yet at the element's order there" in text
    assert "(orders 2.6 to 2.6): both at the element's order at every orbit." in text and " too." not in text
    # with u's and v's own errors: 9e-3 of the second orbit's v, sqrt(2e-3) = 4.47e-2, is 0.20 of it
    uv = ds.assign(fe_harmonic_reference_u_error=(pt, [[[1e-5, 1e-3]]]),
                   fe_harmonic_reference_v_error=(pt, [[[1e-5, 9e-3]]]))
    text = "\n".join(validation._fe_asymmetric(uv, [4, 8], 2, 0.01))
    assert "| 1.0e-06 / 4.0e-06 / 1.0e-05 / 1.0e-05 |" in text and "w / odd part / u / v, on a polar grid" in text
    # u: 1e-3 of (2e-3)^(2/3) = 1.59e-2 is 6.3e-2 of it
    assert ("at most 2.0e-02 of the finest mesh's deviations of w and odd part (the deviations are the mesh's); "
            "2.0e-01 of the finest mesh's deviations of u and v (not negligible against them at delta 1.1 (0.06 m), "
            "where the measured orders of these fields are partly the harmonics' own error; below 0.1 of them "
            "elsewhere).") in text
    # both orbits' own errors large: one clause per delta
    both = uv.assign(fe_harmonic_reference_v_error=(pt, [[[1e-2, 9e-3]]]))
    assert "against them at delta 1.1 (0.02 and 0.06 m), where" in "\n".join(validation._fe_asymmetric(both, [4, 8], 2,
                                                                                                       0.01))


def test_the_paper_damping_band_reads_every_saddle_node_but_the_lowest():
    import xarray as xr

    from model.continuation import FOLD

    def branch(order, omega, amplitude, folds):
        kind = np.zeros(len(omega) + 1, np.int8)
        kind[folds] = FOLD
        pad = [np.nan]
        return xr.Dataset({"Omega": (("c", "point"), [omega + pad]), "amplitude": (("c", "point"), [amplitude + pad]),
                           "point_type": (("c", "point"), [kind]), "n_points": (("c",), [len(omega)])},
                          coords={"c": [0.05]}, attrs={"model_order": order, "membrane_Gamma": 2200.0,
                                                       "membrane_h": 1e-3})

    text = " ".join(validation._paper_damping_band([
        branch(8, [30.0, 34.3, 34.2, 34.35, 33.0], [0.01, 0.14, 0.13, 0.145, 0.03], [1, 3, 4]),
        branch(12, [30.0, 34.4, 34.3, 33.0], [0.01, 0.12, 0.13, 0.03], [1, 3])], 32.5))
    assert "saddle-nodes 3 at 8, 2 at 12 functions" in text
    assert "(33.000 rad/s, 0.030 m)" in text  # once for both
    assert "lie at 34.300-34.400 rad/s" in text and "with 0.120-0.145 m" in text
    assert f"{0.05 / (2 * 2.2 * 32.5):.2e} omega_10 / omega_m0" in text
    assert "grows with the resolution" not in text  # 3 -> 2
    # a branch without saddle-nodes is counted, and nothing else is claimed of it
    text = " ".join(validation._paper_damping_band([branch(8, [30.0, 31.0], [0.01, 0.02], []),
                                                    branch(12, [30.0, 34.4, 33.0], [0.01, 0.12, 0.03], [1, 2])],
                                                   32.5))
    assert "saddle-nodes 0 at 8, 2 at 12 functions" in text and "lie at 34.400-34.400 rad/s" in text
    assert "grows with the resolution (0 -> 2)" in text


def test_saddle_node_moves_between_branches():
    moves = validation._fold_moves([np.array([34.0, 33.0]), np.array([34.1, 32.95]), np.array([34.1]),
                                    np.array([]), np.array([])])
    np.testing.assert_allclose(moves[:1], [0.1])
    assert moves[1:3] == [np.inf, np.inf] and moves[3] == 0.0
