"""A refinement fetches its level's template once per call, not once per block or group."""

from __future__ import annotations

import sys

import pytest

import blockmesh
import blockmesh.refinement.template as template_module


@pytest.fixture
def fetches(monkeypatch):
    """Count the calls of pentagon_template made through every module that imported it."""
    calls: list[int] = []
    original = template_module.pentagon_template

    def counting(level: int):
        calls.append(level)
        return original(level)

    for module in list(sys.modules.values()):
        if getattr(module, "pentagon_template", None) is original:
            monkeypatch.setattr(module, "pentagon_template", counting)
    return calls


@pytest.mark.parametrize(
    ("name", "level", "options", "expected"),
    [
        ("square-cut", 3, {}, [3]),
        ("annulus", 3, {}, [3]),
        ("square-cut", 3, {"smooth": 2}, [3]),
        ("sp", 8, {}, [2, 6]),  # deeper than BLOCK_LEVEL: two stages, a template each
    ],
)
def test_one_template_per_call(fetches, name, level, options, expected):
    domain = blockmesh.load_domain(name)
    blockmesh.refine(domain, level, **options)  # fills the per-level pattern caches
    fetches.clear()
    blockmesh.refine(domain, level, **options)
    assert sorted(fetches) == expected
