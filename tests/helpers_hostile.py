"""Running the command line as a separate process, as an attacker would: exit code, output, peak.

The reproducers of hostile inputs (``tests/hostile``) run ``python -m blockmesh ...`` in a child
process and collect what the issue asks of each: the exit code, the messages, the child's own
peak resident memory (``os.wait4`` gives the rusage of that one child) and whether it ended at all
(a child still running after ``timeout`` seconds is killed: a hang).
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

#: What a reproducer may use at most (the issue: under 500 MB, bombs included).
PEAK_LIMIT = 500 * 2**20
#: Seconds after which a reproducer counts as hung (the issue: each ends in under 10 s).
TIME_LIMIT = 10.0


@dataclass(frozen=True)
class Run:
    """What one run of the command line did."""

    argv: tuple[str, ...]
    code: int
    out: str
    err: str
    peak_bytes: int
    killed: bool

    @property
    def error_lines(self) -> list[str]:
        return [line for line in self.err.splitlines() if line.strip()]

    def describe(self) -> str:
        return (
            f"blockmesh {' '.join(self.argv)!r}: exit {self.code}, peak "
            f"{self.peak_bytes / 2**20:.0f} MB{' (killed: it hung)' if self.killed else ''}\n"
            f"stdout: {self.out[-2000:]!r}\nstderr: {self.err[-3000:]!r}"
        )


def run_blockmesh(
    *argv: str,
    cwd: Path | str | None = None,
    timeout: float = TIME_LIMIT,
    env: dict[str, str] | None = None,
    signal_after: tuple[float, int] | None = None,
) -> Run:
    """Run ``python -m blockmesh ARGV`` in a child process; its exit code, output and peak memory.

    ``signal_after = (seconds, signum)`` sends that signal once, after that many seconds.
    """
    environ = {**os.environ, **(env or {})}
    environ.pop("BLOCKMESH_DEBUG", None)
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        child = subprocess.Popen(
            [sys.executable, "-m", "blockmesh", *argv],
            stdin=subprocess.DEVNULL,
            stdout=out,
            stderr=err,
            cwd=cwd,
            env=environ,
            start_new_session=True,
        )
        killed = threading.Event()

        def kill() -> None:
            killed.set()
            os.killpg(child.pid, signal.SIGKILL)

        timer = threading.Timer(timeout, kill)
        timer.start()
        sender = None
        if signal_after is not None:
            sender = threading.Timer(signal_after[0], os.kill, (child.pid, signal_after[1]))
            sender.start()
        try:
            _, status, usage = os.wait4(child.pid, 0)
        finally:
            timer.cancel()
            if sender is not None:
                sender.cancel()
        child.returncode = os.waitstatus_to_exitcode(status)
        with contextlib.suppress(OSError):
            os.killpg(child.pid, signal.SIGKILL)  # workers it may have left
        out.seek(0)
        err.seek(0)
        return Run(
            argv=tuple(argv),
            code=child.returncode,
            out=out.read().decode(errors="replace"),
            err=err.read().decode(errors="replace"),
            peak_bytes=usage.ru_maxrss * 1024,
            killed=killed.is_set(),
        )


def listing(folder: Path) -> dict[str, tuple[int, int]]:
    """Every path under ``folder`` (links not followed) with its mode and size."""
    out = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = Path(root) / name
            info = path.lstat()
            out[str(path.relative_to(folder))] = (info.st_mode, info.st_size)
    return out


def assert_refused(
    run: Run, *, names: tuple[str, ...] = (), codes: tuple[int, ...] = (1, 2)
) -> None:
    """One located message (naming each of ``names``), exit code 1 or 2, in time and memory."""
    assert not run.killed, run.describe()
    assert run.code in codes, run.describe()
    lines = run.error_lines
    assert len(lines) == 1, run.describe()
    assert lines[0].startswith("blockmesh "), run.describe()
    assert "internal error" not in lines[0] and "Traceback" not in run.err, run.describe()
    for name in names:
        assert name in lines[0], f"{name!r} not in the message\n{run.describe()}"
    assert run.peak_bytes < PEAK_LIMIT, run.describe()
