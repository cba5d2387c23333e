"""Reading a finished run's output folder (``mpm run --out DIR`` or ``Simulation(..., out=DIR)``) without VTK."""
import csv
import json
import os
import re

import numpy as np

_ARRAY = re.compile(rb'<DataArray type="(\w+)"(?: Name="([^"]*)")? NumberOfComponents="(\d+)"'
                    rb'(?: ComponentName\d+="[^"]*")* format="appended" offset="(\d+)"/>')
_DATASET = re.compile(r'<DataSet timestep="([^"]+)"[^>]* file="([^"]+)"')
_PIECE = re.compile(r'<Piece Source="([^"]+)"/>')
_TYPES = {b"Float64": "<f8", b"Int64": "<i8"}


def read_vtp(path):
    """The points (n x 3) and point fields (name -> array of n rows) of a particles_NNNN.vtp file as mpm writes it
    (raw appended data, little-endian, UInt64 block headers)."""
    with open(path, "rb") as f:
        content = f.read()
    marker = content.find(b'<AppendedData encoding="raw">')
    if marker < 0:
        raise ValueError(f"{path}: not a .vtp file written by mpm (no raw appended data)")
    start = content.index(b"_", marker) + 1
    fields, points = {}, None
    for kind, name, components, offset in _ARRAY.findall(content[:marker]):
        at = start + int(offset)
        size = int(np.frombuffer(content, "<u8", 1, at)[0])
        values = np.frombuffer(content, _TYPES[kind], size // 8, at + 8)
        components = int(components)
        values = values.reshape(-1, components) if components > 1 else values
        if name:
            if name not in (b"connectivity", b"offsets"):
                fields[name.decode()] = values
        else:
            points = values
    return points, fields


def _read_frame(folder, dataset):
    path = os.path.join(folder, dataset)
    if not dataset.endswith(".pvtp"):
        return read_vtp(path)
    with open(path) as f:
        pieces = [read_vtp(os.path.join(folder, p)) for p in _PIECE.findall(f.read())]
    points = np.concatenate([p for p, _ in pieces])
    fields = {name: np.concatenate([f[name] for _, f in pieces]) for name in pieces[0][1]}
    return points, fields


class Output:
    """A finished run: ``summary`` (summary.json as a dict), ``history`` (history.csv: column name -> array),
    ``times`` (the frames' times) and ``frame(k)`` (points and fields of frame k, read when asked)."""

    def __init__(self, folder):
        self.folder = os.fspath(folder)
        summary = os.path.join(self.folder, "summary.json")
        if not os.path.isfile(summary):
            raise ValueError(f"{self.folder}: not an mpm output folder (no summary.json)")
        with open(summary) as f:
            self.summary = json.load(f)
        self.history = {}
        history = os.path.join(self.folder, "history.csv")
        if os.path.isfile(history):
            with open(history, newline="") as f:
                rows = list(csv.reader(f))
            columns = np.array(rows[1:], dtype=float).T if len(rows) > 1 else [[]] * len(rows[0])
            self.history = {name: np.asarray(col) for name, col in zip(rows[0], columns)}
        self._frames = []
        pvd = os.path.join(self.folder, "particles.pvd")
        if os.path.isfile(pvd):
            with open(pvd) as f:
                self._frames = [(float(t), name) for t, name in _DATASET.findall(f.read())]
        self.times = np.array([t for t, _ in self._frames])

    def __len__(self):
        return len(self._frames)

    def frame(self, k):
        """Frame k (negative counts from the last): a dict of the point fields with "x" the positions (n x 3) and
        "time"."""
        t, dataset = self._frames[k]
        points, fields = _read_frame(self.folder, dataset)
        return {"time": t, "x": points, **fields}

    def __repr__(self):
        return (f"Output({self.folder!r}: {self.summary.get('status')}, {len(self)} frames, "
                f"{len(next(iter(self.history.values()), []))} history rows)")


def read_output(folder):
    """Load the output folder of a finished (or stopped) run: see Output."""
    return Output(folder)
