"""Readers of what `mpm run --out DIR` writes: the particle frames (DIR/particles.pvd and the .vtp files it
lists) and the per-step history (DIR/history.csv). Needs only numpy; VTK is not used.

The engine writes every .vtp with raw appended data (mpm::io::write_vtp, src/io/vtk.cpp): one Float64 block per
point-data array, then the points; read_vtp reads that layout only. Its arrays have the shapes VTK's
vtkXMLPolyDataReader and vtk_to_numpy give: "points" (n, 3), a one-component array (n,), a k-component array
(n, k).

apps/mpm/python/render.py (`mpm render`) carries its own copy of the .vtp reader: CMake compiles it into the
binary (apps/mpm/embed_python.cmake), which runs it from a temporary file, so it cannot import this module.
"""
import csv
import pathlib
import xml.etree.ElementTree as ET

import numpy as np

TYPES = {"Float64": "f8", "Float32": "f4", "Int64": "i8", "Int32": "i4", "UInt64": "u8", "UInt32": "u4",
         "Int8": "i1", "UInt8": "u1"}
MARKER = b'<AppendedData encoding="raw">'


def read_vtp(path):
    """The arrays of a .vtp with raw appended data: {"points": (n, 3), name: (n,) or (n, components)}."""
    data = pathlib.Path(path).read_bytes()
    at = data.find(MARKER)
    if at < 0:
        raise ValueError(f"{path}: no raw <AppendedData> block (only raw appended .vtp files are supported)")
    root = ET.fromstring(data[:at] + b"</VTKFile>")
    if root.get("compressor"):
        raise ValueError(f"{path}: compressed .vtp files are not supported")
    order = "<" if root.get("byte_order", "LittleEndian") == "LittleEndian" else ">"
    size_type = np.dtype(order + TYPES[root.get("header_type", "UInt32")])
    base = data.index(b"_", at + len(MARKER)) + 1

    def array(node):
        start = base + int(node.get("offset"))
        nbytes = int(np.frombuffer(data, size_type, 1, start)[0])
        value_type = np.dtype(order + TYPES[node.get("type")])
        values = np.frombuffer(data, value_type, offset=start + size_type.itemsize, count=nbytes // value_type.itemsize)
        components = int(node.get("NumberOfComponents", "1"))
        return values if components == 1 else values.reshape(-1, components)

    piece = root.find("PolyData/Piece")
    arrays = {"points": array(piece.find("Points/DataArray"))}
    for node in piece.findall("PointData/DataArray"):
        arrays[node.get("Name")] = array(node)
    return arrays


def read_frame(path):
    """A frame's arrays: a .vtp, or the pieces a .pvtp lists (a run divided between ranks, one piece per rank),
    joined in the order listed."""
    path = pathlib.Path(path)
    if path.suffix != ".pvtp":
        return read_vtp(path)
    sources = [p.get("Source") for p in ET.parse(path).getroot().iter("Piece")]
    if not sources:
        raise ValueError(f"{path} lists no pieces")
    parts = [read_vtp(path.parent / source) for source in sources]
    return {name: np.concatenate([part[name] for part in parts]) for name in parts[0]}


def read_pvd(path):
    """[(time, path of the dataset)] from a .pvd collection, in its order; the paths are relative to its folder."""
    path = pathlib.Path(path)
    return [(float(d.get("timestep")), path.parent / d.get("file")) for d in ET.parse(path).getroot().iter("DataSet")]


def read_history(path):
    """{column name: values} from a history.csv. A run stopped mid-write may leave a partly written last line,
    which is dropped."""
    rows = []
    with open(path) as f:
        reader = csv.reader(f)
        head = next(reader)
        for row in reader:
            try:
                if len(row) == len(head):
                    rows.append([float(v) for v in row])
            except ValueError:
                pass
    data = np.array(rows, dtype=float).reshape(-1, len(head))
    return {name: data[:, i] for i, name in enumerate(head)}
