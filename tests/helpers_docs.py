"""The examples the README and the documentation pages show, run verbatim in a fresh folder.

Every ``$`` command of a console block, the ``blockmesh`` commands of a bash block (the
quickstart), every complete ``blockmesh ...`` command quoted in the text, every Python block, and
the OpenFOAM shell block of a page run in a new temporary folder, as a reader would type them:
``blockmesh ARGV`` is the command's ``main(ARGV)``, in this process (an interpreter's start-up per
command would take minutes), and a Python block runs as a script. The commands of one console
block share their folder, in order. A command must succeed (exit 0) unless the page shows it
failing: a shown ``error:`` line means exit 2, ``is not valid`` exit 1, and the message printed
must be the one shown. The first line of a shown output (unless elided) must be what the command
prints, and a Python line ``print(...)  # TEXT`` must print TEXT.

The pages are README.md and every Markdown page under ``docs/`` (the built site and generated
folders excepted). Files an example needs that a page has the reader make first (``Save the file
above as arch.toml``, the mesh a gmsh snippet opens) are made by ``SETUP``; the examples that need
what a test machine lacks are in ``SKIP``, with the reason; those that need an optional extra are
in ``NEEDS`` (skipped, with the reason, when it is absent); the long ones are in ``SLOW`` (marked
``slow``: left out of the default run, run by CI's slow step). Each table is keyed by a unique
piece of the example's text, and a test checks that every key still matches an example.
"""

from __future__ import annotations

import contextlib
import io
import re
import shlex
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest
from helpers import missing
from helpers_io import foam_tool

from blockmesh.cli import main

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
#: Folders of docs/ that hold no page written by hand (the build, generated pages).
NOT_PAGES = {"_build", "_templates", "generated", "auto_gallery"}
TIMEOUT = 600


def doc_pages() -> list[Path]:
    """Every Markdown page of the documentation site, in path order."""
    return sorted(
        path
        for path in DOCS.rglob("*.md")
        if not NOT_PAGES.intersection(path.relative_to(DOCS).parts)
    )


#: Examples (by a unique piece of their text) that cannot run here, and why. Kept small.
SKIP = {
    "--scheduler tcp://head:8786": "needs a Dask cluster at a remote scheduler (tcp://head:8786)",
    'bd.refine_to(domain, 7, "j8.xdmf", partitions=8)': (
        "meshes 2.2 M cells on a local Dask cluster and gathers them (minutes on a small "
        "machine); the same calls run at small levels in tests/distributed"
    ),
}

#: Examples (by a unique piece of their text) that need an optional module: the module, and the
#: extra that installs it.
NEEDS = {
    "--partitions 4 --workers 2": ("dask.distributed", "distributed"),
    "import gmsh": ("gmsh", "test"),
}

#: Examples (by a unique piece of their text) that take seconds each: marked ``slow``.
SLOW = {
    "bar = solve_elasticity(": "VEM solves on a level-4 mesh, AMG included",
    "--partitions 4 --workers 2": "starts a local Dask cluster",
    "blockmesh mesh star --level 3 --placement angles": "optimises 14,256 cells' nodes",
    "'mydomains/*.toml' sp ring --level 5": "three meshes at level 5, written as VTU",
    "square-cut l-shape ring --level 4 --plot": "three meshes drawn on two cores",
    "--adapt --max-unknowns 20000": "twelve adaptive solves, up to 13,000 unknowns",
    "--size 1e-5 --max-memory 1G": "the memory guard measures a field of 15 billion cells (~60 s)",
    "--diffusion fibre=20": "meshes the fibre cell and solves on 91,368 cells",
}

#: Inline code that starts with ``blockmesh`` but names an option, not a command to run.
NOT_COMMANDS = {"blockmesh mesh --placement optimized"}


@dataclass(frozen=True)
class Example:
    """One example: its page (relative to the repository), kind, line and text."""

    page: str
    kind: str  # "console", "command", "python" or "sh"
    line: int
    text: str

    @property
    def id(self) -> str:
        """A test id: the page, the kind and the line."""
        return f"{self.page.removesuffix('.md')}:{self.kind}-line{self.line}"


def page_name(path: Path) -> str:
    """A page's path relative to the repository (``README.md``, ``docs/domains.md``)."""
    return path.relative_to(ROOT).as_posix()


def examples(path: Path) -> list[Example]:
    """The examples of one page, in order: the blocks, then the commands quoted in the text."""
    text = path.read_text(encoding="utf-8")
    page = page_name(path)
    found = []
    for m in re.finditer(r"```(console|python|bash|sh)\n(.*?)```", text, re.S):
        kind, body = m.group(1), m.group(2)
        line = text.count("\n", 0, m.start()) + 1
        if kind == "bash":  # the quickstart: its blockmesh command (CI runs the install)
            for part in body.replace("\n", " && ").split("&&"):
                if part.strip().startswith("blockmesh "):
                    found.append(Example(page, "command", line, part.strip()))
        else:
            found.append(Example(page, kind, line, body))
    prose = re.sub(r"```.*?```", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    for m in re.finditer(r"`(blockmesh\s[^`]*)`", prose):
        command = " ".join(m.group(1).split())
        placeholder = re.search(r"\[|\.\.\.|\b[A-Z]{1,6}\b", command)
        words = command.split()
        bare = len(words) == 2 and command != "blockmesh catalogue"
        options_only = len(words) > 2 and all(w.startswith("--") for w in words[2:])  # names
        if not (placeholder or bare or options_only or command in NOT_COMMANDS):
            found.append(Example(page, "command", prose.count("\n", 0, m.start()) + 1, command))
    return found


def params(paths: list[Path]) -> list:
    """``pytest.param`` of every example of these pages, the slow ones marked, with ids."""
    out = []
    for path in paths:
        for example in examples(path):
            slow = [pytest.mark.slow] if any(key in example.text for key in SLOW) else []
            out.append(pytest.param(example, marks=slow, id=example.id))
    return out


def _toml_block(first_line: str) -> str:
    """The TOML block of the README or a docs page that starts with ``first_line``."""
    for path in [README, *doc_pages()]:
        for body in re.findall(r"```toml\n(.*?)```", path.read_text(encoding="utf-8"), re.S):
            if body.startswith(first_line):
                return body
    raise AssertionError(f"no TOML block starting with {first_line!r} in the pages")


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
        {"docs/examples/channel.geo": (DOCS / "examples/channel.geo").read_text()},
        [],
    ),
    "cat > 0/T": ({}, ["blockmesh mesh l-shape --level 3 -o l-shape-case --format openfoam"]),
}


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
    """The ``$`` commands of a console block, each with the output lines the page shows."""
    out: list[tuple[str, list[str]]] = []
    for line in body.splitlines():
        if line.startswith("$ "):
            out.append((line[2:], []))
        elif out:
            out[-1][1].append(line)
    return out


def _expected_code(shown: list[str]) -> tuple[int, str | None]:
    """The exit code and the message the page shows for a command's output."""
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
            pytest.skip(f"{argv[0]} is not installed ({where} needs it)")
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


def run_example(
    example: Example,
    folder: Path,
    monkeypatch: pytest.MonkeyPatch,
    capfd: pytest.CaptureFixture[str],
) -> None:
    """Run one example in ``folder`` (made the current directory), as its page shows it."""
    monkeypatch.chdir(folder)
    where = f"{example.page} line {example.line}"
    for key, reason in SKIP.items():
        if key in example.text:
            pytest.skip(reason)
    for key, (module, extra) in NEEDS.items():
        if key in example.text and missing(module):
            pytest.skip(f"needs {module} (pip install -e '.[{extra}]'); {where}")
    _setup(example, folder)
    if example.kind == "console":
        for command, shown in _commands(example.text):
            _run_command(command, shown, folder, where)
    elif example.kind == "command":
        _run_command(example.text, [], folder, where)
    elif example.kind == "python":
        capfd.readouterr()
        exec(compile(example.text, where, "exec"), {"__name__": "__main__"})
        printed = capfd.readouterr().out
        for comment in re.findall(r"^print\(.*\)\s+# (.*)$", example.text, re.M):
            assert comment in printed, f"{where}: printed {printed!r}, the page says {comment}"
    else:  # the OpenFOAM shell block, run in the case folder
        tool = foam_tool("laplacianFoam")
        if tool is None:
            pytest.skip("OpenFOAM's laplacianFoam is not installed")
        _, env = tool
        run = subprocess.run(
            ["bash", "-e", "-c", example.text],
            cwd=folder / "l-shape-case",
            env=env,
            capture_output=True,
            text=True,
            timeout=TIMEOUT,
        )
        out = run.stdout + run.stderr
        assert run.returncode == 0 and re.search(r"^End\s*$", out, re.M), f"{where}:\n{out[-3000:]}"
