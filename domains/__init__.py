"""The catalogue of ready-made domain files, shipped inside the package as ``blockmesh.domains``."""
