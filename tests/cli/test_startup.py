"""Fast start: --help and --version import no numerical library; every public name still loads."""

from __future__ import annotations

import argparse
import subprocess
import sys

import pytest

import blockmesh
from blockmesh.commands import SUMMARIES, load

PROBE = """
import sys
from blockmesh.cli import main
try:
    main({argv!r})
except SystemExit:
    pass
heavy = sorted(m for m in ("numpy", "scipy", "shapely", "networkx", "matplotlib", "meshio", "h5py")
               if m in sys.modules)
print(",".join(heavy) or "none")
"""


@pytest.mark.parametrize("argv", [["--version"], ["--help"], []])
def test_help_and_version_import_nothing_heavy(argv):
    out = subprocess.run(
        [sys.executable, "-c", PROBE.format(argv=argv)], capture_output=True, text=True, check=True
    )
    assert out.stdout.strip().splitlines()[-1] == "none"


FORMAT_MODULES = [
    f"blockmesh.io.{name}" for name in ("vtu", "vtk", "xdmf", "msh", "mat", "openfoam", "npz")
]

MODULES_PROBE = """
import sys
import numpy  # what numpy loads by itself is not the command's doing (numpy 1.x loads secrets)
before = set(sys.modules)
from blockmesh.cli import main
assert main({argv!r}) == 0
print(",".join(m for m in {names!r} if m in sys.modules and m not in before) or "none")
"""


def _loaded(argv: list[str], names: list[str], cwd) -> list[str]:
    """Which of ``names`` a fresh interpreter has loaded after ``blockmesh ARGV``."""
    out = subprocess.run(
        [sys.executable, "-c", MODULES_PROBE.format(argv=argv, names=names)],
        cwd=cwd,
        capture_output=True,
        text=True,
        check=True,
    )
    last = out.stdout.strip().splitlines()[-1]
    return [] if last == "none" else last.split(",")


def test_meshing_without_output_imports_no_export_format(tmp_path):
    names = [*FORMAT_MODULES, "socket", "secrets", "blockmesh.refinement"]
    assert _loaded(["mesh", "sp", "--level", "1"], names, tmp_path) == ["blockmesh.refinement"]


def test_writing_imports_the_formats(tmp_path):
    assert _loaded(["mesh", "sp", "--level", "1", "-o", "m.vtu"], FORMAT_MODULES, tmp_path) == (
        FORMAT_MODULES
    )
    assert (tmp_path / "m.vtu").is_file()


def test_import_blockmesh_is_lazy():
    code = "import sys, blockmesh; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_every_public_name_is_importable():
    for name in blockmesh.__all__:
        assert getattr(blockmesh, name) is not None, name
    namespace: dict = {}
    exec("from blockmesh import *", namespace)
    assert set(blockmesh.__all__) <= set(namespace)
    assert set(blockmesh.__all__) <= set(dir(blockmesh))
    assert blockmesh.__all__ == sorted(blockmesh._EXPORTS)
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        blockmesh.nonsense  # noqa: B018


@pytest.mark.parametrize("name", list(SUMMARIES))
def test_summaries_are_the_registered_help(name):
    parser = argparse.ArgumentParser()
    subparsers = parser.add_subparsers()
    load(name).register(subparsers)
    (action,) = subparsers._choices_actions
    assert action.help == SUMMARIES[name]


def test_load_domain_imports_no_scipy():
    code = (
        "import sys, blockmesh\n"
        "from blockmesh.domain.catalogue import catalogue_names\n"
        "for name in catalogue_names():\n"
        "    blockmesh.load_domain(name)\n"
        "print(sorted({m.split('.')[1] for m in sys.modules if m.startswith('scipy.')}))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert "spatial" not in out.stdout and "sparse" not in out.stdout, out.stdout
