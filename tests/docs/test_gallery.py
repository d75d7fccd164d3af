"""Every script of the examples gallery (``docs/gallery/plot_*.py``) runs and draws its pictures.

The site's gallery shows what each script prints and the figures it leaves open (sphinx-gallery
runs them when the site is built); here each runs as ``python plot_NAME.py`` would, in a fresh
temporary folder with matplotlib's Agg backend, and must finish without error and draw at least
one figure with something on it. The quick scripts are in the default run; the long ones are
marked ``slow``, those that need an optional extra skip when it is absent.
"""

from __future__ import annotations

import ast
import importlib.util
import runpy
import tempfile
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt

GALLERY = Path(__file__).resolve().parents[2] / "docs" / "gallery"
SCRIPTS = sorted(GALLERY.glob("plot_*.py"))

#: Scripts that take more than a few seconds: left out of the default run.
SLOW = {"plot_holes_and_arcs.py": "decomposes a polygon with an arc and a circle into 549 blocks"}

#: Scripts that need an optional extra: the module, and the extra that installs it.
NEEDS = {"plot_partitioned_mesh.py": ("distributed", "distributed")}


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
        if importlib.util.find_spec(module) is None:
            pytest.skip(f"needs {module} (pip install -e '.[{extra}]')")
    work, temporary = tmp_path / "work", tmp_path / "tmp"
    work.mkdir()
    temporary.mkdir()
    monkeypatch.chdir(work)
    monkeypatch.setattr(tempfile, "tempdir", str(temporary))  # what the scripts write
    plt.close("all")
    try:
        runpy.run_path(str(script), run_name="__main__")
        figures = [plt.figure(n) for n in plt.get_fignums()]
        assert figures, f"{script.name} drew no figure"
        for figure in figures:
            assert any(ax.has_data() for ax in figure.axes), f"{script.name}: an empty figure"
    finally:
        plt.close("all")
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
