"""One-way imports: ``model`` is pure physics (no MPI, no xarray, no sweep), and no module of
``model`` or ``sweep`` imports itself through others."""

import ast
import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "model"


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


def import_graph(root: Path, packages=("model", "sweep")) -> dict[str, set[str]]:
    """The imports between the modules of ``packages`` under ``root``: module -> the modules
    it imports.

    Every ``import`` statement counts, at module level or inside a function (a deferred
    import is still a dependency).  ``from p import n`` names the module ``p.n`` when there
    is one, else ``p``; relative imports are resolved.  Importing ``p.m`` also runs
    ``p/__init__.py``, but that implicit edge is not counted (it would make every package
    whose ``__init__`` imports a submodule a cycle).
    """
    files = {}
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            files[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    graph = {}
    for name, path in files.items():
        here = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    anchor = here.split(".")[:len(here.split(".")) - node.level + 1]
                    base = ".".join(anchor + ([base] if base else []))
                targets.update(f"{base}.{a.name}" if f"{base}.{a.name}" in files else base for a in node.names)
        graph[name] = {t for t in targets if t in files and t != name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One cycle ``[a, b, ..., a]`` through each strongly connected component of more than
    one module (Tarjan's algorithm), sorted."""
    index, low, stack, on_stack, components = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                components.append(set(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    out = []
    for component in components:
        start = min(component)
        path, seen = [start], {start}
        while True:  # walk inside the component back to the start: a cycle through it
            nxt = sorted(w for w in graph[path[-1]] if w in component)
            back = start in nxt
            if back:
                out.append(path + [start])
                break
            step = next((w for w in nxt if w not in seen), None)
            if step is None:  # a dead end inside the component: the shortest way back
                out.append(_shortest_cycle(graph, start, component))
                break
            path.append(step)
            seen.add(step)
    return sorted(out)


def _shortest_cycle(graph, start, component):
    paths, frontier = {start: [start]}, [start]
    while frontier:
        following = []
        for v in frontier:
            for w in sorted(graph[v]):
                if w == start:
                    return paths[v] + [start]
                if w in component and w not in paths:
                    paths[w] = paths[v] + [w]
                    following.append(w)
        frontier = following
    raise AssertionError(f"{start} is on no cycle of {sorted(component)}")


def test_the_cycle_finder_names_a_cycle():
    graph = {"a": {"b"}, "b": {"c", "d"}, "c": {"a"}, "d": set(), "e": {"e"}, "f": {"g"}, "g": {"f"}}
    assert cycles(graph) == [["a", "b", "c", "a"], ["f", "g", "f"]]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"d"}, "d": {"b"}}) == [["b", "c", "d", "b"]]


def test_the_import_graph_sees_deferred_and_relative_imports():
    graph = import_graph(ROOT)
    assert "sweep.analyses.options" in graph["sweep.analyses.basins"]   # from . import options
    assert "sweep.analyses.base" in graph["sweep.analyses.basins"]      # from .base import ...
    assert "model.continuation" in graph["sweep.figures.continuation"]  # inside a function


def test_no_module_of_model_or_sweep_is_in_an_import_cycle():
    found = cycles(import_graph(ROOT))
    assert found == [], "import cycles: " + "; ".join(" -> ".join(c) for c in found)
