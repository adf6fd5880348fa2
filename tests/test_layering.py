"""The package's one-way architecture, checked from the source (no imports executed).

Layers, lowest first: the exact core (``hairbed._core``: validation, kernels, ``Solution``,
the solver's wrappers), the lab workflows (units, inverse, branches, ...), the outer rooms
(cli, plotting, the benchmark, the explorer), and the package's ``__init__`` that re-exports
the public names. A module may import only from its own layer or below; nothing in the core
or the lab imports the package itself (``import hairbed`` / ``from hairbed import``, which
runs ``__init__`` and creates import cycles); there are no cycles between modules; and no
module is named like a function or class it defines (``from hairbed import solve`` must not
be able to bind a module).

The rules live in :func:`layering_violations`, tested on deliberately wrong layouts below,
so the test on the real package is one that can fail.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "hairbed"

#: Outer rooms: modules that may use the public package. Everything else is core or lab.
OUTER = (
    "hairbed.cli",
    "hairbed.__main__",
    "hairbed._command",
    "hairbed._benchmark",
    "hairbed.plotting",
    "hairbed.explorer",
)
CORE = ("hairbed._core",)


def _layer(module: str) -> int:
    """0 core, 1 lab, 2 outer, 3 the package's own __init__."""
    if module == "hairbed":
        return 3
    if any(module == p or module.startswith(p + ".") for p in CORE):
        return 0
    if any(module == p or module.startswith(p + ".") for p in OUTER):
        return 2
    return 1


def _module_name(root: Path, path: Path) -> str:
    rel = path.relative_to(root.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _resolve(module: str, is_package: bool, node: ast.ImportFrom) -> str:
    """The absolute module an ``ImportFrom`` names (relative imports resolved)."""
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _runtime_nodes(tree: ast.AST) -> list[ast.AST]:
    """Every node of the tree except those under ``if TYPE_CHECKING:`` (never executed)."""
    out: list[ast.AST] = []
    todo = [tree]
    while todo:
        node = todo.pop()
        out.append(node)
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            todo.extend(node.orelse)
            continue
        todo.extend(ast.iter_child_nodes(node))
    return out


def _imports(root: Path) -> dict[str, set[str]]:
    """module -> the hairbed modules it imports (any depth: lazy imports count too)."""
    pkg = root.name
    names = {_module_name(root, p) for p in root.rglob("*.py")}
    graph: dict[str, set[str]] = {}
    for path in sorted(root.rglob("*.py")):
        module = _module_name(root, path)
        is_package = path.name == "__init__.py"
        targets: set[str] = set()
        for node in _runtime_nodes(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names if a.name.split(".")[0] == pkg)
            elif isinstance(node, ast.ImportFrom):
                base = _resolve(module, is_package, node)
                if base.split(".")[0] != pkg:
                    continue
                for alias in node.names:
                    sub = f"{base}.{alias.name}"
                    targets.add(sub if sub in names else base)
        graph[module] = {t for t in targets if t != module}
    return graph


def _defined_names(path: Path) -> set[str]:
    tree = ast.parse(path.read_text())
    return {
        n.name
        for n in tree.body
        if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef)
    }


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Elementary cycles found by depth-first search (each reported once, from its start)."""
    found: list[list[str]] = []
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(u: str) -> None:
        state[u] = 1
        stack.append(u)
        for v in sorted(graph.get(u, ())):
            if v not in graph:
                continue
            if state.get(v) == 1:
                found.append(stack[stack.index(v) :] + [v])
            elif v not in state:
                visit(v)
        stack.pop()
        state[u] = 2

    for u in sorted(graph):
        if u not in state:
            visit(u)
    return found


def layering_violations(root: Path) -> list[str]:
    """Every breach of the layering rules in the package at ``root`` (module docstring)."""
    pkg = root.name
    graph = _imports(root)
    out: list[str] = []
    for module, targets in sorted(graph.items()):
        layer = _layer(module.replace(pkg, "hairbed", 1))
        for target in sorted(targets):
            t_layer = _layer(target.replace(pkg, "hairbed", 1))
            if target == pkg:
                if layer < 2:  # the outer rooms are the package's users: they may
                    out.append(f"{module} imports the package {pkg} (use the module it needs)")
            elif t_layer > layer:
                out.append(f"{module} (layer {layer}) imports {target} (layer {t_layer})")
    for cycle in _cycles(graph):
        out.append("import cycle: " + " -> ".join(cycle))
    for path in sorted(root.rglob("*.py")):
        stem = path.stem
        if stem != "__init__" and stem in _defined_names(path):
            out.append(f"{_module_name(root, path)} defines {stem}(), named like its module")
    return out


def test_the_package_keeps_its_layers():
    assert layering_violations(SRC) == []


def test_the_core_imports_nothing_above_it():
    graph = _imports(SRC)
    core = [m for m in graph if _layer(m) == 0]
    assert "hairbed._core.solver" in core and "hairbed._core._kernels.roots" in core
    for module in core:
        assert all(_layer(t) == 0 for t in graph[module]), (module, graph[module])


# -- the rules on deliberately wrong layouts -------------------------------------------------


def _write(root: Path, files: dict[str, str]) -> Path:
    pkg = root / "hairbed"
    for name, text in files.items():
        path = pkg / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return pkg


GOOD = {
    "__init__.py": "from ._core.solver import run\nfrom . import lab\n",
    "_core/__init__.py": "",
    "_core/solver.py": "def run():\n    return 1\n",
    "lab.py": "from ._core.solver import run\n",
    "cli.py": "import hairbed\n",
}


def test_a_good_layout_passes(tmp_path):
    assert layering_violations(_write(tmp_path, GOOD)) == []


def test_import_hairbed_in_a_lab_module_is_caught(tmp_path):
    pkg = _write(tmp_path, {**GOOD, "lab.py": "def f():\n    import hairbed\n"})
    assert layering_violations(pkg) == [
        "hairbed.lab imports the package hairbed (use the module it needs)",
        "import cycle: hairbed -> hairbed.lab -> hairbed",
    ]


def test_from_hairbed_import_in_the_core_is_caught(tmp_path):
    pkg = _write(tmp_path, {**GOOD, "_core/solver.py": "from hairbed import lab\n"})
    problems = layering_violations(pkg)
    assert "hairbed._core.solver (layer 0) imports hairbed.lab (layer 1)" in problems
    assert any(p.startswith("import cycle:") for p in problems)


def test_a_lab_module_importing_an_outer_room_is_caught(tmp_path):
    pkg = _write(tmp_path, {**GOOD, "lab.py": "from .cli import main\n"})
    assert "hairbed.lab (layer 1) imports hairbed.cli (layer 2)" in layering_violations(pkg)


def test_imports_for_type_checkers_only_do_not_count(tmp_path):
    init = "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .cli import main\n"
    assert layering_violations(_write(tmp_path, {**GOOD, "lab.py": init})) == []


def test_a_cycle_between_lab_modules_is_caught(tmp_path):
    files = {**GOOD, "lab.py": "from . import other\n", "other.py": "from .lab import x\n"}
    problems = layering_violations(_write(tmp_path, files))
    assert problems == ["import cycle: hairbed.lab -> hairbed.other -> hairbed.lab"]


@pytest.mark.parametrize("kind", ["def", "class"])
def test_a_module_named_like_its_function_is_caught(tmp_path, kind):
    body = "def solve():\n    pass\n" if kind == "def" else "class solve:\n    pass\n"
    pkg = _write(tmp_path, {**GOOD, "_core/solve.py": body})
    assert layering_violations(pkg) == [
        "hairbed._core.solve defines solve(), named like its module"
    ]
