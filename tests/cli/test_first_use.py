"""What a new user tripped over (issue 22, item 4): mesh files, --json, options, pictures."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import run_cli

import blockmesh


@pytest.fixture
def l_shape_file(tmp_path):
    """The l-shape at level 1 saved as .npz (24 blocks, 144 cells)."""
    return blockmesh.write(blockmesh.load_domain("l-shape").mesh(1), tmp_path / "l.npz")


# ------------------------------------------------------------------ mesh files keep their level
def test_a_mesh_file_keeps_its_level_without_level(capsys, l_shape_file):
    """`blockmesh mesh FILE` added 2 levels (the default for a domain) where `integrate FILE`
    used the file's own level; now a mesh file is refined only when --level asks for it."""
    code, out, err = run_cli(capsys, "mesh", str(l_shape_file), "--json")
    report = json.loads(out)
    assert code == 0, err
    assert report["level"] == 1 and report["cells"] == 24 * 6
    code, out, err = run_cli(capsys, "mesh", str(l_shape_file), "--level", "1", "--json")
    assert code == 0 and json.loads(out)["level"] == 2 and json.loads(out)["cells"] == 24 * 36


def test_a_catalogue_domain_still_defaults_to_level_2(capsys):
    code, out, err = run_cli(capsys, "mesh", "l-shape", "--json")
    assert code == 0 and json.loads(out)["level"] == 2


def test_mesh_help_says_what_the_default_level_is_for_a_mesh_file(capsys):
    with pytest.raises(SystemExit):
        run_cli(capsys, "mesh", "--help")
    text = " ".join(capsys.readouterr().out.split())
    assert "a mesh file keeps its own level" in text


# --------------------------------------------------------------- --level 0 keeps the parents
def test_refining_zero_times_keeps_every_array():
    mesh = blockmesh.load_domain("l-shape").mesh(2)
    for smooth in (0, 1):
        same = blockmesh.refine(mesh, 0, smooth=smooth)
        assert np.array_equal(same.parent, mesh.parent), smooth
        assert np.array_equal(same.block_id, mesh.block_id)
        assert np.array_equal(same.cells, mesh.cells) and same.level == mesh.level


def test_level_0_re_export_keeps_the_parents(capsys, tmp_path, l_shape_file):
    """`mesh FILE --level 0 -o OUT` reset `parent` to -1 (the block mesh's value)."""
    out_path = tmp_path / "again.vtu"
    code, out, err = run_cli(capsys, "mesh", str(l_shape_file), "--level", "0", "-o", str(out_path))
    assert code == 0, err
    again, before = blockmesh.read(out_path), blockmesh.read(l_shape_file)
    assert np.array_equal(again.parent, before.parent) and again.parent.max() == 23
    assert again.level == 1
