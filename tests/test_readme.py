"""The README's examples, run verbatim in a fresh folder (issue 11).

Every ``$`` command of a console block, the quickstart's ``blockmesh`` command, every complete
``blockmesh ...`` command quoted in the text, every Python block, and the OpenFOAM shell block
run in a new temporary folder, as a reader would type them: ``blockmesh ARGV`` is the command's
``main(ARGV)``, in this process (an interpreter's start-up per command would take minutes), and
a Python block runs as a script. The commands of one console block share their folder, in
order. A command must succeed (exit 0) unless the README shows it failing: a shown ``error:``
line means exit 2, ``is not valid`` exit 1, and the message printed must be the one shown. The
first line of a shown output (unless elided) must be what the command prints.

Files an example needs that the README has the reader make first (``Save the file above as
arch.toml``, the mesh a gmsh snippet opens) are made by ``SETUP``; the examples that need what a
test machine lacks are in ``SKIP``, with the reason, and those that need an optional extra that
``pip install -e '.[test]'`` does not bring (Dask for ``--partitions``) skip by ``EXTRAS`` when it
is absent.
"""

from __future__ import annotations

import contextlib
import importlib.metadata
import io
import re
import shlex
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest
from helpers_io import foam_tool

from blockmesh.cli import main

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
TIMEOUT = 600

#: Examples (by a unique piece of their text) that cannot run here, and why. Kept small.
SKIP = {
    "--scheduler tcp://head:8786": "needs a Dask cluster at a remote scheduler (tcp://head:8786)",
    'bd.refine_to(domain, 7, "j8.xdmf", partitions=8)': (
        "meshes 2.2 M cells on a local Dask cluster and gathers them (minutes on a small "
        "machine); the same calls run at small levels in tests/distributed"
    ),
}

#: What an example needs beyond ``pip install -e '.[test]'``, by a piece of its text: the
#: distribution (as pip names it) and what brings it. Without it the example skips with that
#: reason (a fresh clone's test run passes); with it the example runs. A rule for every example
#: that uses the feature, so no README text needs to match it. (Asked of the installed
#: distributions, not of the import path: ``tests/distributed`` would pass for ``distributed``.)
EXTRAS = {
    "--partitions": ("distributed", "Dask: pip install -e '.[distributed]'"),
    "blockmesh.distributed": ("distributed", "Dask: pip install -e '.[distributed]'"),
    "import gmsh": ("gmsh", "the gmsh Python package: pip install gmsh"),
}

#: Inline code that starts with ``blockmesh`` but names an option, not a command to run.
NOT_COMMANDS = {"blockmesh mesh --quality-rule optimized"}


def _toml_block(first_line: str) -> str:
    """The README's TOML block that starts with ``first_line``."""
    for body in re.findall(r"```toml\n(.*?)```", README, re.S):
        if body.startswith(first_line):
            return body
    raise AssertionError(f"no TOML block starting with {first_line!r} in the README")


ARCH = _toml_block('name = "arch"')
PLATE = _toml_block('name = "plate"')

#: What a reader has made before an example (by a unique piece of its text): files to write and
#: ``blockmesh`` commands to run.
SETUP: dict[str, tuple[dict[str, str], list[str]]] = {
    "arch.toml      # with center = [0.8, 0.6]": (
        {"arch.toml": ARCH.replace("center = [0.9, 0.3]", "center = [0.8, 0.6]", 1)},
        [],
    ),
    "arch.toml": ({"arch.toml": ARCH}, []),
    "l-shape.npz": ({}, ["blockmesh mesh l-shape --level 2 -o l-shape.npz"]),
    "mydomains/*.toml": ({"mydomains/plate.toml": PLATE}, []),
    'gmsh.open("l-shape.msh")': (
        {},
        ["blockmesh mesh l-shape --level 3 -o l-shape.msh --split quad5"],
    ),
    "docs/examples/channel.geo": (
        {"docs/examples/channel.geo": (ROOT / "docs/examples/channel.geo").read_text()},
        [],
    ),
    "cat > 0/T": ({}, ["blockmesh mesh l-shape --level 3 -o l-shape-case --format openfoam"]),
}


@dataclass(frozen=True)
class Example:
    """One example: its kind, where it is in the README, and its text."""

    kind: str  # "console", "command", "python" or "sh"
    line: int
    text: str

    @property
    def id(self) -> str:
        """A test id: the kind and the README line."""
        return f"{self.kind}-line{self.line}"


def _installed(distribution: str) -> bool:
    """Whether the distribution ``distribution`` is installed."""
    try:
        importlib.metadata.distribution(distribution)
    except importlib.metadata.PackageNotFoundError:
        return False
    return True


def _line_of(offset: int) -> int:
    return README.count("\n", 0, offset) + 1


def _examples() -> list[Example]:
    found = []
    for m in re.finditer(r"```(console|python|bash|sh)\n(.*?)```", README, re.S):
        kind, body = m.group(1), m.group(2)
        line = _line_of(m.start())
        if kind == "bash":  # the quickstart: its blockmesh command (CI runs the install)
            for part in body.replace("\n", " && ").split("&&"):
                if part.strip().startswith("blockmesh "):
                    found.append(Example("command", line, part.strip()))
        else:
            found.append(Example(kind, line, body))
    prose = re.sub(r"```.*?```", lambda m: "\n" * m.group(0).count("\n"), README, flags=re.S)
    for m in re.finditer(r"`(blockmesh\s[^`]*)`", prose):
        text = " ".join(m.group(1).split())
        placeholder = re.search(r"\[|\.\.\.|\b[A-Z]{1,6}\b", text)
        words = text.split()
        bare = len(words) == 2 and text != "blockmesh catalogue"
        options_only = len(words) > 2 and all(w.startswith("--") for w in words[2:])  # names
        if not (placeholder or bare or options_only or text in NOT_COMMANDS):
            found.append(Example("command", prose.count("\n", 0, m.start()) + 1, text))
    return found


EXAMPLES = _examples()


def _blockmesh(argv: list[str]) -> tuple[int, str, str]:
    """``blockmesh ARGV`` in this process (the command's own entry point), in the current folder.

    In-process saves the interpreter's start-up (seconds on a loaded machine) per command; what
    runs is the same ``main`` that ``python -m blockmesh`` calls, with the same arguments.
    """
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exit_:  # argparse's own errors
            code = exit_.code if isinstance(exit_.code, int) else 1
    return code, out.getvalue(), err.getvalue()


def _setup(example: Example, folder: Path) -> None:
    for key, (files, commands) in SETUP.items():
        if key in example.text:
            for name, content in files.items():
                (folder / name).parent.mkdir(parents=True, exist_ok=True)
                (folder / name).write_text(content)
            for command in commands:
                code, _, err = _blockmesh(shlex.split(command)[1:])
                assert code == 0, f"setup {command!r} failed:\n{err}"
            return  # the first (most specific) key only


def _commands(body: str) -> list[tuple[str, list[str]]]:
    """The ``$`` commands of a console block, each with the output lines the README shows."""
    out: list[tuple[str, list[str]]] = []
    for line in body.splitlines():
        if line.startswith("$ "):
            out.append((line[2:], []))
        elif out:
            out[-1][1].append(line)
    return out


def _expected_code(shown: list[str]) -> tuple[int, str | None]:
    """The exit code and the message the README shows for a command's output."""
    for line in shown:
        if re.match(r"blockmesh \w+: error: ", line):
            return 2, line
        if re.match(r"blockmesh check: .* is not valid: ", line):
            return 1, line
    return 0, None


def _sizes_masked(text: str) -> str:
    """``text`` with every memory size (``8.2 GB``) replaced by ``SIZE``."""
    return re.sub(r"\b\d+(\.\d+)? ([kKMGT]i?)?B\b", "SIZE", text)


def _run_command(command: str, shown: list[str], folder: Path, where: str) -> None:
    argv = shlex.split(command, comments=True)
    if argv[0] != "blockmesh":
        if shutil.which(argv[0]) is None:
            pytest.skip(f"{argv[0]} is not installed (the README's {where} needs it)")
        run = subprocess.run(argv, cwd=folder, capture_output=True, text=True, timeout=TIMEOUT)
        assert run.returncode == 0, f"{where}: {command}\n{run.stdout}\n{run.stderr}"
        return
    got, out, err = _blockmesh(argv[1:])
    code, message = _expected_code(shown)
    report = f"{where}: {command}\nexit {got}\n{out}\n{err}"
    assert got == code, report
    assert "Traceback" not in err, report
    if message is not None:  # sizes depend on what the process holds (this one: pytest too)
        assert _sizes_masked(message) in _sizes_masked(err), report
    first = shown[0] if shown else ""
    if first and "..." not in first and not first.lstrip().startswith("{") and code == 0:
        assert first.strip() in out, report


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.id for e in EXAMPLES])
def test_readme_example_runs(
    example: Example,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capfd: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.chdir(tmp_path)
    for key, reason in SKIP.items():
        if key in example.text:
            pytest.skip(reason)
    for key, (distribution, source) in EXTRAS.items():
        if key in example.text and not _installed(distribution):
            pytest.skip(f"needs {distribution}, which is not installed ({source})")
    where = f"README line {example.line}"
    _setup(example, tmp_path)
    if example.kind == "console":
        for command, shown in _commands(example.text):
            _run_command(command, shown, tmp_path, where)
    elif example.kind == "command":
        _run_command(example.text, [], tmp_path, where)
    elif example.kind == "python":
        capfd.readouterr()
        exec(compile(example.text, where, "exec"), {"__name__": "__main__"})
        printed = capfd.readouterr().out
        for comment in re.findall(r"^print\(.*\)\s+# (.*)$", example.text, re.M):
            assert comment in printed, f"{where}: printed {printed!r}, the README says {comment}"
    else:  # the OpenFOAM shell block, run in the case folder
        tool = foam_tool("laplacianFoam")
        if tool is None:
            pytest.skip("OpenFOAM's laplacianFoam is not installed")
        _, env = tool
        run = subprocess.run(
            ["bash", "-e", "-c", example.text],
            cwd=tmp_path / "l-shape-case",
            env=env,
            capture_output=True,
            text=True,
            timeout=TIMEOUT,
        )
        out = run.stdout + run.stderr
        assert run.returncode == 0 and re.search(r"^End\s*$", out, re.M), f"{where}:\n{out[-3000:]}"


def test_every_kind_of_example_is_found() -> None:
    """The extraction itself: the README's examples are all collected (none silently lost)."""
    kinds = {e.kind for e in EXAMPLES}
    assert kinds == {"console", "command", "python", "sh"}
    assert sum(e.kind == "console" for e in EXAMPLES) == README.count("```console")
    assert sum(e.kind == "python" for e in EXAMPLES) == README.count("```python")
    texts = [e.text for e in EXAMPLES]
    assert "blockmesh mesh square-cut --level 3 -o square-cut.vtu --plot square-cut.png" in texts
    assert "blockmesh show l-shape" in texts
    for key in [*SKIP, *SETUP]:
        assert any(key in t for t in texts), f"{key!r} matches no README example any more"
