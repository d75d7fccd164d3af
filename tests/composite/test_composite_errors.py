"""Bad composite input: each problem one located message naming the parts (issue 23, item 5)."""

from __future__ import annotations

import warnings

import pytest
import shapely
from helpers import run_cli

from blockmesh import BlockMeshWarning, Domain, DomainError, DomainFormatError, SolverError
from blockmesh.vem import solve_poisson

box = shapely.box


def test_a_partial_overlap_is_resolved_by_the_rule():
    # The later part is cut out of the earlier: a keeps [0, 1] x [0, 1].
    d = Domain.compose({"a": box(0, 0, 2, 1), "b": box(1, 0, 3, 1)})
    assert d.region_names == ("a", "b") and d.interface_names == ("a|b",)
    areas = d.block_areas()
    assert areas[d.region == 0].sum() == pytest.approx(1.0) and d.area == pytest.approx(3.0)


def test_a_part_left_empty_names_the_parts():
    with pytest.raises(
        DomainError, match=r"part 0 \('a'\) is covered entirely by the later part 1"
    ):
        Domain.compose({"a": box(0, 0, 1, 1), "b": box(-1, -1, 2, 2)})


def test_a_sliver_names_the_parts_and_the_point():
    with pytest.raises(
        DomainError,
        match=r"a sliver of part 0 \('a'\) is only 1e-09 wide near \(1\.0000000005, 0\.5\).*"
        r"part 0 \('a'\) and part 1 \('b'\)",
    ):
        Domain.compose({"a": box(0, 0, 1 + 1e-9, 1), "b": box(1, 0, 2, 0.5)})


def test_a_gap_names_the_parts_and_the_point():
    with pytest.raises(
        DomainError,
        match=r"part 0 \('a'\) and part 1 \('b'\) come within 1e-09 of each other near "
        r"\(0\.999999999, 0\) without meeting",
    ):
        Domain.compose({"a": box(0, 0, 1 - 1e-9, 1), "b": box(1, 0, 2, 1)})


def test_parts_touching_at_a_point_only():
    with pytest.raises(
        DomainError, match=r"part 0 \('a'\) and part 1 \('b'\) touch at the single point \(1, 1\)"
    ):
        Domain.compose({"a": box(0, 0, 1, 1), "b": box(1, 1, 2, 2)})
    # A fibre touching the matrix's edge from inside pinches the matrix.
    with pytest.raises(DomainError, match=r"touches itself at the single point \(1, 0\)"):
        Domain.compose(
            {"m": box(0, 0, 2, 2), "f": {"circles": [{"center": [1, 0.5], "radius": 0.5}]}}
        )
    # Nearly touching is a sliver, reported as such.
    with pytest.raises(DomainError, match=r"a sliver of part 0 \('m'\) is only 1e-09 wide"):
        Domain.compose(
            {"m": box(0, 0, 2, 2), "f": {"circles": [{"center": [1, 0.5 + 1e-9], "radius": 0.5}]}}
        )


def test_a_region_given_twice():
    text = """
[[parts]]
region = "a"
polygon = [[0, 0], [1, 0], [1, 1]]
[[parts]]
region = "a"
polygon = [[1, 0], [2, 0], [1, 1]]
"""
    with pytest.raises(
        DomainError, match=r"the region 'a' is given twice, by part 0 \('a'\) and part 1 \('a'\)"
    ):
        Domain.from_toml_text(text)


def test_a_hole_filled_by_another_part_is_read_as_an_interface_and_said_so():
    plate = box(0, 0, 2, 2).difference(box(0.5, 0.5, 1.5, 1.5))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        d = Domain.compose({"plate": plate, "insert": box(0.5, 0.5, 1.5, 1.5)})
    assert d.interface_names == ("plate|insert",) and d.area == pytest.approx(4.0)
    (warning,) = [w for w in caught if issubclass(w.category, BlockMeshWarning)]
    assert str(warning.message) == (
        "hole 0 of part 0 ('plate') is not empty: part 1 ('insert') fills it, so its edge is "
        "read as the interface 'plate|insert' between them (a hole stays empty only where no "
        "part covers it)"
    )


def test_an_interface_named_like_a_boundary_patch():
    with pytest.raises(DomainError, match="interface 'left' has the name of a boundary patch"):
        Domain.compose(
            {"a": box(0, 0, 1, 1), "b": box(1, 0, 2, 1)},
            patches={"a": {"left": [2]}},  # shapely's box runs (1,0),(1,1),(0,1),(0,0): 2 is x = 0
            interfaces={"a|b": "left"},
        )
    with pytest.raises(DomainError, match="interface 'a|c' names the region 'c'"):
        Domain.compose({"a": box(0, 0, 1, 1), "b": box(1, 0, 2, 1)}, interfaces={"a|c": "glue"})


def test_bad_parts_tables():
    with pytest.raises(DomainFormatError, match=r"parts entry 0 needs region"):
        Domain.from_toml_text("[[parts]]\npolygon = [[0, 0], [1, 0], [1, 1]]")
    with pytest.raises(DomainFormatError, match=r"parts entry 0 has the unknown key 'vertices'"):
        Domain.from_toml_text('[[parts]]\nregion = "a"\nvertices = [[0, 0]]')
    with pytest.raises(
        DomainFormatError, match=r"with \[\[parts\]\], the geometry is in the parts"
    ):
        Domain.from_toml_text('polygon = [[0, 0], [1, 0], [1, 1]]\n[[parts]]\nregion = "a"')
    with pytest.raises(DomainError, match=r"part 0 \('a'\) is not a valid polygon \(self-inter"):
        Domain.compose({"a": shapely.Polygon([(0, 0), (1, 1), (1, 0), (0, 1)])})


def test_a_condition_on_an_interface_is_refused_naming_it():
    mesh = Domain.compose({"a": box(0, 0, 1, 1), "b": box(1, 0, 2, 1)}).mesh(1)
    with pytest.raises(SolverError, match=r"dirichlet condition on 'a\|b': that is an interface"):
        solve_poisson(mesh, 0, dirichlet={"a|b": 0, "boundary": 1})


def test_cli_errors_are_located_and_write_nothing(capsys, tmp_path):
    bad = tmp_path / "bad.wkt"
    bad.write_text(
        "a = POLYGON ((0 0, 1 0, 1 1, 0 1, 0 0))\nb = POLYGON ((1 1, 2 1, 2 2, 1 2, 1 1))\n"
    )
    out = tmp_path / "out.vtu"
    code, _, stderr = run_cli(capsys, "mesh", str(bad), "--level", "1", "-o", str(out))
    assert code != 0 and "touch at the single point (1, 1)" in stderr and not out.exists()
