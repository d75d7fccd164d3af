"""Every public name of release 0.1 still imports, from the path it had (moved ones with a warning).

``tests/data/public-names-0.1.json`` is every module of release 0.1 with its ``__all__``, as it was
before the stage packages (issue 21). A module that moved still imports from its old path with a
DeprecationWarning naming the new one; a module that stayed (or became a package of the same
name) gives its names without a warning. Private modules (a part of the path starting with ``_``,
such as ``blockmesh.commands._common``) are the package's own business and are left out.
"""

from __future__ import annotations

import importlib
import json
import warnings
from pathlib import Path

import pytest

import blockmesh
from blockmesh._moved import MOVED

SNAPSHOT = json.loads(
    (Path(__file__).parents[1] / "data" / "public-names-0.1.json").read_text(encoding="utf-8")
)


PUBLIC = sorted(m for m in SNAPSHOT if not any(part.startswith("_") for part in m.split(".")))


@pytest.mark.parametrize("module", PUBLIC)
def test_every_name_of_release_0_1_imports_from_its_old_path(module):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        imported = importlib.import_module(module)
        missing = [name for name in SNAPSHOT[module] if not hasattr(imported, name)]
    assert missing == []
    moved = module in MOVED or any(
        issubclass(w.category, DeprecationWarning) and "moved to" in str(w.message) for w in caught
    )
    if module not in MOVED and module != "blockmesh.decompose.conversion":
        assert not moved, [str(w.message) for w in caught]


def test_the_top_level_names_need_no_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        for name in blockmesh.__all__:
            assert getattr(blockmesh, name) is not None


def test_an_old_path_names_its_new_home():
    with pytest.warns(DeprecationWarning, match="blockmesh.template moved to blockmesh.refinement"):
        importlib.reload(importlib.import_module("blockmesh.template"))
