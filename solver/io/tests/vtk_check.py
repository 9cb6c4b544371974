#!/usr/bin/env python3
"""Reads .pvd / .vtu files written by fdem back with xml.etree (an independent
parser) and the standard library's zlib, checks their structure and prints
their contents for the tests. A .vtu may hold its arrays as ASCII or as VTK's
raw appended data (header_type UInt32/UInt64, uncompressed or
vtkZLibDataCompressor blocks), decoded here from VTK's file-format
description, not from fdem's writer.

Checks: well-formed XML; a .pvd's DataSets exist and parse; a .pvtu's
pieces (Piece Source) exist, parse, and hold exactly the point arrays its
PPointData and PPoints declare (name, type, components, in order); each .vtu Piece's
arrays hold NumberOfPoints (NumberOfCells) x NumberOfComponents finite values;
connectivity indices are in range, offsets increase by the cell type's vertex
count (1 for VTK_VERTEX, 4 for VTK_TETRA).

Prints, one per line:
  dataset <time> <file>                       (for a .pvd)
  source <pvtu file> <piece file>             (for a .pvtu, then the piece's lines)
  piece <file> points <N> cells <M>
  array <file> <PointData|CellData|Points|Cells|FieldData> <name> <components> <values...>
Exit status 1 with a message on the first violation.
"""
import math
import os
import struct
import sys
import xml.etree.ElementTree as ET
import zlib

VERTS = {1: 1, 10: 4}
# VTK type name -> struct code (little-endian, as byte_order="LittleEndian" says).
CODES = {"Float64": "d", "Float32": "f", "Int64": "q", "Int32": "i", "UInt64": "Q", "UInt32": "I", "UInt8": "B"}


def fail(msg):
    print("vtk_check: " + msg, file=sys.stderr)
    sys.exit(1)


class Appended:
    """The raw appended-data section of a .vtu and how to decode its arrays."""

    def __init__(self, root, data):
        self.data = data
        if root.get("byte_order", "LittleEndian") != "LittleEndian":
            fail("only little-endian files are read")
        self.header_code = CODES[root.get("header_type", "UInt32")]
        self.header_size = struct.calcsize(self.header_code)
        self.compressor = root.get("compressor")
        if self.compressor not in (None, "vtkZLibDataCompressor"):
            fail(f"unsupported compressor {self.compressor}")

    def words(self, at, count):
        end = at + count * self.header_size
        if end > len(self.data):
            fail("appended data ends inside an array header")
        return list(struct.unpack(f"<{count}{self.header_code}", self.data[at:end])), end

    def array_bytes(self, offset):
        if self.compressor is None:
            (size,), at = self.words(offset, 1)
            if at + size > len(self.data):
                fail("appended data ends inside an array")
            return self.data[at:at + size]
        (blocks, block_size, last_size), at = self.words(offset, 3)
        sizes, at = self.words(at, blocks)
        out = b""
        for b, size in enumerate(sizes):
            try:
                chunk = zlib.decompress(self.data[at:at + size])
            except zlib.error as e:
                fail(f"block {b} of the array at offset {offset} does not decompress: {e}")
            expected = last_size if (b == blocks - 1 and last_size) else block_size
            if len(chunk) != expected:
                fail(f"block {b} of the array at offset {offset} holds {len(chunk)} bytes, header says {expected}")
            out += chunk
            at += size
        return out


def split_appended(path):
    """The file's XML (with the raw appended bytes removed) and those bytes."""
    with open(path, "rb") as f:
        raw = f.read()
    start = raw.find(b"<AppendedData")
    if start < 0:
        return raw, None
    underscore = raw.find(b"_", raw.find(b">", start))
    stop = raw.rfind(b"</AppendedData>")
    if underscore < 0 or stop < underscore:
        fail(f"{path}: AppendedData section not closed")
    data = raw[underscore + 1:stop]
    if data.endswith(b"\n"):
        data = data[:-1]  # the writer's line break before the closing tag
    return raw[:underscore] + raw[stop:], data


def values(arr, appended=None):
    kind = arr.get("type")
    if arr.get("format", "ascii") == "appended":
        if appended is None:
            fail(f"array {arr.get('Name')}: appended format but no AppendedData")
        payload = appended.array_bytes(int(arr.get("offset")))
        code = CODES[kind]
        if len(payload) % struct.calcsize(code):
            fail(f"array {arr.get('Name')}: {len(payload)} bytes is not a whole number of {kind}")
        out = list(struct.unpack(f"<{len(payload) // struct.calcsize(code)}{code}", payload))
    elif arr.get("format", "ascii") == "ascii":
        text = (arr.text or "").split()
        out = [float(t) if kind.startswith("Float") else int(t) for t in text]
    else:
        fail(f"array {arr.get('Name')}: unsupported format {arr.get('format')}")
    if kind.startswith("Float"):
        for v in out:
            if not math.isfinite(v):
                fail(f"array {arr.get('Name')}: non-finite value {v}")
    return out


def check_vtu(path):
    xml, data = split_appended(path)
    root = ET.fromstring(xml)
    appended = Appended(root, data) if data is not None else None
    if root.tag != "VTKFile" or root.get("type") != "UnstructuredGrid":
        fail(f"{path}: not a VTKFile UnstructuredGrid")
    grid = root.find("UnstructuredGrid")
    for fd in grid.findall("FieldData/DataArray"):
        print("array", path, "FieldData", fd.get("Name"), 1, *values(fd, appended))
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
            v = values(arr, appended)
            if len(v) != count * comps:
                fail(f"{path}: {section}/{arr.get('Name')} holds {len(v)} values, expected {count} x {comps}")
            data[(section, arr.get("Name"))] = v
            print("array", path, section, arr.get("Name"), comps, *v)
    cells = {a.get("Name"): values(a, appended) for a in piece.findall("Cells/DataArray")}
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


def declared(arr):
    return (arr.get("Name"), arr.get("type"), int(arr.get("NumberOfComponents", "1")))


def check_pvtu(path):
    root = ET.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "PUnstructuredGrid":
        fail(f"{path}: not a VTKFile PUnstructuredGrid")
    grid = root.find("PUnstructuredGrid")
    point_data = [declared(a) for a in grid.findall("PPointData/PDataArray")]
    points = [declared(a) for a in grid.findall("PPoints/PDataArray")]
    if len(points) != 1:
        fail(f"{path}: PPoints declares {len(points)} arrays, expected one")
    sources = [p.get("Source") for p in grid.findall("Piece")]
    if not sources:
        fail(f"{path}: no Piece")
    base = os.path.dirname(path)
    for source in sources:
        piece = os.path.join(base, source)
        print("source", path, source)
        if not os.path.isfile(piece):
            fail(f"{path}: piece {piece} missing")
        check_vtu(piece)
        xml, _ = split_appended(piece)
        grid_piece = ET.fromstring(xml).find("UnstructuredGrid/Piece")
        held = [declared(a) for a in grid_piece.findall("PointData/DataArray")]
        if held != point_data:
            fail(f"{piece}: point arrays {held} differ from those {path} declares {point_data}")
        held_points = [declared(a) for a in grid_piece.findall("Points/DataArray")]
        if [(t, c) for _, t, c in held_points] != [(t, c) for _, t, c in points]:
            fail(f"{piece}: Points {held_points} differ from {path}'s {points}")


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
        (check_pvtu if target.endswith(".pvtu") else check_vtu)(target)


if __name__ == "__main__":
    for p in sys.argv[1:]:
        try:
            (check_pvd if p.endswith(".pvd") else check_pvtu if p.endswith(".pvtu") else check_vtu)(p)
        except ET.ParseError as e:
            fail(f"{p}: not well-formed XML: {e}")
