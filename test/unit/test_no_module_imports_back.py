"""No two modules of src/jaka_driver import each other, directly or around a loop.

The graph is built from the source, statically: every ``import`` and ``from ... import`` of
every module (at the top, inside a function, under ``TYPE_CHECKING``: each is a dependency a
reader has to follow). A node is a module; a package's ``__init__`` is a node of its own, its
face. An edge goes to the module named, or — ``from pkg import name`` where ``name`` is no
submodule — to the package's face. Importing a submodule from outside its package also runs the
package's ``__init__`` first, so that is an edge to the face too; from inside the package the
face is already being imported (it is the parent), and that implicit edge is not counted —
an explicit ``from . import name`` of something the face defines is.

Nothing is imported or started.
"""
from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src"
PACKAGE = "jaka_driver"


def _modules() -> dict[str, Path]:
    """Dotted name → file, every module and package face of the package."""
    found = {}
    for path in sorted((SRC / PACKAGE).rglob("*.py")):
        parts = list(path.relative_to(SRC).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        found[".".join(parts)] = path
    return found


def _is_package(name: str, modules: dict[str, Path]) -> bool:
    return modules[name].name == "__init__.py"


def _faces_above(target: str, importer: str, modules: dict[str, Path]) -> list[str]:
    """The package faces that importing ``target`` runs and ``importer`` is not inside."""
    parts = target.split(".")
    faces = []
    for n in range(2, len(parts)):
        face = ".".join(parts[:n])
        if face in modules and not (importer == face or importer.startswith(face + ".")):
            faces.append(face)
    return faces


def import_graph() -> dict[str, set[str]]:
    """Module → the modules of the package it imports (see the module docstring)."""
    modules = _modules()
    graph: dict[str, set[str]] = {name: set() for name in modules}
    for name, path in modules.items():
        package = name if _is_package(name, modules) else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")
                    base = base[:len(base) - (node.level - 1)]
                    source = ".".join(base + ([node.module] if node.module else []))
                else:
                    source = node.module or ""
                for alias in node.names:
                    sub = f"{source}.{alias.name}"
                    targets.append(sub if sub in modules else source)
            for target in targets:
                # the longest prefix that is a module of the package
                while target and target not in modules:
                    target = target.rpartition(".")[0]
                if not target or target == name:
                    continue
                graph[name].add(target)
                graph[name].update(_faces_above(target, name, modules))
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

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


def test_the_graph_sees_the_package():
    graph = import_graph()
    # the door imports the contract's face; a backend its own motion sources
    assert "jaka_driver.backend" in graph["jaka_driver.driver.robot_driver"]
    assert "jaka_driver.sim.motions" in graph["jaka_driver.sim.physics"]
    # outside its package, a submodule's import runs the package's face too
    assert "jaka_driver.protocol" in graph["jaka_driver.controller.servo_commands"]
    assert sum(len(v) for v in graph.values()) > 300


def test_the_cycle_finder_finds_a_loop_and_a_face():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"p": {"p.x"}, "p.x": {"q"}, "q": {"p"}}) == [["p", "p.x", "q"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_no_module_imports_another_that_imports_it_back():
    found = cycles(import_graph())
    assert not found, "import loops (each a set of modules that reach each other):\n" + \
        "\n".join("  " + " ↔ ".join(c) for c in found)

