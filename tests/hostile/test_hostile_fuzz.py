"""A bounded fuzz of every reader (slow): damaged valid files, only the library's errors escape.

Each target runs in its own process (``fuzz_readers.py``) for a few seconds, with its address
space limited (a case needing 2 GB fails with MemoryError) and each case limited to 10 s of
CPU time (30 s of real time). Long runs of ten minutes a reader are made by hand; their counts
are in ``docs/reliability.md``.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from fuzz_readers import TARGETS

#: Seconds of fuzzing per target in this test (the counts vary with the machine's speed).
SECONDS = 6


@pytest.mark.slow
@pytest.mark.parametrize("target", TARGETS)
def test_a_bounded_fuzz_finds_only_library_errors(tmp_path, target):
    script = Path(__file__).with_name("fuzz_readers.py")
    out = tmp_path / "report.json"
    run = subprocess.run(
        [sys.executable, str(script), "--target", target, "--seconds", str(SECONDS),
         "--seed", "26", "--keep", str(tmp_path / "failures"), "--out", str(out)],
        capture_output=True, text=True, timeout=SECONDS + 300, check=False,
    )  # fmt: skip
    assert out.exists(), run.stderr[-3000:]
    report = json.loads(out.read_text())
    assert report["cases"] > 0
    assert report["failures"] == 0, json.dumps(report["failure_list"], indent=1)
    assert report["read"] + report["refused"] == report["cases"]
    assert report["peak_rss_bytes"] < 2 * 10**9
