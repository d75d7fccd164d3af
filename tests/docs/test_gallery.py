"""Every script of the examples gallery (``docs/gallery/plot_*.py``) runs and draws its pictures.

The site's gallery shows what each script prints and the figures each of its cells leaves open
(sphinx-gallery runs the scripts cell by cell, ``# %%`` apart, when the site is built); here each
runs the same way, in a fresh temporary folder with matplotlib's Agg backend, and must finish
without error and draw at least one figure, every panel of every figure with something on it as
the cell that drew it left it. The quick scripts are in the default run; the long ones are
marked ``slow``, those that need an optional extra skip when it is absent.
"""

from __future__ import annotations

import ast
import itertools
import re
import tempfile
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from helpers import missing

GALLERY = Path(__file__).resolve().parents[2] / "docs" / "gallery"
SCRIPTS = sorted(GALLERY.glob("plot_*.py"))

#: Scripts that take more than a few seconds: left out of the default run.
SLOW = {"plot_holes_and_arcs.py": "decomposes a polygon with an arc and a circle into 549 blocks"}

#: Scripts that need an optional extra: the module, and the extra that installs it.
NEEDS = {"plot_partitioned_mesh.py": ("dask.distributed", "distributed")}


def _cells(source: str) -> list[str]:
    """The script's cells (split at ``# %%`` lines), each padded to keep its line numbers."""
    lines = source.splitlines(keepends=True)
    starts = [0] + [i for i, line in enumerate(lines) if re.match(r"# %%", line)] + [len(lines)]
    return ["\n" * a + "".join(lines[a:b]) for a, b in itertools.pairwise(starts)]


def _params() -> list:
    return [
        pytest.param(path, id=path.stem, marks=[pytest.mark.slow] if path.name in SLOW else [])
        for path in SCRIPTS
    ]


@pytest.mark.parametrize("script", _params())
def test_gallery_script_runs_and_draws(
    script: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    if script.name in NEEDS:
        module, extra = NEEDS[script.name]
        if missing(module):
            pytest.skip(f"needs {module} (pip install -e '.[{extra}]')")
    work, temporary = tmp_path / "work", tmp_path / "tmp"
    work.mkdir()
    temporary.mkdir()
    monkeypatch.chdir(work)
    monkeypatch.setattr(tempfile, "tempdir", str(temporary))  # what the scripts write
    plt.close("all")
    source = script.read_text(encoding="utf-8")
    namespace = {"__name__": "__main__", "__file__": str(script)}
    pictures = []
    try:
        for cell in _cells(source):
            exec(compile(cell, str(script), "exec"), namespace)
            for number in plt.get_fignums():  # the pictures as sphinx-gallery saves them
                figure = plt.figure(number)
                pictures += [(ax.get_title(), ax.has_data()) for ax in figure.axes]
            plt.close("all")
    finally:
        plt.close("all")
    assert pictures, f"{script.name} drew no figure"
    for title, drawn in pictures:
        assert drawn, f"{script.name}: the panel {title!r} is empty when its cell ends"
    assert list(work.iterdir()) == [], f"{script.name} wrote into its working folder"


def test_gallery_scripts_are_pages() -> None:
    """Each script opens with a titled docstring (the gallery's page title), and the gallery has
    between 6 and 10 of them; SLOW and NEEDS name scripts that exist."""
    assert 6 <= len(SCRIPTS) <= 10
    names = {path.name for path in SCRIPTS}
    assert set(SLOW) <= names and set(NEEDS) <= names
    for path in SCRIPTS:
        doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8")), clean=True)
        assert doc, f"{path.name} has no docstring"
        title, underline = doc.splitlines()[:2]
        assert title and set(underline) == {"="} and len(underline) >= len(title), path.name
    assert (GALLERY / "README.rst").is_file()
