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


# ------------------------------------------------------------- options (issue 22, item 4)
def test_integrate_takes_the_short_level_option(capsys):
    code, out, err = run_cli(capsys, "integrate", "sp", "-f", "1", "-l", "1", "--json")
    assert code == 0, err
    assert json.loads(out)["level"] == 1 and json.loads(out)["cells"] == 6


SOURCE = "2*pi^2*sin(pi*x)*sin(pi*y)"


def _solve(capsys, *arguments: str) -> dict:
    code, out, err = run_cli(capsys, "solve", "square", "--level", "2", "--source", SOURCE,
                             *arguments, "--json")  # fmt: skip
    assert code == 0, err
    return json.loads(out)


def test_dirichlet_star_means_every_patch_not_otherwise_given(capsys):
    """A bracket needed six --dirichlet flags, one per patch."""
    walls = [a for side in ("left", "right", "top", "bottom") for a in ("--dirichlet", f"{side}=0")]
    one_by_one = _untimed(_solve(capsys, *walls))
    assert _untimed(_solve(capsys, "--dirichlet", "*=0")) == one_by_one
    listed = _solve(capsys, "--dirichlet", "left,right=0", "--dirichlet", "top, bottom=0")
    assert listed["u_max"] == one_by_one["u_max"] and listed["dof"] == one_by_one["dof"]
    mixed = _solve(capsys, "--neumann", "left=0", "--dirichlet", "*=0")
    assert mixed["dof"] > one_by_one["dof"]  # left is free: its nodes are unknowns


def _untimed(report: dict) -> dict:
    return {k: v for k, v in report.items() if "seconds" not in k and "bytes" not in k}


def test_star_takes_the_patches_left_over_by_both_flags(capsys):
    code, out, err = run_cli(capsys, "solve", "square", "--level", "1", "--source", "1",
                             "--dirichlet", "*=0", "--neumann", "*=1")  # fmt: skip
    assert code == 2 and "'*' is given twice" in err


@pytest.mark.parametrize(
    ("flag", "message"),
    [
        ("left,nowhere=0", "no patch 'nowhere'"),
        ("left,,right=0", "an empty patch name"),
        ("left,left=0", "patch 'left' is given twice"),
    ],
)
def test_patch_lists_are_checked(capsys, flag, message):
    code, out, err = run_cli(capsys, "solve", "square", "--level", "1", "--source", "1",
                             "--dirichlet", flag)  # fmt: skip
    assert code == 2 and message in err, err


# ------------------------------------------------------------ naming the edges of a polygon
L_BRACKET = "0,0 4,0 4,1 1,1 1,3 0,3"


def test_patch_names_the_edges_of_an_inline_polygon(capsys):
    """--polygon and WKT domains had one patch, `boundary` (issue 22)."""
    code, out, err = run_cli(capsys, "check", "--polygon", L_BRACKET, "--patch", "fixed=left",
                             "--patch", "load=1", "--patch", "inner=3-4", "--json")  # fmt: skip
    assert code == 0, err
    report = json.loads(out)
    assert list(report["patches"]) == ["fixed", "load", "inner", "boundary"]
    mesh = blockmesh.Domain.from_polygon(
        blockmesh.domain.loading.parse_polygon_string(L_BRACKET),
        patches={"fixed": ["left"], "load": [1], "inner": [3, 4]},
    ).mesh(1)
    fixed = mesh.points[np.unique(mesh.patch_edges("fixed"))]
    assert np.all(fixed[:, 0] == 0) and np.ptp(fixed[:, 1]) == 3


def test_direction_words_pick_the_edges_facing_that_way():
    domain = blockmesh.Domain.from_polygon(
        [(0, 0), (4, 0), (4, 1), (1, 1), (1, 3), (0, 3)],
        patches={"left": ["left"], "right": ["right"], "top": ["top"], "bottom": ["bottom"]},
    )
    mesh = domain.mesh(0)
    for name, (axis, sign) in {"left": (0, -1), "right": (0, 1), "top": (1, 1),
                               "bottom": (1, -1)}.items():  # fmt: skip
        a, b = mesh.points[mesh.patch_edges(name)].transpose(1, 0, 2)
        normal = np.column_stack([b[:, 1] - a[:, 1], a[:, 0] - b[:, 0]])  # outward (CCW ring)
        assert np.all(sign * normal[:, axis] > np.abs(normal[:, 1 - axis])), name
    assert "boundary" not in domain.patch_names  # every edge of this bracket faces one way


def test_patch_works_on_a_wkt_file_and_is_refused_where_patches_are_the_files(capsys, tmp_path):
    wkt = tmp_path / "bracket.wkt"
    wkt.write_text("POLYGON ((0 0, 4 0, 4 1, 1 1, 1 3, 0 3, 0 0))")
    code, out, err = run_cli(capsys, "check", str(wkt), "--patch", "fixed=left", "--json")
    assert code == 0, err
    assert "fixed" in json.loads(out)["patches"]
    code, out, err = run_cli(capsys, "check", "l-shape", "--patch", "fixed=left")
    assert code == 1 and "--patch" in err and "polygon" in err


@pytest.mark.parametrize(
    ("spec", "message"),
    [("fixed", "write NAME=EDGES"), ("fixed=up", "'up'"), ("fixed=3-1", "'3-1'")],
)
def test_bad_patch_options_say_what_to_write(capsys, spec, message):
    code, out, err = run_cli(capsys, "mesh", "--polygon", L_BRACKET, "--patch", spec)
    assert code == 2 and message in err, err


def test_help_documents_patch_and_the_patch_lists(capsys):
    with pytest.raises(SystemExit):
        run_cli(capsys, "solve", "--help")
    text = " ".join(capsys.readouterr().out.split())
    assert "--patch NAME=EDGES" in text and "left, right, top, bottom" in text
    assert "'*=EXPR'" in text and "'left,right=EXPR'" in text


# ----------------------------------------------------------- --json: one object, errors too
@pytest.mark.parametrize(
    ("argv", "code", "kind", "message"),
    [
        (["mesh", "no-such-domain"], 2, "DomainFormatError", "neither a catalogue domain"),
        (["mesh", "sp", "--level", "400"], 2, "ResourceError", "largest level that fits"),
        (["integrate", "sp", "-f", "x +"], 2, "ExpressionError", "x +"),
        (["solve", "square", "--dirichlet", "nowhere=0"], 2, "BlockMeshError", "no patch"),
        (["convert", "/no/such/mesh.msh", "-o", "/tmp/x.toml"], 2, "DomainFormatError", "no such"),
        (["check", "--polygon", "0,0 1,1 0,1 1,0"], 1, "DomainError", "cross"),
    ],
)
def test_every_json_error_is_one_json_object(capsys, argv, code, kind, message):
    """`mesh --json` printed nothing on error while `check --json` printed {"valid": false}."""
    got, out, err = run_cli(capsys, *argv, "--json")
    assert got == code, err
    report = json.loads(out)  # exactly one object: json.loads refuses trailing text
    assert isinstance(report, dict)
    assert report["error"]["type"] == kind and report["error"]["exit_code"] == code
    assert message in report["error"]["message"]


def test_json_usage_errors_are_json_too(capsys):
    with pytest.raises(SystemExit) as stop:
        run_cli(capsys, "mesh", "sp", "--level", "two", "--json")
    out = capsys.readouterr().out
    assert stop.value.code == 2
    report = json.loads(out)
    assert report["error"]["exit_code"] == 2 and "invalid int value" in report["error"]["message"]


def test_json_of_an_interrupted_or_broken_command(capsys, monkeypatch):
    def interrupted(*_args, **_kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr("blockmesh.commands.mesh.single.refine", interrupted)
    code, out, err = run_cli(capsys, "mesh", "sp", "--json")
    assert code == 130 and json.loads(out)["error"]["exit_code"] == 130

    def broken(*_args, **_kwargs):
        raise ZeroDivisionError("boom")

    monkeypatch.setattr("blockmesh.commands.mesh.single.refine", broken)
    monkeypatch.delenv("BLOCKMESH_DEBUG", raising=False)
    code, out, err = run_cli(capsys, "mesh", "sp", "--json")
    report = json.loads(out)
    assert code == 3 and report["error"]["exit_code"] == 3 and "boom" in report["error"]["message"]


def test_a_json_report_is_not_followed_by_a_second_object(capsys, monkeypatch):
    """A signal recorded after the report was printed: the exit code says so, stdout stays one
    object."""
    from blockmesh._system import interrupts

    real = interrupts.raise_pending
    calls = []

    def pending_after_the_report():
        calls.append(1)
        raise KeyboardInterrupt

    monkeypatch.setattr("blockmesh.cli.raise_pending", pending_after_the_report)
    code, out, err = run_cli(capsys, "mesh", "sp", "--json")
    assert code == 130 and calls
    assert "error" not in json.loads(out) and json.loads(out)["cells"] == 36
    assert real is interrupts.raise_pending


# ------------------------------------------------------------------- pictures and listings
@pytest.fixture(scope="module")
def many_blocks():
    """1,116 blocks: the lake-island's level-1 cells as the blocks of a domain."""
    from blockmesh.commands.check import domain_of_mesh

    return domain_of_mesh(blockmesh.load_domain("lake-island").mesh(1))


def _label_boxes(fig):
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    return [t.get_window_extent(renderer) for t in ax.texts]


def test_show_numbers_only_the_blocks_whose_number_fits(many_blocks):
    """`show` on 1,000+ blocks printed every block number, one over the other."""
    from blockmesh.plot import domain_figure, pyplot

    fig = domain_figure(many_blocks)
    try:
        boxes = _label_boxes(fig)
        assert 0 < len(boxes) < many_blocks.n_blocks
        for k, box in enumerate(boxes):
            assert not any(box.overlaps(other) for other in boxes[k + 1 :]), k
        assert "numbers where they fit" in fig.axes[0].get_title()
    finally:
        pyplot().close(fig)


@pytest.mark.parametrize(("labels", "count"), [("all", 1116), ("none", 0)])
def test_block_numbers_can_be_turned_on_and_off(many_blocks, labels, count):
    from blockmesh.plot import domain_figure, pyplot

    fig = domain_figure(many_blocks, labels=labels)
    try:
        assert len(fig.axes[0].texts) == count
    finally:
        pyplot().close(fig)


def test_show_takes_labels(capsys, tmp_path):
    path = tmp_path / "l.png"
    code, out, err = run_cli(capsys, "show", "l-shape", "-o", str(path), "--labels", "none")
    assert code == 0 and path.is_file(), err


def test_mesh_plot_colours_the_regions_with_a_legend():
    """`mesh --plot` never showed the regions."""
    from matplotlib.colors import to_hex

    from blockmesh.plot import mesh_figure, pyplot

    mesh = blockmesh.load_domain("l-shape").mesh(1)
    fig = mesh_figure(mesh)
    try:
        ax = fig.axes[0]
        faces = [to_hex(c) for c in ax.collections[0].get_facecolors()]
        by_region = {r: {faces[c] for c in np.flatnonzero(mesh.region == r)} for r in range(3)}
        assert all(len(colours) == 1 for colours in by_region.values())
        assert len(set().union(*by_region.values())) == 3
        titles = [legend.get_title().get_text() for legend in [*fig.legends, ax.get_legend()]]
        assert "regions" in titles
        texts = {t.get_text() for legend in fig.legends for t in legend.get_texts()}
        assert texts >= {"corner", "arm-right", "arm-up"}
    finally:
        pyplot().close(fig)


def test_the_catalogue_table_keeps_its_columns(capsys):
    """Long names (quarter-plate-hole) pushed the other columns right."""
    code, out, err = run_cli(capsys, "catalogue")
    lines = out.splitlines()
    header, rows = lines[0], lines[1:]
    assert code == 0 and len(rows) == len(blockmesh.domain.catalogue.catalogue_names())
    start = header.index("description")
    area_end = header.index("area") + len("area")
    for row in rows:
        assert row[start - 2 : start] == "  " and row[start] != " ", row
        assert row[area_end - 1] != " " and row[area_end] == " ", row


def test_a_file_of_unknown_kind_is_refused_not_read_as_toml(tmp_path, capsys):
    """A WKT file named .txt was parsed as TOML ('Expected '=' after a key ...')."""
    path = tmp_path / "bracket.txt"
    path.write_text("POLYGON ((0 0, 4 0, 4 1, 1 1, 1 3, 0 3, 0 0))")
    with pytest.raises(blockmesh.DomainFormatError) as caught:
        blockmesh.load_domain(path)
    message = str(caught.value)
    assert "'.txt'" in message and ".wkt" in message and ".toml" in message and ".msh" in message
    code, out, err = run_cli(capsys, "check", str(path))
    assert code == 1 and "'.txt'" in err


def test_dir_shows_the_public_names():
    names = set(dir(blockmesh))
    assert names >= set(blockmesh.__all__) | {"__version__"}
    assert not names & {"Any", "TYPE_CHECKING", "annotations", "importlib", "domain", "io"}
    assert all(n in blockmesh.__all__ or n.startswith("__") for n in names)
    assert not hasattr(blockmesh, "Any") and not hasattr(blockmesh, "importlib")
