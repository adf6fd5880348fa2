"""What pyproject.toml promises against the files: extras, version source, py.typed, docs.

Read from the source tree (no build): a README that names an extra pyproject does not
define, a version written in two places, or a docs extension the docs extra does not
install would each make a fresh clone fail somewhere else.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

tomllib = pytest.importorskip("tomllib")  # Python 3.11+

import hairbed  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
EXTRAS = PYPROJECT["project"]["optional-dependencies"]


def _requirement_names(extra: str) -> set[str]:
    return {re.split(r"[<>=\[ ;]", r, maxsplit=1)[0].lower() for r in EXTRAS[extra]}


def test_every_extra_the_readme_names_exists():
    text = (ROOT / "README.md").read_text()
    named = set(re.findall(r"\.\[([a-z,]+)\]", text)) | set(
        re.findall(r"hairbed\[([a-z,]+)\]", text)
    )
    extras = {e for group in named for e in group.split(",")}
    assert {"plot", "io", "sweep", "app", "docs"} <= extras  # the Install section lists them
    assert extras <= set(EXTRAS), extras - set(EXTRAS)


def test_the_io_extra_writes_netcdf_as_the_readme_says():
    assert {"xarray", "netcdf4"} <= _requirement_names("io")
    assert _requirement_names("io") <= _requirement_names("sweep")


def test_the_version_is_written_once():
    attr = PYPROJECT["tool"]["setuptools"]["dynamic"]["version"]["attr"]
    module, _, name = attr.rpartition(".")
    path = ROOT / "src" / Path(*module.split(".")).with_suffix(".py")
    tree = ast.parse(path.read_text())
    values = [
        n.value.value
        for n in tree.body
        if isinstance(n, ast.Assign)
        and any(isinstance(t, ast.Name) and t.id == name for t in n.targets)
        and isinstance(n.value, ast.Constant)
    ]
    assert values == [hairbed.__version__]
    written = [
        p.relative_to(ROOT)
        for p in (ROOT / "src").rglob("*.py")
        if re.search(r"^__version__\s*=", p.read_text(), re.MULTILINE)
    ]
    assert written == [path.relative_to(ROOT)]


def test_py_typed_is_shipped():
    assert (ROOT / "src" / "hairbed" / "py.typed").is_file()
    assert "py.typed" in PYPROJECT["tool"]["setuptools"]["package-data"]["hairbed"]


def test_the_docs_extra_installs_every_sphinx_extension():
    conf = ast.parse((ROOT / "docs" / "conf.py").read_text())
    (extensions,) = [
        n.value
        for n in conf.body
        if isinstance(n, ast.Assign) and getattr(n.targets[0], "id", "") == "extensions"
    ]
    used = {ast.literal_eval(e).split(".")[0] for e in extensions.elts}
    providers = {"sphinx": "sphinx", "myst_parser": "myst-parser", "sphinxarg": "sphinx-argparse"}
    assert used <= set(providers), used - set(providers)
    assert {providers[u] for u in used} <= _requirement_names("docs")


def test_the_cli_page_has_every_command():
    """docs/api/cli.rst renders ``docs/cli_parser.parser()``: hairbed.cli.build_parser with
    hand-laid text (indented examples) as literal blocks, every command with its help."""
    import argparse
    import importlib.util

    spec = importlib.util.spec_from_file_location("cli_parser", ROOT / "docs" / "cli_parser.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    parser = module.parser()
    (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    assert {"solve", "sweep", "invert", "explore", "calibrate", "measure"} <= set(sub.choices)
    for name, command in sub.choices.items():
        for text in (command.description, command.epilog):
            if text and "\n " in text:  # indented lines survive only inside a literal block
                assert text.startswith(".. code-block:: text\n\n"), name
