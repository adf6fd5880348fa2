"""The documentation's code examples, as a new user meets them.

Every Python example of README.md, docs/index.md and docs/api/*.rst (```python fences,
``.. code-block:: python`` and ``::`` literal blocks that start with an import or a prompt)
must parse, and every name it uses must be defined by an earlier line of the same page or be
a builtin: an example that reads ``t``, ``x`` or ``bed`` from nowhere fails here (a static
check, milliseconds; running every example costs minutes). The quick start of
docs/index.md, whose outputs are printed, runs as a doctest.
"""

from __future__ import annotations

import ast
import builtins
import doctest
import re
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [
    ROOT / "README.md",
    ROOT / "docs" / "index.md",
    *sorted((ROOT / "docs" / "api").glob("*.rst")),
]


def _blocks(path: Path) -> list[tuple[int, str]]:
    """(line, source) of each Python example of a page, prompts stripped."""
    text = path.read_text(encoding="utf-8")
    found = [(m.start(), m.group(1)) for m in re.finditer(r"```python\n(.*?)```", text, re.S)]
    if path.suffix == ".rst":
        lines = text.split("\n")
        i = 0
        while i < len(lines):
            if lines[i].rstrip().endswith("::") or lines[i].strip() == ".. code-block:: python":
                j = i + 1
                while j < len(lines) and not lines[j].strip():
                    j += 1
                body = []
                while j < len(lines) and (lines[j].startswith("   ") or not lines[j].strip()):
                    body.append(lines[j])
                    j += 1
                block = textwrap.dedent("\n".join(body))
                if re.match(r"\s*(import |from |>>> )", block):
                    found.append((sum(len(x) + 1 for x in lines[:i]), block))
                i = j
            else:
                i += 1
    out = []
    for start, block in sorted(found):
        if ">>>" in block:
            block = "\n".join(
                line[4:] for line in block.splitlines() if line.startswith((">>> ", "... "))
            )
        out.append((text[:start].count("\n") + 1, block))
    return out


def _bound(node: ast.AST) -> set[str]:
    """The names a statement binds (assignments, imports, loops, defs, with, walrus), and
    the local names of its lambdas and comprehensions."""
    names: set[str] = set()
    for sub in ast.walk(node):
        if isinstance(sub, ast.Name) and isinstance(sub.ctx, (ast.Store, ast.Del)):
            names.add(sub.id)
        elif isinstance(sub, (ast.Import, ast.ImportFrom)):
            names.update((a.asname or a.name).split(".")[0] for a in sub.names)
        elif isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(sub.name)
        elif isinstance(sub, ast.arg):
            names.add(sub.arg)
    return names


def _undefined(blocks: list[tuple[int, str]]) -> list[str]:
    defined = set(dir(builtins))
    missing = []
    for line, source in blocks:
        tree = ast.parse(source, filename=f"line {line}")
        for stmt in tree.body:
            local = _bound(stmt) if not isinstance(stmt, ast.Assign) else set()
            if isinstance(stmt, ast.Assign):  # the right side is read before the targets bind
                local = {a.arg for a in ast.walk(stmt.value) if isinstance(a, ast.arg)}
                local |= {
                    n.id
                    for c in ast.walk(stmt.value)
                    if isinstance(c, ast.comprehension)
                    for n in ast.walk(c.target)
                    if isinstance(n, ast.Name)
                }
            for sub in ast.walk(stmt):
                if (
                    isinstance(sub, ast.Name)
                    and isinstance(sub.ctx, ast.Load)
                    and sub.id not in defined
                    and sub.id not in local
                ):
                    missing.append(f"line {line + sub.lineno - 1}: {sub.id}")
            defined |= _bound(stmt)
    return missing


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_example_parses_and_defines_its_names(page):
    blocks = _blocks(page)
    assert _undefined(blocks) == []


def test_the_pages_have_examples():
    """The extraction finds what it should (a regex that found nothing would pass above)."""
    counts = {p.name: len(_blocks(p)) for p in PAGES}
    assert counts["README.md"] >= 10 and counts["index.md"] >= 2
    assert counts["design.rst"] >= 3 and counts["porous.rst"] >= 3
    assert counts["rheometer.rst"] >= 1 and counts["units.rst"] >= 2


def test_the_quick_start_runs_as_written():
    """docs/index.md's quick start: the printed values are the paper's worked example."""
    text = (ROOT / "docs" / "index.md").read_text(encoding="utf-8")
    source = "".join(re.findall(r"```python\n(.*?)```", text, re.S))
    test = doctest.DocTestParser().get_doctest(source, {}, "index.md", "docs/index.md", 0)
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    result = runner.run(test)
    assert result.attempted >= 8 and result.failed == 0


def test_the_design_spec_example_is_the_pages_and_reads():
    """docs/examples/valve.toml (named in ``hairbed design --help``) is the spec that
    docs/api/design.rst prints, and it reads as a design problem (no optimisation here:
    tests/test_cli_design.py runs specs)."""
    tomllib = pytest.importorskip("tomllib")  # Python 3.11+, as hairbed design itself
    from hairbed.design import _spec

    spec = tomllib.loads((ROOT / "docs" / "examples" / "valve.toml").read_text())
    page = (ROOT / "docs" / "api" / "design.rst").read_text(encoding="utf-8")
    block = re.search(r"source tree\)::\n\n((?:   .*\n|\n)+)", page)
    assert block is not None
    assert tomllib.loads(textwrap.dedent(block.group(1))) == spec
    assert spec["objective"]["quantity"] in _spec.QUANTITIES
    assert all(c["quantity"] in _spec.QUANTITIES for c in spec["constraints"])
