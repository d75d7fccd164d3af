"""What a command imports: only what it uses (start-up time is part of every command's cost)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

FORMAT_MODULES = {
    "blockmesh.io.vtu",
    "blockmesh.io.legacy_vtk",
    "blockmesh.io.xdmf",
    "blockmesh.io.msh",
    "blockmesh.io.mat",
    "blockmesh.io.openfoam",
    "blockmesh.io.npz",
}


def _modules_after(argv: list[str], cwd) -> set[str]:
    """The modules loaded once ``blockmesh ARGV`` has run, in a fresh interpreter."""
    code = (
        "import json, sys\n"
        "from blockmesh.cli import main\n"
        "try:\n"
        f"    code = main({argv!r})\n"
        "except SystemExit as stop:\n"
        "    code = stop.code\n"
        "assert code in (0, None), code\n"
        "sys.stderr.write(json.dumps(sorted(sys.modules)))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=cwd, capture_output=True, text=True, check=True
    )
    return set(json.loads(done.stderr.strip().splitlines()[-1]))


@pytest.mark.parametrize("argv", [["--version"], ["--help"]])
def test_version_and_help_import_no_numerical_library(argv, tmp_path):
    loaded = _modules_after(argv, tmp_path)
    assert not {"numpy", "shapely", "scipy", "networkx", "meshio"} & loaded


def test_meshing_without_output_imports_no_export_format(tmp_path):
    loaded = _modules_after(["mesh", "sp", "--level", "1"], tmp_path)
    assert "blockmesh.refinement" in loaded
    assert not FORMAT_MODULES & loaded
    assert not {"socket", "secrets"} & loaded


def test_writing_imports_the_formats(tmp_path):
    loaded = _modules_after(["mesh", "sp", "--level", "1", "-o", "m.vtu"], tmp_path)
    assert FORMAT_MODULES.issubset(loaded)
    assert (tmp_path / "m.vtu").is_file()
