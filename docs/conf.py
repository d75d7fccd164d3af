"""Sphinx configuration of the blockmesh documentation site.

Build (after ``pip install -e '.[docs]'``)::

    python -m sphinx -W --keep-going -b html docs docs/_build/html

Pages are Markdown (MyST); the API reference is generated from the package's numpydoc docstrings
(autosummary, recursive over the ``blockmesh`` package, so it follows the package layout); the
examples gallery runs ``docs/gallery/plot_*.py`` (sphinx-gallery) and keeps the pictures they draw.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))  # the blockmesh of this checkout, even without an install

import blockmesh  # noqa: E402

project = "blockmesh"
author = "the blockmesh authors"
copyright = "the blockmesh authors, MIT licence"
version = release = blockmesh.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "gallery/README.rst", "**/README.md"]
templates_path = ["_templates"]

# MyST: headings get anchors (links such as ``refinement.md#memory-guard``), $...$ maths.
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# The API reference.
autosummary_generate = True
autosummary_ignore_module_all = True  # each module page lists what the module itself defines
autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "signature"
numpydoc_show_class_members = False  # the class template lists the members itself
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()

html_theme = "pydata_sphinx_theme"
html_title = f"blockmesh {release}"
html_static_path: list[str] = []
html_theme_options = {
    "navigation_depth": 2,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
}

sphinx_gallery_conf = {
    "examples_dirs": "gallery",
    "gallery_dirs": "auto_gallery",
    "filename_pattern": r"/plot_",
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "matplotlib_animations": False,
    "remove_config_comments": True,
}


def _public_names() -> dict[str, str]:
    """Where each top-level name is documented: ``blockmesh.Name`` -> ``home.module.Name``."""
    homes = {}
    for name in blockmesh.__all__:
        value = getattr(blockmesh, name)
        homes[f"blockmesh.{name}"] = f"{value.__module__}.{value.__qualname__}"
    return homes


PUBLIC = _public_names()
autosummary_context = {"public_api": sorted(blockmesh.__all__, key=str.lower)}


def _resolve_public(app: Any, env: Any, node: Any, contnode: Any) -> Any:
    """Link ``blockmesh.Name`` (the names users type) to the page of the module that defines it."""
    if node.get("refdomain") != "py":
        return None
    target = node.get("reftarget", "")
    home = PUBLIC.get(target)
    if home is None:
        return None
    domain = env.get_domain("py")
    node = node.deepcopy()
    node["reftarget"] = home
    return domain.resolve_xref(
        env, node.get("refdoc", ""), app.builder, node["reftype"], home, node, contnode
    )


def setup(app: Any) -> None:
    """Sphinx's hook: link the top-level names."""
    app.connect("missing-reference", _resolve_public)
