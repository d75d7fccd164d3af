"""The command line under hostile or unlucky input: outputs go where sent, no tracebacks."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from helpers import run_cli

import blockmesh


def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def test_a_domain_name_cannot_choose_where_output_goes(tmp_path, capsys, monkeypatch):
    domain = _write(tmp_path / "d.toml", 'name = "../../ESCAPED"\npolygon = [[0,0],[1,0],[0,1]]\n')
    work = tmp_path / "a" / "b"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    code, out, err = run_cli(capsys, "mesh", str(domain), "--level", "1", "-o", "out/{name}.vtu")
    assert code == 0, err
    assert (work / "out" / "ESCAPED.vtu").is_file()
    written = sorted(p.name for p in tmp_path.rglob("*.vtu"))
    assert written == ["ESCAPED.vtu"]


@pytest.mark.parametrize("name", ["ev\x1b[2Jil", "bell\x07", "two\nlines"])
def test_control_characters_in_names_are_refused(tmp_path, capsys, name):
    domain = _write(
        tmp_path / "d.toml", f"name = {json.dumps(name)}\npolygon = [[0,0],[1,0],[0,1]]\n"
    )
    code, out, err = run_cli(capsys, "check", str(domain))
    assert code == 1 and "control character" in err
    assert "\x1b" not in err and "\x07" not in err


def test_templated_outputs_get_their_folders_and_the_summary_lists_them(tmp_path, capsys):
    pattern = str(tmp_path / "out" / "{name}-{level}.png")
    code, out, err = run_cli(capsys, "mesh", "sp", "usp", "--level", "1", "--plot", pattern)
    assert code == 0, err
    for name in ("sp", "usp"):
        picture = tmp_path / "out" / f"{name}-1.png"
        assert picture.read_bytes()[:4] == b"\x89PNG"
        assert str(picture) in out


def test_a_missing_folder_without_template_fails_before_the_work(tmp_path, capsys):
    code, out, err = run_cli(capsys, "mesh", "sp", "-o", str(tmp_path / "nope" / "m.vtu"))
    assert code == 2 and "does not exist" in err and "mkdir -p" in err


@pytest.mark.parametrize("level", ["300", "400", "1000"])
def test_absurd_levels_are_refused_readably(capsys, level):
    code, out, err = run_cli(capsys, "mesh", "sp", "--level", level)
    assert code == 2 and out == ""
    assert "needs about 10^" in err and "largest level that fits" in err
    assert len(err) < 400 and "Traceback" not in err


@pytest.mark.parametrize("size", ["inf", "nan", "-1G", "1e400", "lots"])
def test_bad_memory_limits_are_refused(capsys, size):
    with pytest.raises(SystemExit) as stop:
        run_cli(capsys, "mesh", "sp", f"--max-memory={size}")
    assert stop.value.code == 2
    assert "is not a size" in capsys.readouterr().err


def test_a_square_far_from_the_origin_is_refused_not_broken(tmp_path, capsys):
    polygon = "1e15,0 1000000000000001,0 1000000000000001,1 1e15,1"
    target = tmp_path / "far.vtu"
    code, out, err = run_cli(
        capsys, "mesh", "--polygon", polygon, "--level", "2", "-o", str(target)
    )
    assert code == 2 and "double precision" in err and "near the origin" in err
    assert not target.exists() and list(tmp_path.iterdir()) == []


def test_a_square_at_1e9_meshes_with_valid_cells(capsys):
    polygon = "1e9,0 1000000001,0 1000000001,1 1e9,1"
    code, out, err = run_cli(capsys, "mesh", "--polygon", polygon, "--level", "3", "--json")
    report = json.loads(out)
    assert code == 0, err
    assert report["quality"]["not_strictly_convex"] == 0
    assert report["area"] == pytest.approx(1.0, rel=1e-6)


def test_mesh_defaults_to_level_2_and_json_keys_are_always_there(capsys):
    code, out, _ = run_cli(capsys, "mesh", "sp", "--json")
    report = json.loads(out)
    assert code == 0 and report["level"] == 2 and report["cells"] == 36
    assert report["plot"] is None and report["output"] is None and report["quality_plot"] is None
    assert report["bandwidth"]["rcm"] is None


@pytest.mark.parametrize("suffix", [".npz", ".vtu"])
def test_mesh_files_are_targets_for_check_mesh_and_show(tmp_path, capsys, monkeypatch, suffix):
    path = tmp_path / f"l{suffix}"
    blockmesh.write(blockmesh.load_domain("l-shape").mesh(1), path)
    code, out, err = run_cli(capsys, "check", str(path), "--json")
    report = json.loads(out)
    assert code == 0, err
    assert report["valid"] and report["blocks"] == 24 * 6 and report["patches"]["inlet"] == 4
    code, out, err = run_cli(capsys, "mesh", str(path), "--level", "1", "--json")
    assert code == 0 and json.loads(out)["level"] == 2 and json.loads(out)["cells"] == 24 * 36
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, "show", str(path))
    assert code == 0 and (tmp_path / "l-shape.png").is_file()


def test_a_file_that_is_not_a_blockmesh_mesh_says_so(tmp_path, capsys):
    path = tmp_path / "junk.npz"
    np.savez(path, a=np.arange(3))
    code, out, err = run_cli(capsys, "check", str(path))
    assert code == 1 and "blockmesh convert" in err and "Traceback" not in err


def test_show_writes_name_png_by_default(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, _ = run_cli(capsys, "show", "sp")
    assert code == 0 and "(sp: 1 block)" in out and (tmp_path / "sp.png").is_file()


def test_sigterm_during_a_write_unwinds_like_ctrl_c(tmp_path, capsys, monkeypatch):
    target = tmp_path / "m.vtu"
    target.write_bytes(b"old")

    def die_instead_of_renaming(*_args):
        os.kill(os.getpid(), signal.SIGTERM)  # the new file is complete, not yet in place

    monkeypatch.setattr(os, "replace", die_instead_of_renaming)
    code, out, err = run_cli(capsys, "mesh", "sp", "--level", "1", "-o", str(target))
    assert code == 128 + signal.SIGTERM and "terminated by signal" in err
    assert target.read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.vtu"]
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_signal_just_after_a_temporary_is_made_leaves_nothing(
    tmp_path, capsys, monkeypatch, signum
):
    """The window between creating a temporary and the writer's ``try`` (a real SIGTERM at the
    start of a VTU write left ``.m.vtu.HOST-PID-RANDOM.tmp`` behind in 2 of 3 runs)."""
    target = tmp_path / "m.vtu"
    target.write_bytes(b"old")
    real_open = os.open

    def open_then_signal(path, *args, **kwargs):
        fd = real_open(path, *args, **kwargs)
        if Path(path).name.startswith(".m.vtu."):  # a temporary was just made
            if signum == signal.SIGINT:  # what Python's own handler does, without the signal
                raise KeyboardInterrupt  # (a real SIGINT could reach pytest in a long session)
            os.kill(os.getpid(), signum)  # handled before the writer reaches its try
        return fd

    monkeypatch.setattr(os, "open", open_then_signal)
    code, _, err = run_cli(capsys, "mesh", "sp", "--level", "1", "-o", str(target))
    assert code == 128 + signum, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.vtu"]
    assert target.read_bytes() == b"old"


@pytest.mark.parametrize(
    ("signame", "fmt"), [("SIGINT", "xdmf"), ("SIGTERM", "vtu"), ("SIGHUP", "openfoam")]
)
def test_a_real_signal_at_the_start_of_a_write(tmp_path, signame, fmt):
    """A real process, signalled the moment its first temporary appears: never exit 0, never
    "Exception ignored" (Ctrl-C swallowed in an XDMF write, issue 14), no temporary left, and
    the old output whole (or, if the signal came after the commit, the new one whole)."""
    signum = getattr(signal, signame)
    folder = tmp_path / "out"
    folder.mkdir()
    target = folder / ("case" if fmt == "openfoam" else f"m.{fmt}")
    blockmesh.write(blockmesh.load_domain("sp").mesh(1), target, format=fmt)
    before = {p.relative_to(folder): p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2]))
    argv = ["mesh", "l-shape", "--level", "5", "-o", str(target), "--format", fmt]
    run = subprocess.Popen(
        [sys.executable, "-m", "blockmesh", *argv],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    while run.poll() is None and not any(p.name.startswith(".") for p in folder.rglob("*")):
        pass  # poll as fast as possible: the signal lands as the write begins
    if run.poll() is not None:  # a starved poller never saw the write: nothing was tested
        _, err = run.communicate()
        assert run.returncode == 0, err
        pytest.skip("the command finished before a temporary was seen (machine too loaded)")
    run.send_signal(signum)
    _, err = run.communicate(timeout=300)
    assert run.returncode == 128 + signum, err
    assert "Exception ignored" not in err and "Traceback" not in err
    assert not [p for p in folder.rglob(".*")], err
    after = {p.relative_to(folder): p.read_bytes() for p in folder.rglob("*") if p.is_file()}
    if after != before:  # the signal landed after the commit (a loaded machine): new, whole
        assert blockmesh.read(target, format=fmt).n_cells == 24 * 6**5, sorted(after)


def test_python_dash_m_blockmesh_runs_the_command_line():
    done = subprocess.run(
        [sys.executable, "-m", "blockmesh", "--version"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0 and done.stdout.startswith("blockmesh ")


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_an_error_raised_while_a_signal_unwinds_reports_the_signal(
    tmp_path, capsys, monkeypatch, signum
):
    """A library turning the signal's exception into its own (h5py raised a TypeError when
    Ctrl-C landed inside it) is still the signal: its exit code, not "internal error"."""

    def library_that_converts(*_args, **_kwargs):
        try:
            os.kill(os.getpid(), signum)
        except KeyboardInterrupt:  # Terminated is one too
            raise TypeError("the library's state after the interrupt") from None

    monkeypatch.setattr("blockmesh.commands.mesh.single.write", library_that_converts)
    monkeypatch.delenv("BLOCKMESH_DEBUG", raising=False)
    code, _, err = run_cli(capsys, "mesh", "sp", "--level", "1", "-o", str(tmp_path / "m.vtu"))
    assert code == 128 + signum, err
    assert "internal error" not in err and ("interrupted" in err or "terminated" in err)
    monkeypatch.setattr("blockmesh.commands.mesh.single.write", blockmesh.write)
    code, _, err = run_cli(capsys, "mesh", "sp", "--level", "1", "-o", str(tmp_path / "m.vtu"))
    assert code == 0, err  # the record does not outlive the command


def test_unexpected_errors_are_one_line_not_a_traceback(capsys, monkeypatch):
    def broken(*_args, **_kwargs):
        raise ZeroDivisionError("boom")

    monkeypatch.setattr("blockmesh.commands.mesh.single.refine", broken)
    monkeypatch.delenv("BLOCKMESH_DEBUG", raising=False)
    code, out, err = run_cli(capsys, "mesh", "sp")
    assert code == 3 and "internal error (ZeroDivisionError: boom)" in err
    assert "Traceback" not in err


def test_first_hour_small_things(capsys):
    """Issue 11, item 9: a LICENSE as pyproject says, a --level help that says what a level is,
    a one-line repr of a mesh (it printed every boundary edge), "1 block" not "1 blocks"."""
    root = Path(__file__).resolve().parents[2]
    assert (root / "LICENSE").read_text().startswith("MIT License")
    assert 'license = "MIT"' in (root / "pyproject.toml").read_text()
    with pytest.raises(SystemExit):
        run_cli(capsys, "mesh", "--help")
    help_text = " ".join(capsys.readouterr().out.split())
    assert "--level L, -l L refinement level: every block becomes 6**L pentagons (default 2;" in (
        help_text
    )
    mesh = blockmesh.load_domain("l-shape").mesh(3)
    for text in (str(mesh), repr(mesh)):
        assert "\n" not in text and len(text) < 200, text
        assert "5,184 cells" in text or "5184 cells" in text


def test_check_prints_several_problems_one_per_line(capsys):
    """Coordinates of +-1e308: three located problems, each on its own line (they were joined
    by a literal backslash-n, the newlines escaped like control characters in a name)."""
    code, out, err = run_cli(capsys, "check", "--polygon", "1e308,0 -1e308,0 0,1e308")
    lines = err.splitlines()
    assert code == 1 and out == "" and "\\n" not in err and "Traceback" not in err
    assert lines[0] == "blockmesh check: polygon is not valid: 3 problems:"
    assert all("is too far out" in line for line in lines[1:]) and len(lines) == 4
