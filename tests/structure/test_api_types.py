"""Bad argument types at the public entry points raise the library's own errors (issue 14).

A raw ``TypeError``, ``AttributeError`` or ``ValueError`` from deep inside (``expected str,
bytes or os.PathLike object, not NoneType``; ``'float' object is not iterable``) names neither
the argument nor the call; every case here must raise a :class:`blockmesh.BlockMeshError` with a
message saying what was expected.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import blockmesh
from blockmesh import BlockMeshError

BAD = [None, 3.5, [1, 2], object()]
SP = blockmesh.load_domain("sp")
MESH = SP.mesh(1)


def calls(tmp: Path, bad: object) -> dict[str, tuple]:
    """Name -> (callable, args, kwargs): each passes ``bad`` where something else belongs."""
    mapping = "not a mapping" if bad is None else bad  # None means "none" for these
    return {
        "write(path)": (blockmesh.write, (MESH, bad), {}),
        "write(mesh)": (blockmesh.write, (bad, tmp / "m.vtu"), {}),
        "read(path)": (blockmesh.read, (bad,), {}),
        "Domain.write_toml(path)": (SP.write_toml, (bad,), {}),
        "from_blocks(patches)": (
            blockmesh.Domain.from_blocks,
            (SP.vertices, SP.blocks),
            {"patches": mapping},
        ),
        "from_blocks(regions)": (
            blockmesh.Domain.from_blocks,
            (SP.vertices, SP.blocks),
            {"regions": mapping},
        ),
        "from_blocks(vertices)": (blockmesh.Domain.from_blocks, (bad, SP.blocks), {}),
        "from_polygon(coords)": (blockmesh.Domain.from_polygon, (bad,), {}),
        "Mesh.renumbered(order)": (MESH.renumbered, (bad,), {}),
        "refine(level)": (blockmesh.refine, (SP, bad), {}),
        "refine(domain)": (blockmesh.refine, (bad, 1), {}),
        "integrate(f)": (blockmesh.integrate, (SP, bad), {"order": 3, "level": 1}),
        "integrate(order)": (blockmesh.integrate, (SP, "x"), {"order": bad}),
        "exact_integral(f)": (blockmesh.exact_integral, (SP, bad), {}),
        "load_domain(source)": (blockmesh.load_domain, (bad,), {}),
    }


@pytest.mark.parametrize("bad", BAD, ids=lambda b: type(b).__name__)
@pytest.mark.parametrize("name", list(calls(Path("."), None)))
def test_bad_argument_types_raise_library_errors(tmp_path, name, bad):
    func, args, kwargs = calls(tmp_path, bad)[name]
    with pytest.raises(BlockMeshError) as caught:
        func(*args, **kwargs)
    assert str(caught.value)  # a message, naming what was wrong
    assert list(tmp_path.iterdir()) == []


def test_paths_may_be_str_or_pathlike(tmp_path):
    assert blockmesh.write(MESH, str(tmp_path / "a.npz")).name == "a.npz"
    assert blockmesh.read(tmp_path / "a.npz").n_cells == MESH.n_cells
    SP.write_toml(tmp_path / "sp.toml")
    assert np.array_equal(blockmesh.load_domain(tmp_path / "sp.toml").blocks, SP.blocks)
