"""One name sanitiser for every format (OpenFOAM words, MATLAB identifiers, Gmsh names)."""

from __future__ import annotations

import re

from hypothesis import given
from hypothesis import strategies as st

from blockmesh.io.names import FOAM_WORD, GMSH_NAME, MATLAB_NAME


@given(st.lists(st.text(max_size=80), min_size=1, max_size=8))
def test_names_become_valid_and_distinct(names: list[str]) -> None:
    for rule, valid in (
        (FOAM_WORD, r"[A-Za-z_][A-Za-z0-9_.:-]*"),
        (MATLAB_NAME, r"[A-Za-z][A-Za-z0-9_]{0,62}"),
        (GMSH_NAME, r'[^"\r\n]*'),
    ):
        out = rule.unique(names, taken={"frontAndBack"})
        assert len(set(out)) == len(out) == len(names)
        assert "frontAndBack" not in out
        assert all(re.fullmatch(valid, w) for w in out), (rule.what, out)


def test_valid_names_are_kept() -> None:
    for rule in (FOAM_WORD, MATLAB_NAME, GMSH_NAME):
        assert rule.unique(["inlet", "outlet"]) == ["inlet", "outlet"]
    assert MATLAB_NAME.unique(["a" * 70, "a" * 70]) == ["a" * 63, "a" * 61 + "_2"]
