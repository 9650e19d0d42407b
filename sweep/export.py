"""``python -m sweep export``: the 2-D finite-element check's meshes and mode shapes as files
ParaView opens.

For a ``linear`` job on ``[model] kind = "fe2d"`` (:mod:`sweep.models.fe2d`), one VTK
unstructured-grid file (``.vtu``, written with meshio) per grid point, on the mesh of
``[model]`` (``linear.basis`` is ignored):

* points: the undeformed annulus (m), ``z = 0``, the quadratic elements of ``"P2"`` split into
  four linear triangles each (scikit-fem's ``refinterp``; the fields are exact at the points);
* point data ``prestretch`` (m): the in-plane displacement of the pre-stretch;
* point data ``W m=<m> n=<n>: <omega> rad/s`` and ``UV m=<m> n=<n>: <omega> rad/s`` for each
  mode ``(m, n)`` of ``[linear] modes`` (a sine companion ``n < 0`` gets the shape the mesh's
  eigensolver returns for ``|n|``, one of the degenerate pair): the transverse (``(0, 0, w)``) and in-plane
  (``(u_x, u_y, 0)``) mode shapes, scaled to a largest displacement of 1 (dimensionless:
  "Warp By Vector" in ParaView with a factor in metres draws them), their frequencies in their
  names (meshio's VTU writer keeps no field data).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from sweep.errors import RunError
from sweep.jobspec import load_job


def export_fe(job_path: str | Path, outdir: str | Path) -> list[Path]:
    """Write the ``.vtu`` files of the job's grid points into ``outdir``; their paths."""
    import meshio

    from model.fe_annulus import fe_modes
    from sweep.models.fe2d import fe_prestretch_for

    job = load_job(job_path)
    if job.model.kind != "fe2d" or job.analysis_name != "linear":
        raise RunError(f"{job_path}: export needs a linear job on [model] kind = \"fe2d\" (this one: "
                       f"analysis {job.analysis_name!r}, model {job.model.kind!r})")
    o = job.model.options
    modes = job.options.modes
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    paths, seen = [], set()
    for t in range(job.layout.n_tasks):
        point, _ = job.point(t)
        if tuple(point.grid.items()) in seen:  # the subtasks of a basis study: one mesh
            continue
        seen.add(tuple(point.grid.items()))
        membrane = point.membrane
        state = fe_prestretch_for(membrane, o.radial, o.circumferential, o.element, o.grading)
        count, n_max = max(m for m, _ in modes), max(abs(n) for _, n in modes)
        try:
            fields = {kind: fe_modes(state, kind, count, n_max, o.mass) for kind in ("W", "UV")}
        except ValueError as exc:
            raise RunError(f"{job_path}: at {point.grid}: {exc}") from None
        scalar = state.mesh.basis(1)
        refined, _ = scalar.refinterp(np.zeros(scalar.N), nrefs=1)
        points = membrane.Re * np.column_stack([refined.p.T, np.zeros(refined.p.shape[1])])
        point_data = {"prestretch": membrane.Re * _planar(state.basis, state.d)}
        for m, n in modes:
            omega_w, shapes_w = fields["W"][abs(n)]
            omega_uv, shapes_uv = fields["UV"][abs(n)]
            w = scalar.refinterp(shapes_w[:, m - 1], nrefs=1)[1]
            point_data[f"W m={m} n={n}: {omega_w[m - 1]:.4f} rad/s"] = np.column_stack(
                [np.zeros((w.size, 2)), w / np.abs(w).max()])
            uv = _planar(state.mesh.basis(2), shapes_uv[:, m - 1])
            point_data[f"UV m={m} n={n}: {omega_uv[m - 1]:.4f} rad/s"] = uv / np.linalg.norm(uv, axis=1).max()
        cells = [("quad" if refined.t.shape[0] == 4 else "triangle", refined.t.T)]
        name = "_".join(f"{k}={v:g}" for k, v in point.grid.items())
        path = outdir / f"{job.name}_{name}.vtu"
        meshio.write(path, meshio.Mesh(points, cells, point_data=point_data))
        paths.append(path)
    return paths


def _planar(basis, dofs) -> np.ndarray:
    """``(points, 3)``: a two-component field of the vector ``basis`` on the refined mesh of
    :func:`export_fe`, ``z`` component zero."""
    parts = [basis.split_bases()[c].refinterp(dofs[basis.split_indices()[c]], nrefs=1)[1] for c in range(2)]
    return np.column_stack(parts + [np.zeros(parts[0].size)])
