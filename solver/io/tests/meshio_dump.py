#!/usr/bin/env python3
"""Reads a .vtu with meshio (Debian's python3-meshio, a reader written apart
from fdem) and prints its contents in vtk_check.py's line format, so a test can
compare them with the values it wrote:
  piece <file> points <N> cells <M>
  array <file> <PointData|CellData|Points|Cells|FieldData> <name> <components> <values...>
  celltype <file> <meshio cell type>   (per cell block: vertex, tetra)
Floats print as Python's shortest round-trip repr, so equal text means equal bits.
"""
import sys

import meshio


def line(*words):
    print(" ".join(str(w) for w in words))


def flat(array):
    return [repr(float(v)) if array.dtype.kind == "f" else str(int(v)) for v in array.reshape(-1)]


def components(array):
    return 1 if array.ndim == 1 else array.shape[1]


def dump(path):
    mesh = meshio.read(path)
    cells = sum(len(block.data) for block in mesh.cells)
    line("piece", path, "points", len(mesh.points), "cells", cells)
    for name, data in mesh.field_data.items():
        line("array", path, "FieldData", name, 1, *flat(data))
    for name, data in mesh.point_data.items():
        line("array", path, "PointData", name, components(data), *flat(data))
    for name, blocks in mesh.cell_data.items():
        for data in blocks:
            line("array", path, "CellData", name, components(data), *flat(data))
    line("array", path, "Points", "Points", 3, *flat(mesh.points))
    for block in mesh.cells:
        line("array", path, "Cells", "connectivity", 1, *flat(block.data))
        line("celltype", path, block.type)


if __name__ == "__main__":
    for p in sys.argv[1:]:
        dump(p)
