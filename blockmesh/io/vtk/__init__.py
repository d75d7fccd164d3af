"""Legacy VTK ``.vtk``: the format record, the writer and the direct reader."""

from __future__ import annotations

from blockmesh.io.vtk.format import FORMAT, decode_name, encode_name, read_vtk, write_vtk

__all__ = ["FORMAT", "decode_name", "encode_name", "read_vtk", "write_vtk"]
