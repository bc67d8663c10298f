"""Where things live: the modules of aero_env and agents import one another in no circle, and none imports
another's ``_private`` name (DEVELOPERS.md, "Where things go"). Read from the source with ``ast``: every import
counts, a function's lazy one and one for type checking only included."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("aero_env", "agents")


def _modules(root: Path, packages) -> dict[str, tuple[Path, bool]]:
    """Dotted module name -> (file, is a package's __init__)."""
    found = {}
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            is_package = parts[-1] == "__init__"
            found[".".join(parts[:-1] if is_package else parts)] = (path, is_package)
    return found


def import_graph(root: Path, packages=PACKAGES) -> tuple[dict[str, set[str]], list[tuple[str, str, str]]]:
    """Each module's imports of the others, and every (importer, module, name) that imports a ``_private`` name."""
    modules = _modules(root, packages)
    graph: dict[str, set[str]] = {name: set() for name in modules}
    private = []
    for name, (path, is_package) in modules.items():
        package = name if is_package else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                graph[name] |= {a.name for a in node.names if a.name in modules}
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[:len(package.split(".")) - node.level + 1]
                    source = ".".join(base + ([node.module] if node.module else []))
                else:
                    source = node.module or ""
                for alias in node.names:
                    if f"{source}.{alias.name}" in modules:  # a submodule: from . import run
                        graph[name].add(f"{source}.{alias.name}")
                    elif source in modules:
                        graph[name].add(source)
                        if alias.name.startswith("_") and not alias.name.startswith("__"):
                            private.append((name, source, alias.name))
        graph[name].discard(name)
    return graph, private


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The circles of ``graph``: its strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
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
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_no_module_imports_in_a_circle():
    graph, _ = import_graph(ROOT)
    assert len(graph) > 50 and "aero_env.models.reduced.batch" in graph  # the scan saw the tree
    assert cycles(graph) == []


def test_no_module_imports_another_modules_private_name():
    _, private = import_graph(ROOT)
    assert private == [], "give these a public name in the module that owns them: " + ", ".join(
        f"{importer} imports {name} from {source}" for importer, source, name in private)


def test_the_check_finds_a_circle_and_a_private_import(tmp_path):
    pkg = tmp_path / "aero_env"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "sub" / "__init__.py").write_text("from .a import A\n")
    (pkg / "sub" / "a.py").write_text("A = 1\n\ndef f():\n    from ..b import B\n")  # a lazy import counts
    (pkg / "b.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .sub import a\n"
                              "from .sub.a import _helper\nB = 2\n")
    graph, private = import_graph(tmp_path, ("aero_env",))
    assert cycles(graph) == [["aero_env.b", "aero_env.sub.a"]]
    assert private == [("aero_env.b", "aero_env.sub.a", "_helper")]
