"""Sphinx configuration of the hairbed documentation (``make docs``).

The figure gallery is drawn while the configuration loads: every figure of
:data:`hairbed.plotting.FIGURES` is written into ``docs/_generated/figures`` (git-ignored)
and ``docs/_generated/gallery.md`` lists them with their docstrings. The figures are redrawn
only when a source file of the package is newer than the gallery page. The tables of
``hairbed._variables`` are written into ``docs/_generated/variables.rst`` (every build).
"""

from __future__ import annotations

import inspect
import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(DOCS))  # cli_parser, for the command line's page
os.environ.setdefault("MPLBACKEND", "Agg")

import hairbed  # noqa: E402

project = "hairbed"
author = "the hairbed developers"
copyright = "2026, the hairbed developers"
release = hairbed.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.viewcode",
    "sphinxarg.ext",  # the command line's page, from hairbed.cli.build_parser
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "figures", "README.md", "_generated/variables.rst"]
myst_heading_anchors = 3
suppress_warnings = ["myst.xref_missing"]

# numpydoc-style docstrings through napoleon
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True  # "Attributes" as fields: no duplicate of a dataclass's members
napoleon_preprocess_types = False
autodoc_typehints = "none"  # the docstrings carry the types and units [brackets]
autodoc_member_order = "bysource"
# the members the results inherit (success and message from StatusResult and
# CollocatedState), none of the builtins' members
autodoc_default_options = {
    "members": True,
    "show-inheritance": False,
    "inherited-members": "BaseException,ImportError,ValueError,Exception,Warning,UserWarning,"
    "tuple,dict,list,str,int,float,Mapping",
}
autosummary_generate = False
add_module_names = False

html_theme = "alabaster"  # shipped with Sphinx: nothing is fetched when the pages are read
html_static_path: list[str] = []
html_title = f"hairbed {release}"
html_theme_options = {"description": "Exact shapes of a hair bed bent by channel flow"}


def _stale(stamp: Path) -> bool:
    if not stamp.exists():
        return True
    built = stamp.stat().st_mtime
    sources = list((ROOT / "src" / "hairbed").rglob("*.py")) + [Path(__file__)]
    return any(p.stat().st_mtime > built for p in sources)


def _first_paragraph(func: object) -> str:
    doc = inspect.getdoc(func) or ""
    return doc.split("\n\n", 1)[0].replace("\n", " ").strip()


def _rest_of_docstring(func: object) -> str:
    doc = inspect.getdoc(func) or ""
    parts = doc.split("\n\n")
    keep = []
    for part in parts[1:]:
        if part.lstrip().startswith(("Parameters", "Returns", "Examples", "Notes\n-", "See Also")):
            break
        keep.append(part)
    return "\n\n".join(keep)


def make_gallery() -> None:
    """Draw every figure and write the gallery page (skipped while the page is up to date)."""
    from hairbed.plotting import FIGURES, make_all

    out = DOCS / "_generated"
    page = out / "gallery.md"
    if not _stale(page):
        return
    make_all(out / "figures", dpi=110, verbose=False)
    lines = [
        "# Figure gallery",
        "",
        "Every figure of `hairbed.plotting`, drawn from the exact solution while these pages were",
        "built (`python -m hairbed figures --out DIR` writes the same PNGs). The paper's figures",
        "carry the paper's numbers (arXiv:2203.04169); the others are new. The text under each",
        "figure is the docstring of the function that draws it.",
        "",
    ]
    for name, func in FIGURES.items():
        lines += [
            f"## `{func.__name__}`",
            "",
            f"```{{figure}} figures/{name}.png",
            f":alt: {name}",
            ":width: 100%",
            "",
            _first_paragraph(func),
            "```",
            "",
        ]
        rest = _rest_of_docstring(func)
        if rest:
            lines += ["```text", rest, "```", ""]
        lines += [f"API: {{func}}`hairbed.plotting.{func.__name__}`", ""]
    page.write_text("\n".join(lines))


def make_variables_table() -> None:
    """Write every table of ``hairbed._variables`` as a list-table (included by the API)."""
    from hairbed._variables import BED, PILLAR, SI, SOLUTION, WINDOW

    out = DOCS / "_generated"
    out.mkdir(exist_ok=True)
    lines: list[str] = []
    for title, table in (
        ("The dimensionless problem (SOLUTION)", SOLUTION),
        ("A bed's parameters (BED)", BED),
        ("A bed's state in SI units (SI)", SI),
        ("The bistable window of a pair (eps, theta0) (WINDOW)", WINDOW),
        ("An isolated pillar in a shear layer (PILLAR)", PILLAR),
    ):
        lines += [title, "-" * len(title), "", ".. list-table::", "   :header-rows: 1", ""]
        lines += [
            f"   * - {h}" if i == 0 else f"     - {h}"
            for i, h in enumerate(("name", "group", "CF units", "label [unit]", "description"))
        ]
        for v in table.values():
            cells = (f"``{v.name}``", v.group, f"``{v.units}``", v.heading, v.description)
            for i, cell in enumerate(cells):
                text = cell.replace("*", "\\*").replace("|", "\\|")
                lines.append(f"   * - {text}" if i == 0 else f"     - {text}")
        lines.append("")
    target = out / "variables.rst"
    text = "\n".join(lines)
    if not target.exists() or target.read_text() != text:  # unchanged: no rebuild of the page
        target.write_text(text)


make_gallery()
make_variables_table()
