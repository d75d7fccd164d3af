"""XDMF 3 + HDF5: the format record, the writer and the reader."""

from __future__ import annotations

from blockmesh.io.xdmf.format import FORMAT, read_xdmf, write_xdmf

__all__ = ["FORMAT", "read_xdmf", "write_xdmf"]
