"""One-way imports: ``model`` is pure physics (no MPI, no xarray, no sweep)."""

import ast
import json
import subprocess
import sys
from pathlib import Path

MODEL = Path(__file__).resolve().parents[1] / "model"


def test_importing_every_model_module_loads_no_mpi_xarray_or_sweep():
    modules = [f"model.{p.stem}" for p in sorted(MODEL.glob("*.py")) if p.stem != "__init__"]
    code = ("import importlib, json, sys; "
            f"[importlib.import_module(m) for m in {modules!r}]; "
            "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('mpi4py', 'xarray', 'h5py', 'netCDF4', 'sweep', 'matplotlib'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert json.loads(out.stdout) == []


def test_model_sources_do_not_import_sweep():
    for path in MODEL.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                assert node.module.split(".")[0] != "sweep", f"{path.name} imports {node.module}"
            if isinstance(node, ast.Import):
                assert all(a.name.split(".")[0] != "sweep" for a in node.names), path.name
