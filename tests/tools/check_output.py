#!/usr/bin/env python3
"""Checks that every file in an adem output folder is complete (scripts/killtest.sh).

  check_output.py OUTDIR        prints one line per problem and a summary; exit 1 if any

VTU: the XML head parses, the file ends with the closing tags, and the raw appended blocks (an
UInt64 size, then the data) tile the appended section exactly. PVD: parses as XML and every
DataSet's file exists. CSV: the header, then whole rows (newline-terminated) with the header's
column count, every field a number. checkpoint: the header's payload size and FNV-1a checksum
match. If python3-vtk9 is installed, VTK's XML readers open every VTU and PVD as well. Hidden
temporary files (.NAME.tmp.PID.N) of a killed process are counted, not judged: adem never reads
them.
"""
import os
import struct
import sys
import xml.etree.ElementTree as ET

try:
    import vtk  # optional: python3-vtk9
    vtk.vtkObject.GlobalWarningDisplayOff()
except Exception:  # noqa: BLE001 - any import failure means: no VTK check
    vtk = None

TAIL = b"\n  </AppendedData>\n</VTKFile>\n"


def check_vtu(path, data):
    start = data.find(b'<AppendedData encoding="raw">')
    if start < 0:
        return "no AppendedData section"
    us = data.find(b"_", start)
    if us < 0 or not data.endswith(TAIL):
        return "does not end with the closing tags"
    try:
        root = ET.fromstring(data[:start] + b"</VTKFile>")
    except ET.ParseError as e:
        return "XML head does not parse: %s" % e
    block = data[us + 1:len(data) - len(TAIL)]
    offsets = sorted(int(a.get("offset")) for a in root.iter("DataArray") if a.get("format") == "appended")
    for k, off in enumerate(offsets):
        if off + 8 > len(block):
            return "appended block at %d is cut" % off
        (n,) = struct.unpack_from("<Q", block, off)
        end = offsets[k + 1] if k + 1 < len(offsets) else len(block)
        if off + 8 + n != end:
            return "appended block at %d holds %d bytes, %d expected" % (off, end - off - 8, n)
    piece = root.find("./UnstructuredGrid/Piece")
    if piece is None:
        return "no Piece"
    return None


def check_pvd(path, data):
    try:
        root = ET.fromstring(data)
    except ET.ParseError as e:
        return "does not parse: %s" % e
    folder = os.path.dirname(path)
    for ds in root.iter("DataSet"):
        if not os.path.exists(os.path.join(folder, ds.get("file"))):
            return "lists %s, which is missing" % ds.get("file")
    return None


def check_csv(path, data):
    if not data.endswith(b"\n"):
        return "ends inside a row"
    lines = data.decode("ascii", "replace").split("\n")[:-1]
    ncol = len(lines[0].split(","))
    for i, line in enumerate(lines[1:], start=2):
        fields = line.split(",")
        if len(fields) != ncol:
            return "row %d has %d fields, the header %d" % (i, len(fields), ncol)
        try:
            [float(f) for f in fields]
        except ValueError:
            return "row %d has a field that is not a number" % i
    return None


def fnv1a(data):
    h = 0xCBF29CE484222325
    for b in data:
        h = ((h ^ b) * 0x100000001B3) & 0xFFFFFFFFFFFFFFFF
    return h


def check_checkpoint(path, data):
    if len(data) < 40 or data[:8] != b"ADEMCKPT":
        return "no checkpoint header"
    payload, h = struct.unpack_from("<QQ", data, 16)
    if payload != len(data) - 40:
        return "payload size %d, file holds %d" % (payload, len(data) - 40)
    if fnv1a(data[40:]) != h:
        return "checksum does not match"
    return None


def check_vtk(path):
    if path.endswith(".vtu"):
        r = vtk.vtkXMLUnstructuredGridReader()
    elif path.endswith(".pvd"):
        r = vtk.vtkPVDReader() if hasattr(vtk, "vtkPVDReader") else None
        if r is None:
            return None
    else:
        return None
    errors = []
    r.AddObserver("ErrorEvent", lambda obj, ev: errors.append(ev))
    r.SetFileName(path)
    r.Update()
    if errors or r.GetErrorCode():
        return "VTK's reader fails"
    if path.endswith(".vtu") and r.GetOutput().GetNumberOfPoints() != r.GetNumberOfPoints():
        return "VTK reads another number of points"
    return None


def main():
    out = sys.argv[1]
    problems, counts, temps = [], {}, 0
    for folder, _, files in os.walk(out):
        for name in sorted(files):
            path = os.path.join(folder, name)
            if name.startswith("."):
                temps += 1
                continue
            with open(path, "rb") as f:
                data = f.read()
            kind = ("vtu" if name.endswith(".vtu") else "pvd" if name.endswith(".pvd") else
                    "csv" if name.endswith(".csv") else "checkpoint" if name == "checkpoint" else None)
            if kind is None:
                continue
            counts[kind] = counts.get(kind, 0) + 1
            why = {"vtu": check_vtu, "pvd": check_pvd, "csv": check_csv,
                   "checkpoint": check_checkpoint}[kind](path, data)
            if why is None and vtk is not None:
                why = check_vtk(path)
            if why:
                problems.append("%s: %s" % (os.path.relpath(path, out), why))
    for p in problems:
        print("corrupt: " + p)
    print("checked %s; %d corrupt; %d hidden temporary file(s); vtk %s" % (
        ", ".join("%d %s" % (n, k) for k, n in sorted(counts.items())) or "nothing",
        len(problems), temps, "on" if vtk is not None else "off"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
