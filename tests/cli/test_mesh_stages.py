"""The mesh command's memory guard, stage progress and out-of-memory handling."""

from __future__ import annotations

import contextlib
import io
import json

import pytest
from helpers import run_cli

import blockmesh.commands._progress as progress_module
from blockmesh._system.memory import process_rss
from blockmesh.commands._progress import StageProgress


def test_json_reports_the_predicted_peak(capsys, tmp_path):
    code, out, _ = run_cli(capsys, "mesh", "joined-8", "--level", "4", "--json")
    plain = json.loads(out)["predicted_peak_bytes"]
    code, out, _ = run_cli(
        capsys, "mesh", "joined-8", "--level", "4", "--json", "-o", str(tmp_path / "m.msh"),
        "--split", "quad5",
    )  # fmt: skip
    report = json.loads(out)
    assert code == 0 and report["predicted_peak_bytes"] > plain > 10**6


def _limit(extra: int) -> str:
    """A memory limit ``extra`` bytes above what this (test) process holds already."""
    return str(process_rss() + extra)


def test_an_oversize_request_is_refused_before_any_work(capsys, tmp_path):
    code, out, err = run_cli(
        capsys, "mesh", "sp", "--level", "9", "--max-memory", _limit(300_000_000),
        "-o", str(tmp_path / "m.vtu"), "--plot", str(tmp_path / "m.png"),
    )  # fmt: skip
    assert code == 2 and out == ""
    line = err.strip()
    assert "\n" not in line and "Traceback" not in err
    assert "sp at level 9 needs about" in line and "at its peak (" in line
    assert "more than --max-memory (" in line and "the largest level that fits is" in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_the_largest_level_offered_does_fit(capsys):
    limit = _limit(400_000_000)
    code, _, err = run_cli(capsys, "mesh", "joined-8", "--level", "8", "--max-memory", limit)
    fits = int(err.rsplit("fits is", 1)[1].strip().rstrip("."))
    code, out, _ = run_cli(
        capsys, "mesh", "joined-8", "--level", str(fits), "--max-memory", limit, "--json"
    )
    assert code == 0 and json.loads(out)["predicted_peak_bytes"] <= int(limit)


def test_running_out_of_memory_while_writing_is_a_located_error(capsys, tmp_path, monkeypatch):
    import blockmesh.commands.mesh.single

    def exhausted(*args, **kwargs):
        raise MemoryError

    monkeypatch.setattr(blockmesh.commands.mesh.single, "write", exhausted)
    target = tmp_path / "m.vtu"
    code, out, err = run_cli(capsys, "mesh", "sp", "--level", "3", "-o", str(target))
    assert code == 2 and out == "" and "Traceback" not in err
    assert f"ran out of memory while writing {target}" in err and "predicted to need" in err
    assert not target.exists()


def test_stage_lines_appear_for_slow_stages_only(monkeypatch):
    monkeypatch.setattr(progress_module, "SHOW_AFTER", 0.0)
    monkeypatch.setattr(progress_module, "_TICK", 0.01)
    stream = io.StringIO()
    progress = StageProgress("sp", enabled=True, stream=stream)
    import time

    with progress.stage("refining") as tick:
        tick(1, 2)
        time.sleep(0.05)
        tick(2, 2)
    text = stream.getvalue()
    assert "sp: refining [" in text and "2/2" in text and "done in" in text
    counts = io.StringIO()
    with StageProgress("sp", enabled=True, stream=counts).stage("measuring the cells") as tick:
        tick(8_912_896, 13_436_928)
        time.sleep(0.05)
    assert "8,912,896/13,436,928" in counts.getvalue()  # big counts are readable
    monkeypatch.setattr(progress_module, "SHOW_AFTER", 10.0)
    quiet = io.StringIO()
    with StageProgress("sp", enabled=True, stream=quiet).stage("measuring"):
        pass
    assert quiet.getvalue() == ""


@pytest.mark.parametrize("fails", [False, True])
def test_a_stage_past_the_threshold_gets_its_line_even_if_the_watcher_never_ran(monkeypatch, fails):
    """A loaded machine can starve the drawing thread for a whole stage: the line still ends
    the stage (with "done in" when it finished), never silence."""
    monkeypatch.setattr(progress_module, "SHOW_AFTER", 0.0)
    monkeypatch.setattr(progress_module, "_TICK", 3600.0)  # the watcher never draws
    stream = io.StringIO()
    with (
        contextlib.suppress(RuntimeError),
        StageProgress("sp", enabled=True, stream=stream).stage("writing") as tick,
    ):
        tick(3, 4)
        if fails:
            raise RuntimeError
    text = stream.getvalue()
    assert text.startswith("\rsp: writing [") and "3/4" in text and text.endswith("\n")
    assert ("done in" in text) is not fails


def test_a_failing_stage_ends_its_line_without_done(monkeypatch):
    monkeypatch.setattr(progress_module, "SHOW_AFTER", 0.0)
    monkeypatch.setattr(progress_module, "_TICK", 0.01)
    stream = io.StringIO()
    import time

    with pytest.raises(RuntimeError), StageProgress("sp", enabled=True, stream=stream).stage("x"):
        time.sleep(0.05)
        raise RuntimeError
    assert stream.getvalue().endswith("\n") and "done in" not in stream.getvalue()


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--workers", "2"], "--workers and --scheduler go with --partitions P"),
        (["--partitions", "2", "-o", "m.vtu"], "give -o OUT.pvtu"),
        (["--partitions", "2", "-o", "m.pvtu", "--plot", "m.png"], "--plot is not available"),
        (["--partitions", "0", "-o", "m.pvtu"], "--partitions must be 1 or more"),
        (
            ["--partitions", "2", "-o", "m.pvtu", "--numbering", "rcm"],
            "nested numbering, no smoothing",
        ),
        (
            ["--partitions", "2", "-o", "m.pvtu", "--workers", "1", "--scheduler", "tcp://x:1"],
            "give --workers (a local cluster) or --scheduler",
        ),
    ],
)
def test_partition_options_are_checked_first(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, "mesh", "sp", "--level", "2", *argv)
    assert code == 2 and message in err and out == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "command", [["check"], ["mesh", "--level", "0"], ["integrate", "--function", "1"]]
)
def test_reading_a_mesh_file_shows_a_stage_line(capsys, tmp_path, monkeypatch, command):
    """A slow read gets its line like the other stages (on a terminal, without --json)."""
    import time

    import blockmesh.io

    path = tmp_path / "m.npz"
    blockmesh.write(blockmesh.load_domain("sp").mesh(1), path)
    real_read = blockmesh.io.read

    def slow_read(*args, **kwargs):
        time.sleep(0.1)
        return real_read(*args, **kwargs)

    monkeypatch.setattr(blockmesh.io, "read", slow_read)
    monkeypatch.setattr(progress_module, "SHOW_AFTER", 0.0)
    monkeypatch.setattr(progress_module, "_TICK", 0.01)
    monkeypatch.setattr(StageProgress, "wanted", staticmethod(lambda args: True))
    code, _, err = run_cli(capsys, command[0], str(path), *command[1:])
    assert code == 0
    assert "m.npz: reading ..." in err and "done in" in err
