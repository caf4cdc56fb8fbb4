"""The package's layering, read from its source: imports go one way and never in a circle, and no function
outside the compiled kernels is longer than a screen."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
#: the longest function, in lines, that the project allows outside the numba kernels
LONGEST_FUNCTION = 80


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> set:
    """The ``dem_core`` modules that the module at ``path`` imports, wherever in it the import stands."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package
            for _ in range(node.level - 1):
                base = base.rpartition(".")[0]
            module = node.module or ""
            target = (f"{base}.{module}" if module else base) if node.level else module
            found.add(target)
            found.update(f"{target}.{alias.name}" for alias in node.names)
    modules = {_module_name(p) for p in (ROOT / "dem_core").rglob("*.py")}
    return {m for m in found if m in modules and m != name}


def _graph() -> dict:
    return {_module_name(p): _imports(p) for p in sorted((ROOT / "dem_core").rglob("*.py"))}


def _cycle(graph: dict) -> list:
    """One import cycle among the modules of ``graph`` (a list of names, first repeated last), or []."""
    state = {}

    def visit(node, path):
        state[node] = "open"
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                return path[path.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt, path + [nxt])
                if found:
                    return found
        state[node] = "done"
        return []

    for start in sorted(graph):
        if start not in state:
            found = visit(start, [start])
            if found:
                return found
    return []


def _is_package_init(module: str) -> bool:
    return (ROOT / Path(*module.split(".")) / "__init__.py").exists()


def test_the_import_graph_has_no_cycle():
    graph = _graph()
    # a package's __init__ gathers its modules' names; a module importing its package's name is not a cycle
    graph = {m: {d for d in deps if not (_is_package_init(d) and m.startswith(d + "."))} for m, deps in graph.items()}
    assert _cycle(graph) == []


def test_the_engine_imports_nothing_above_it():
    """The engine (model, state, kernels, time step, result) reads no scene builder, analysis or picture."""
    graph = _graph()
    upward = {(m, d) for m, deps in graph.items() if m.startswith("dem_core.engine") for d in deps
              if not d.startswith("dem_core.engine") and d != "dem_core"}
    assert upward == set()


#: the package's layers, lowest first: a module imports from its own layer and the layers below, never above
LAYERS = (("engine", "output_files"), ("inputs", "scene_json"), ("simulation",), ("batch_gpu", "gpu_kernels"), ("batch",), ("analyses",),
          ("pictures", "run_folder", "vtu_series"), ("cli", "__main__"))


def _layer(module: str) -> int:
    part = module.split(".")[1]
    return next(k for k, names in enumerate(LAYERS) if part in names)


def test_no_module_imports_from_a_layer_above_its_own():
    """The scene file does not reach up into the simulation for a constant, nor the engine into the inputs."""
    upward = sorted((m, d) for m, deps in _graph().items() if m != "dem_core" for d in deps
                    if d != "dem_core" and _layer(d) > _layer(m))
    assert upward == []


def test_the_cycle_finder_finds_a_cycle():
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) == []


def _kernels(tree) -> set:
    """Names of the functions numba compiles: decorated with ``njit``/``jit``, or handed to ``njit(...)(...)``."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and any("jit" in ast.unparse(d) for d in node.decorator_list):
            names.add(node.name)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Call) and "jit" in ast.unparse(node.func.func):
            names.update(n.id for arg in node.args for n in ast.walk(arg) if isinstance(n, ast.Name))
    return names


@pytest.mark.parametrize("folder", ["dem_core", "comparisons", "adapters"])
def test_no_function_outside_the_kernels_is_longer_than_a_screen(folder):
    long = []
    for path in sorted((ROOT / folder).rglob("*.py")):
        tree = ast.parse(path.read_text())
        kernels = _kernels(tree)
        long += [f"{path.relative_to(ROOT)}:{node.lineno} {node.name} ({node.end_lineno - node.lineno + 1} lines)"
                 for node in ast.walk(tree) if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
                 and node.name not in kernels and node.end_lineno - node.lineno + 1 > LONGEST_FUNCTION]
    assert long == []
