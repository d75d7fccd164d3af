"""MATLAB ``.mat`` v5: the format record, the writer, the reader and its structural check."""

from __future__ import annotations

from blockmesh.io.mat.format import FORMAT, matlab_name, read_mat, write_mat

__all__ = ["FORMAT", "matlab_name", "read_mat", "write_mat"]
