"""Running the command line as a separate process, as an attacker would: exit code, output, peak.

The reproducers of hostile inputs (``tests/hostile``) run ``python -m blockmesh ...`` in a child
process and collect what the issue asks of each: the exit code, the messages, the child's own
peak resident memory (``os.wait4`` gives the rusage of that one child) and whether it ended at all
(a child still running after ``timeout`` seconds is killed: a hang).
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time
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
    seconds: float = 0.0

    @property
    def error_lines(self) -> list[str]:
        return [line for line in self.err.splitlines() if line.strip()]

    def describe(self) -> str:
        return (
            f"blockmesh {' '.join(self.argv)!r}: exit {self.code}, peak "
            f"{self.peak_bytes / 2**20:.0f} MB{' (killed: it hung)' if self.killed else ''}\n"
            f"stdout: {self.out[-2000:]!r}\nstderr: {self.err[-3000:]!r}"
        )


#: The command line, run as ``python -m blockmesh`` runs it, reporting its peak memory at exit:
#: the process's own high-water mark after exec (/proc VmHWM: the rusage of a child forked
#: from a big test process counts that process's pages) and its waited-for children's (the
#: meshio child).
_LAUNCHER = """
import os, resource, sys
report = sys.argv.pop(1)
def peak():
    own = 0
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                own = int(line.split()[1]) * 1024
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
    with open(report, "w") as f:
        f.write(str(max(own, children)))
try:
    from blockmesh.cli import main
    code = main(sys.argv[1:])
except SystemExit as stop:
    code = stop.code if isinstance(stop.code, int) else 2
finally:
    peak()
sys.exit(code)
"""


def run_blockmesh(
    *argv: str,
    cwd: Path | str | None = None,
    timeout: float = TIME_LIMIT,
    env: dict[str, str] | None = None,
    signal_after: tuple[float, int] | None = None,
) -> Run:
    """Run the command line on ``ARGV`` in a child process: exit code, output, peak memory.

    ``signal_after = (seconds, signum)`` sends that signal once, after that many seconds. The
    peak is the child's own (and its children's), reported by the child as it exits; a child
    killed before it could report counts the rusage of the killed process.
    """
    environ = {**os.environ, **(env or {})}
    environ.pop("BLOCKMESH_DEBUG", None)
    report = Path(tempfile.mkstemp(prefix="blockmesh-peak-")[1])
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        child = subprocess.Popen(
            [sys.executable, "-c", _LAUNCHER, str(report), *argv],
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
        began = time.monotonic()
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
        told = report.read_text().strip()
        report.unlink()
        run = Run(
            argv=tuple(argv),
            code=child.returncode,
            out=out.read().decode(errors="replace"),
            err=err.read().decode(errors="replace"),
            peak_bytes=int(told) if told.isdigit() else usage.ru_maxrss * 1024,
            killed=killed.is_set(),
            seconds=time.monotonic() - began,
        )
    log = os.environ.get("BLOCKMESH_HOSTILE_LOG")  # the figures of docs/reliability.md
    if log:
        with open(log, "a", encoding="utf-8") as handle:
            test = os.environ.get("PYTEST_CURRENT_TEST", "").split(" ")[0]
            handle.write(
                json.dumps(
                    {"test": test, "argv": [a[:80] for a in argv], "code": run.code,
                     "seconds": round(run.seconds, 2), "peak_mb": run.peak_bytes // 2**20,
                     "killed": run.killed, "message": (run.error_lines or [""])[0][:400]}
                ) + "\n"
            )  # fmt: skip
    return run


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


# ------------------------------------------------------------------ decompression bombs
# Streams of gigabytes of zeros made in milliseconds: a compressed piece of zeros is repeated
# (each piece starts afresh: zlib after a full flush, LZMA2 with a dictionary reset), so no
# gigabytes are ever compressed (or held) to make them.


def deflate_zeros(n_bytes: int, piece: int = 1 << 20) -> bytes:
    """A raw deflate stream (no header) of ``n_bytes`` zeros (a multiple of ``piece``)."""
    import zlib

    compressor = zlib.compressobj(9, zlib.DEFLATED, -15)
    block = compressor.compress(bytes(piece)) + compressor.flush(zlib.Z_FULL_FLUSH)
    return block * (n_bytes // piece) + compressor.flush(zlib.Z_FINISH)


def zlib_zeros(n_bytes: int) -> bytes:
    """A zlib stream of ``n_bytes`` zeros, checksum included (Adler-32 of zeros: 1 and n)."""
    adler = ((n_bytes % 65521) << 16) | 1
    return b"\x78\xda" + deflate_zeros(n_bytes) + adler.to_bytes(4, "big")


def xz_zeros(n_bytes: int, piece: int = 16 << 20) -> bytes:
    """An .xz stream (one LZMA2 block, no check) of ``n_bytes`` zeros (a multiple of ``piece``)."""
    import lzma
    import struct
    import zlib

    def varint(n: int) -> bytes:
        out = bytearray()
        while n >= 0x80:
            out.append((n & 0x7F) | 0x80)
            n >>= 7
        out.append(n)
        return bytes(out)

    filters = [{"id": lzma.FILTER_LZMA2, "preset": 0}]
    raw = lzma.compress(bytes(piece), format=lzma.FORMAT_RAW, filters=filters)[:-1]
    data = raw * (n_bytes // piece) + b"\x00"  # each chunk run starts with a dictionary reset
    empty = lzma.compress(b"", format=lzma.FORMAT_XZ, check=lzma.CHECK_NONE, filters=filters)
    stream_header, flags = empty[:12], empty[6:8]
    properties = lzma._encode_filter_properties(filters[0])  # type: ignore[attr-defined]
    body = b"\x00" + varint(0x21) + varint(len(properties)) + properties
    padding = (-(len(body) + 5)) % 4
    header = bytes([(len(body) + 5 + padding) // 4 - 1]) + body + bytes(padding)
    header += struct.pack("<I", zlib.crc32(header))
    block = header + data + bytes((-len(data)) % 4)
    index = b"\x00" + varint(1) + varint(len(header) + len(data)) + varint(n_bytes)
    index += bytes((-len(index)) % 4)
    index += struct.pack("<I", zlib.crc32(index))
    backward = struct.pack("<I", len(index) // 4 - 1)
    footer = struct.pack("<I", zlib.crc32(backward + flags)) + backward + flags + b"YZ"
    return stream_header + block + index + footer
