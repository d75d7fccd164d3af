"""Domain inputs and absurd requests of issue 26: each refused up front with one located message.

As in ``test_hostile_readers``: every reproducer runs ``python -m blockmesh`` in a child process
and must end (within 10 s) with one located message, exit code 1 or 2, nothing written, and a
peak under 500 MB.
"""

from __future__ import annotations

import json
import math

import pytest
from helpers import slow_except
from helpers_hostile import PEAK_LIMIT, assert_refused, listing, run_blockmesh


def _refused(tmp_path, *argv, names=()):
    before = listing(tmp_path)
    run = run_blockmesh(*argv, cwd=tmp_path)
    assert_refused(run, names=names)
    assert listing(tmp_path) == before
    return run


def _ring(n: int) -> list[list[float]]:
    return [[math.cos(2 * math.pi * k / n), math.sin(2 * math.pi * k / n)] for k in range(n)]


# ------------------------------------------------------------------------- domain files
def test_a_geojson_coordinate_of_400_digits_is_located(tmp_path):
    big = "1" * 400
    (tmp_path / "d.geojson").write_text(
        '{"type": "Polygon", "coordinates": [[[0, 0], [' + big + ", 0], [1, 1], [0, 0]]]}"
    )
    _refused(tmp_path, "check", "d.geojson", names=("d.geojson", "400 digits"))


@pytest.mark.parametrize("constant", ["NaN", "Infinity", "-Infinity"])
def test_geojson_constants_that_are_no_numbers_are_located(tmp_path, constant):
    (tmp_path / "d.geojson").write_text(
        '{"type": "Polygon", "coordinates": [[[0, 0], [' + constant + ", 0], [1, 1], [0, 0]]]}"
    )
    _refused(tmp_path, "check", "d.geojson", names=("d.geojson", constant))


def test_a_toml_circle_of_radius_1e300_is_located(tmp_path):
    (tmp_path / "c.toml").write_text("circle = {center = [0, 0], radius = 1e300}\n")
    _refused(tmp_path, "check", "c.toml", names=("c.toml", "radius 1e+300"))


@pytest.mark.parametrize("form", ["blocks", "polygon", "inline"])
def test_a_domain_at_1e_300_scale_is_refused(tmp_path, form):
    s = 1e-300
    corners = [[0, 0], [2 * s, 0], [2 * s, s], [s, 2 * s], [0, s]]
    if form == "inline":
        argv: tuple[str, ...] = ("--polygon", " ".join(f"{x!r},{y!r}" for x, y in corners))
    else:
        text = (
            f"vertices = {corners}\nblocks = [[0, 1, 2, 3, 4]]\n"
            if form == "blocks"
            else f"polygon = {corners}\n"
        )
        (tmp_path / "tiny.toml").write_text(text)
        argv = ("tiny.toml",)
    run = _refused(tmp_path, "check", *argv)
    assert "span only" in run.err or "double precision" in run.err, run.describe()


@pytest.mark.parametrize("points", [250, 500])
def test_a_spline_of_hundreds_of_points_is_checked_in_bounded_memory(tmp_path, points):
    inner = [
        [2 * (k + 1) / (points + 1), -0.05 * math.sin(math.pi * (k + 1) / (points + 1))]
        for k in range(points)
    ]
    (tmp_path / "s.toml").write_text(
        "vertices = [[0, 0], [2, 0], [2, 1], [1, 2], [0, 1]]\nblocks = [[0, 1, 2, 3, 4]]\n"
        f"[[edges]]\nspline = [0, 1]\npoints = {inner}\n"
    )
    run = run_blockmesh("check", "s.toml", cwd=tmp_path)
    assert not run.killed and run.code == 0, run.describe()
    assert run.peak_bytes < PEAK_LIMIT, run.describe()


def test_a_looping_spline_of_thousands_of_points_is_located(tmp_path):
    n = 3000
    loop = [[1 + 0.5 * math.cos(6 * math.pi * k / n), -0.3 + 0.2 * math.sin(6 * math.pi * k / n)]
            for k in range(n)]  # fmt: skip
    (tmp_path / "s.toml").write_text(
        "vertices = [[0, 0], [2, 0], [2, 1], [1, 2], [0, 1]]\nblocks = [[0, 1, 2, 3, 4]]\n"
        f"[[edges]]\nspline = [0, 1]\npoints = {loop}\n"
    )
    _refused(tmp_path, "check", "s.toml", names=("s.toml", "crosses itself"))


@pytest.mark.parametrize("corners", slow_except([10_000, 100_000, 1_000_000], 10_000, 100_000))
def test_huge_toml_polygons_are_refused_while_counting(tmp_path, corners):
    (tmp_path / "p.toml").write_text(f"polygon = {_ring(corners)}\n")
    _refused(tmp_path, "check", "p.toml", names=("p.toml", "corners"))


@pytest.mark.slow
@pytest.mark.parametrize("suffix", [".wkt", ".geojson"])
def test_a_million_coordinates_of_an_outline_are_refused_before_parsing(tmp_path, suffix):
    ring = _ring(1_000_000)
    if suffix == ".wkt":
        text = "POLYGON ((" + ", ".join(f"{x} {y}" for x, y in ring) + ", 1 0))"
    else:
        text = json.dumps({"type": "Polygon", "coordinates": [[*ring, ring[0]]]})
    (tmp_path / f"p{suffix}").write_text(text)
    _refused(tmp_path, "check", f"p{suffix}", names=(f"p{suffix}", "corners"))


def test_an_inline_polygon_of_6000_corners_is_refused_before_parsing(tmp_path):
    text = " ".join(f"{x:.3f},{y:.3f}" for x, y in _ring(6_000))  # 84 KB: one argument
    _refused(tmp_path, "check", "--polygon", text, names=("corners",))


# ------------------------------------------------------------------------- requests
@pytest.mark.parametrize(
    "address",
    slow_except(
        ["bogus", "", "inproc", "tcp://" + "a" * 300 + ":8786", "tcp://host:99999", "ucx://h:1"],
        "bogus",
        "tcp://host:99999",
    ),
)
def test_scheduler_addresses_are_checked_before_dask_starts(tmp_path, address):
    _refused(
        tmp_path, "mesh", "sp", "--level", "2", "--partitions", "2", "--scheduler", address,
        "-o", "p.pvtu", names=("scheduler",),
    )  # fmt: skip


@pytest.mark.parametrize(
    "argv",
    [
        ("solve", "square", "--level", "1" + "0" * 30),
        ("mesh", "sp", "--level", "1" + "0" * 30),
        ("mesh", "sp", "--level", "100000"),
        ("mesh", "sp", "--smooth", "1000000000"),
        ("solve", "square", "--smooth", "1000000000"),
        ("mesh", "sp", "--level", "2", "--partitions", "2", "--workers", "100000", "-o", "p.pvtu"),
        ("mesh", "sp", "--level", "2", "--partitions", "2", "--max-memory", "1", "-o", "p.pvtu"),
        ("mesh", "sp", "--level", "2", "--partitions", "10000000", "-o", "p.pvtu"),
        ("integrate", "sp", "-f", "1", "--level", "1" + "0" * 30),
        ("convert", "in.msh", "-o", "out.toml", "--level", "1" + "0" * 30),
    ],
    ids=[
        "solve-level",
        "mesh-level",
        "level-100000",
        "mesh-smooth",
        "solve-smooth",
        "workers",
        "max-memory-1",
        "partitions",
        "integrate-level",
        "convert-level",
    ],
)
def test_absurd_requests_are_refused_up_front(tmp_path, argv):
    run = _refused(tmp_path, *argv)
    flags = [a for a in argv if a.startswith("--") and a not in ("--level",)] or ["--level"]
    assert flags[-1] in run.err, run.describe()
