"""``blockmesh mesh --partitions`` and ``blockmesh integrate --partitions`` on local clusters."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import run_cli

import blockmesh

pytest.importorskip(
    "dask.distributed",
    reason="dask[distributed] is not installed (pip install 'blockmesh[distributed]')",
)
import blockmesh.distributed as bd


def test_mesh_partitions_writes_pieces_equal_to_the_serial_mesh(capsys, tmp_path):
    index = tmp_path / "{name}-{level}.xdmf"
    code, out, err = run_cli(
        capsys, "mesh", "l-shape", "--level", "3", "--partitions", "3", "--workers", "2",
        "-o", str(index), "--json",
    )  # fmt: skip
    assert code == 0, err
    report = json.loads(out)
    written = tmp_path / "l-shape-3.xdmf"
    assert report["output"] == str(written) and report["partitions"] == 3
    serial = blockmesh.load_domain("l-shape").mesh(3)
    assert (report["cells"], report["nodes"], report["edges"]) == (
        serial.n_cells, serial.n_points, serial.n_edges,
    )  # fmt: skip
    assert report["quality"] == serial.quality().as_dict()
    assert report["predicted_peak_bytes"] > 0 and report["worker_peak_bytes"] > 0
    gathered = bd.gather(written)
    assert np.array_equal(gathered.points, serial.points)
    assert np.array_equal(gathered.cells, serial.cells)


def test_integrate_partitions_sums_to_the_serial_value(capsys):
    argv = ["integrate", "square-cut", "--function", "exp(x)*y^2", "--level", "3", "--json"]
    _, serial, _ = run_cli(capsys, *argv)
    code, parts, err = run_cli(capsys, *argv, "--partitions", "4", "--workers", "2")
    assert code == 0, err
    assert json.loads(parts)["value"] == pytest.approx(json.loads(serial)["value"], rel=1e-14)


def test_an_oversize_partition_is_refused_and_leaves_nothing(capsys, tmp_path):
    code, out, err = run_cli(
        capsys, "mesh", "joined-8", "--level", "7", "--partitions", "1", "--workers", "1",
        "--max-memory", "300M", "-o", str(tmp_path / "big.pvtu"),
    )  # fmt: skip
    assert code == 2 and out == "" and "Traceback" not in err
    assert "partition 0 of 1 needs about" in err and "use at least" in err
    assert list(tmp_path.iterdir()) == []
