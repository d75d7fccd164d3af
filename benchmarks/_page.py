"""The benchmark pages: each ``bench_*.py`` writes its tables to ``docs/benchmarks/<name>.md``.

A re-measurement is then a regenerated page, not a hand edit. A :class:`Page` collects tables
(:class:`Table`, printed on the terminal row by row as they are measured) and paragraphs, and
:meth:`Page.write` writes the page atomically (a temporary file beside it, then one rename) with
what produced it: the date, the machine and the command. Used as::

    page = Page("curved", "Curved domains", __doc__)
    table = page.table("Area error", ["domain", "level", "error"])
    table.row("disc", 0, "2.43e-1")
    page.write(args)  # after add_arguments(parser): --page-dir, --no-page

The scripts run as ``python benchmarks/bench_NAME.py``, which puts this folder on ``sys.path``.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import shlex
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGES = ROOT / "docs" / "benchmarks"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options every benchmark has: where its page goes, or none."""
    parser.add_argument(
        "--page-dir",
        type=Path,
        default=PAGES,
        help=f"write the page (NAME.md) in this folder (default {PAGES.relative_to(ROOT)})",
    )
    parser.add_argument("--no-page", action="store_true", help="print only; write no page")


def _cell(value: object) -> str:
    text = str(value)
    return text.replace("|", "\\|").replace("\n", " ")


class Table:
    """A table: a title, column names and rows of cells (any values, shown with ``str``)."""

    def __init__(self, title: str, columns: Sequence[str], *, echo: bool = True) -> None:
        if not columns:
            raise ValueError("a table needs at least one column")
        self.title = title
        self.columns = [str(c) for c in columns]
        self.rows: list[list[str]] = []
        self.notes: list[str] = []
        self.echo = echo

    def row(self, *cells: object) -> None:
        """Add a row (one cell per column), printing it at once on the terminal."""
        if len(cells) != len(self.columns):
            raise ValueError(
                f"table {self.title!r}: {len(cells)} cells for {len(self.columns)} columns"
            )
        texts = [str(c) for c in cells]
        if self.echo:
            if not self.rows:
                print(f"\n{self.title}")
                print("  " + "  ".join(self.columns), flush=True)
            print("  " + "  ".join(texts), flush=True)
        self.rows.append(texts)

    def note(self, text: str) -> None:
        """A paragraph shown under the table (what the columns mean, how it was measured)."""
        if self.echo:
            print(f"  ({text})", flush=True)
        self.notes.append(text)

    def markdown(self) -> str:
        """The table as a Markdown (pipe) table under a level-2 heading, with its notes."""
        lines = [f"## {self.title}", ""]
        lines.append("| " + " | ".join(_cell(c) for c in self.columns) + " |")
        lines.append("|" + " --- |" * len(self.columns))
        lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in self.rows]
        for text in self.notes:
            lines += ["", text]
        return "\n".join(lines)


def _run(*command: str) -> str:
    try:
        done = subprocess.run(command, capture_output=True, text=True, cwd=ROOT, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return ""
    return done.stdout.strip() if done.returncode == 0 else ""


def _cpu() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _memory() -> str:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                return f"{int(line.split()[1]) / 2**20:.0f} GiB"
    except (OSError, ValueError):
        pass
    return "unknown memory"


def load() -> float | None:
    """The system's load average over the last minute (None where unknown)."""
    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):
        return None


def machine() -> str:
    """One line: the processor, cores, memory, system, Python and NumPy."""
    import numpy

    return (
        f"{_cpu()}, {os.cpu_count()} cores, {_memory()}; {platform.system()} "
        f"{platform.machine()}; Python {platform.python_version()}, NumPy {numpy.__version__}"
    )


def revision() -> str:
    """The blockmesh version and the git commit measured (``+ changes`` when uncommitted)."""
    import blockmesh

    commit = _run("git", "rev-parse", "--short", "HEAD")
    if not commit:
        return f"blockmesh {blockmesh.__version__}"
    dirty = _run("git", "status", "--porcelain", "--untracked-files=no")
    return f"blockmesh {blockmesh.__version__}, commit {commit}{' + changes' if dirty else ''}"


def command() -> str:
    """The command that runs this script, as typed from the repository's root."""
    script = Path(sys.argv[0]).resolve()
    try:
        shown = str(script.relative_to(ROOT))
    except ValueError:
        shown = str(script)
    return shlex.join(["python", shown, *sys.argv[1:]])


class Page:
    """One benchmark's page: a title, what it measures, its tables and paragraphs."""

    def __init__(self, name: str, title: str, about: str | None = None) -> None:
        self.name = name
        self.title = title
        self.about = (about or "").strip()
        self.parts: list[Table | str] = []
        self.load = load()  # how busy the machine was when the measurement started

    def table(self, title: str, columns: Sequence[str]) -> Table:
        """A new table of the page (in the order made)."""
        table = Table(title, columns)
        self.parts.append(table)
        return table

    def text(self, paragraph: str) -> None:
        """A paragraph of the page (printed too)."""
        print(f"\n{paragraph}", flush=True)
        self.parts.append(paragraph.strip())

    def markdown(self, *, when: datetime.datetime | None = None) -> str:
        """The whole page: title, provenance, what is measured, then the tables in order."""
        when = when or datetime.datetime.now(datetime.UTC)
        busy = [f"{value:.1f}" for value in (self.load, load()) if value is not None]
        loads = f"; load average {' at the start, '.join(busy)} at the end" if busy else ""
        lines = [
            f"# {self.title}",
            "",
            f"*Written by `{command()}` on {when:%Y-%m-%d %H:%M} UTC; {revision()}.*",
            f"*Machine: {machine()}{loads}.*",
            "",
        ]
        if self.about:
            lines += [self.about, ""]
        for part in self.parts:
            lines += [part.markdown() if isinstance(part, Table) else part, ""]
        return "\n".join(lines).rstrip() + "\n"

    def write(self, args: argparse.Namespace | None = None) -> Path | None:
        """Write ``<page-dir>/<name>.md`` atomically (no page with ``--no-page``)."""
        if args is not None and getattr(args, "no_page", False):
            return None
        folder = Path(getattr(args, "page_dir", PAGES) if args is not None else PAGES)
        folder.mkdir(parents=True, exist_ok=True)
        target = folder / f"{self.name}.md"
        handle, temporary = tempfile.mkstemp(prefix=f".{self.name}.", suffix=".tmp", dir=folder)
        try:
            with os.fdopen(handle, "w", encoding="utf-8") as out:
                out.write(self.markdown())
                out.flush()
                os.fsync(out.fileno())
            os.replace(temporary, target)
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise
        print(f"\nwrote {target}", flush=True)
        return target
