"""NumPy ``.npz``: the format record, the writer and the reader."""

from __future__ import annotations

from blockmesh.io.npz.format import FORMAT, read_npz, write_npz

__all__ = ["FORMAT", "read_npz", "write_npz"]
