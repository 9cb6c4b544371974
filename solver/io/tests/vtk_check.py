#!/usr/bin/env python3
"""Reads .pvd / .vtu files written by fdem back with xml.etree (an independent
parser), checks their structure and prints their contents for the tests.

Checks: well-formed XML; a .pvd's DataSets exist and parse; each .vtu Piece's
arrays hold NumberOfPoints (NumberOfCells) x NumberOfComponents finite values;
connectivity indices are in range, offsets increase by the cell type's vertex
count (1 for VTK_VERTEX, 4 for VTK_TETRA).

Prints, one per line:
  dataset <time> <file>                       (for a .pvd)
  piece <file> points <N> cells <M>
  array <file> <PointData|CellData|Points|Cells|FieldData> <name> <components> <values...>
Exit status 1 with a message on the first violation.
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

VERTS = {1: 1, 10: 4}


def fail(msg):
    print("vtk_check: " + msg, file=sys.stderr)
    sys.exit(1)


def values(arr):
    text = (arr.text or "").split()
    kind = arr.get("type")
    out = []
    for t in text:
        v = float(t) if kind.startswith("Float") else int(t)
        if kind.startswith("Float") and not math.isfinite(v):
            fail(f"array {arr.get('Name')}: non-finite value {t}")
        out.append(v)
    return out


def check_vtu(path):
    root = ET.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "UnstructuredGrid":
        fail(f"{path}: not a VTKFile UnstructuredGrid")
    grid = root.find("UnstructuredGrid")
    for fd in grid.findall("FieldData/DataArray"):
        print("array", path, "FieldData", fd.get("Name"), 1, *values(fd))
    pieces = grid.findall("Piece")
    if len(pieces) != 1:
        fail(f"{path}: expected one Piece, found {len(pieces)}")
    piece = pieces[0]
    npts, ncells = int(piece.get("NumberOfPoints")), int(piece.get("NumberOfCells"))
    print("piece", path, "points", npts, "cells", ncells)
    data = {}
    for section, count in (("PointData", npts), ("CellData", ncells), ("Points", npts)):
        for arr in piece.findall(f"{section}/DataArray"):
            comps = int(arr.get("NumberOfComponents", "1"))
            v = values(arr)
            if len(v) != count * comps:
                fail(f"{path}: {section}/{arr.get('Name')} holds {len(v)} values, expected {count} x {comps}")
            data[(section, arr.get("Name"))] = v
            print("array", path, section, arr.get("Name"), comps, *v)
    cells = {a.get("Name"): values(a) for a in piece.findall("Cells/DataArray")}
    for name in ("connectivity", "offsets", "types"):
        if name not in cells:
            fail(f"{path}: Cells/{name} missing")
    types, offsets, conn = cells["types"], cells["offsets"], cells["connectivity"]
    if len(types) != ncells or len(offsets) != ncells:
        fail(f"{path}: {len(types)} types and {len(offsets)} offsets for {ncells} cells")
    previous = 0
    for t, o in zip(types, offsets):
        if t not in VERTS or o - previous != VERTS[t]:
            fail(f"{path}: cell type {t} with {o - previous} vertices")
        previous = o
    if previous != len(conn) or any(not (0 <= c < npts) for c in conn):
        fail(f"{path}: connectivity out of range or of wrong length")
    print("array", path, "Cells", "connectivity", 1, *conn)
    if ("Points", "Points") not in data:
        fail(f"{path}: Points missing")


def check_pvd(path):
    root = ET.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "Collection":
        fail(f"{path}: not a VTKFile Collection")
    base = os.path.dirname(path)
    sets = root.findall("Collection/DataSet")
    times = [float(d.get("timestep")) for d in sets]
    if times != sorted(times):
        fail(f"{path}: timesteps not increasing")
    for d in sets:
        print("dataset", d.get("timestep"), d.get("file"))
        target = os.path.join(base, d.get("file"))
        if not os.path.isfile(target):
            fail(f"{path}: dataset {target} missing")
        check_vtu(target)


if __name__ == "__main__":
    for p in sys.argv[1:]:
        try:
            (check_pvd if p.endswith(".pvd") else check_vtu)(p)
        except ET.ParseError as e:
            fail(f"{p}: not well-formed XML: {e}")
