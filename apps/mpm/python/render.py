"""Particle pictures for `mpm render`: one PNG per output time, particles coloured by a field.

Usage: python3 render.py DIR FIELD EVERY [PLANE]   (PLANE: xy, xz or yz; default xy)
Reads DIR/particles.pvd and every EVERY-th dataset it lists (the last one always), and writes
DIR/pictures/FIELD_NNNN.png (NNNN: the index of the dataset in the .pvd, as in particles_NNNN.vtp or, from a run divided between ranks, particles_NNNN.pvtp). FIELD is a point-data array name; vectors and tensors are
coloured by magnitude, or by one component with FIELD:K (e.g. velocity:1, stress:0). Axis limits and colour range
are the same in every frame. The .vtp files are read without VTK (raw appended data, as mpm::io::write_vtp
writes them), so only numpy and matplotlib are needed. Exit status: 2 bad arguments or files, 3 no matplotlib,
4 no such field (the available names go to stderr).
"""
import os
import sys
import xml.etree.ElementTree as ET

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from mpl_toolkits.axes_grid1 import make_axes_locatable
except ImportError:
    sys.stderr.write("python3-matplotlib is not installed (Debian: apt-get install python3-matplotlib)\n")
    sys.exit(3)

TYPES = {"Float64": "f8", "Float32": "f4", "Int64": "i8", "Int32": "i4", "UInt64": "u8", "UInt32": "u4",
         "Int8": "i1", "UInt8": "u1"}
MARKER = b'<AppendedData encoding="raw">'


def fail(message, status=2):
    sys.stderr.write(f"render: {message}\n")
    sys.exit(status)


def read_vtp(path):
    """The arrays of a .vtp with raw appended data: {"points": (n, 3), name: (n, components)}."""
    with open(path, "rb") as f:
        data = f.read()
    at = data.find(MARKER)
    if at < 0:
        fail(f"{path}: no raw <AppendedData> block (only raw appended .vtp files are supported)")
    root = ET.fromstring(data[:at] + b"</VTKFile>")
    if root.get("compressor"):
        fail(f"{path}: compressed .vtp files are not supported")
    order = "<" if root.get("byte_order", "LittleEndian") == "LittleEndian" else ">"
    size_type = np.dtype(order + TYPES[root.get("header_type", "UInt32")])
    base = data.index(b"_", at + len(MARKER)) + 1

    def array(node):
        start = base + int(node.get("offset"))
        nbytes = int(np.frombuffer(data, size_type, 1, start)[0])
        values = np.frombuffer(data, order + TYPES[node.get("type")], offset=start + size_type.itemsize,
                               count=nbytes // np.dtype(TYPES[node.get("type")]).itemsize)
        return values.reshape(-1, int(node.get("NumberOfComponents", "1")))

    piece = root.find("PolyData/Piece")
    arrays = {"points": array(piece.find("Points/DataArray"))}
    for node in piece.findall("PointData/DataArray"):
        arrays[node.get("Name")] = array(node)
    return arrays


def read_labels(path):
    """The names of each array's components and each array's unit, from a frame's header (a .pvtp's first
    piece): ({name: [component names]}, {name: unit}); empty for a file written without them."""
    if path.endswith(".pvtp"):
        piece = next(ET.parse(path).getroot().iter("Piece"), None)
        if piece is None:
            return {}, {}
        path = os.path.join(os.path.dirname(path), piece.get("Source"))
    with open(path, "rb") as f:
        data = f.read()
    at = data.find(MARKER)
    root = ET.fromstring(data[:at] + b"</VTKFile>")
    names = {}
    for node in root.iter("DataArray"):
        k = int(node.get("NumberOfComponents", "1"))
        if node.get("Name") and node.get("ComponentName0") is not None:
            names[node.get("Name")] = [node.get(f"ComponentName{c}", str(c)) for c in range(k)]
    units = {}
    for node in root.iter("Array"):  # the field data: VTK's ASCII strings, bytes as numbers, each ended by 0
        if node.get("Name") == "units" and node.get("type") == "String":
            for entry in bytes(int(b) for b in node.text.split()).split(b"\0"):
                name, _, unit = entry.decode().partition(": ")
                if unit:
                    units[name] = unit
    return names, units


def colour_label(name, component, magnitude, names, units):
    """The colour bar's label: the field, its component by name (or number) or |field| for a magnitude, and
    its unit in brackets when the frame gives one."""
    if magnitude:
        text = f"|{name}|"
    elif component is not None:
        text = f"{name} {names[name][component]}" if name in names else f"{name}:{component}"
    else:
        text = name
    return f"{text} [{units[name]}]" if name in units else text


def read_frame(path):
    """A frame's arrays: a .vtp, or the pieces a .pvtp lists (a run divided between ranks), joined."""
    if not path.endswith(".pvtp"):
        return read_vtp(path)
    sources = [p.get("Source") for p in ET.parse(path).getroot().iter("Piece")]
    if not sources:
        fail(f"{path} lists no pieces")
    parts = [read_vtp(os.path.join(os.path.dirname(path), source)) for source in sources]
    return {name: np.concatenate([part[name] for part in parts]) for name in parts[0]}


def scalar(values, component, name):
    """One value per point: the component asked for, or the magnitude (6 components: a symmetric tensor
    xx yy zz xy yz xz, Frobenius norm)."""
    if component is not None:
        if not 0 <= component < values.shape[1]:
            fail(f"{name} has {values.shape[1]} components; component {component} does not exist", 4)
        return values[:, component]
    if values.shape[1] == 1:
        return values[:, 0]
    weights = np.array([1, 1, 1, 2, 2, 2]) if values.shape[1] == 6 else np.ones(values.shape[1])
    return np.sqrt((values**2) @ weights)


def main(folder, field, every, plane="xy"):
    name, _, comp = field.partition(":")
    try:
        every, component = int(every), (int(comp) if comp else None)
    except ValueError:
        fail(f"EVERY ({every}) and the component in FIELD ({field}) must be integers")
    if every < 1:
        fail(f"EVERY must be at least 1, got {every}")
    pvd = os.path.join(folder, "particles.pvd")
    if not os.path.exists(pvd):
        fail(f"{pvd} does not exist")
    entries = [(float(d.get("timestep")), d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet")]
    if not entries:
        fail(f"{pvd} lists no datasets")
    indices = list(range(0, len(entries), every)) + ([len(entries) - 1] if (len(entries) - 1) % every else [])
    chosen = [entries[i] for i in indices]

    names, units = read_labels(os.path.join(folder, chosen[-1][1]))
    frames = []
    for time, file in chosen:
        arrays = read_frame(os.path.join(folder, file))
        if name not in arrays or name == "points":
            available = ", ".join(k for k in arrays if k != "points")
            fail(f"no field '{name}' in {file}; available: {available}", 4)
        frames.append((time, arrays["points"], scalar(arrays[name], component, name)))
        magnitude = component is None and arrays[name].shape[1] > 1

    if plane not in ("xy", "xz", "yz"):
        fail(f"PLANE must be xy, xz or yz, got {plane}")
    axes = ["xyz".index(plane[0]), "xyz".index(plane[1])]
    xy = np.concatenate([p[:, axes] for _, p, _ in frames])
    values = np.concatenate([v for _, _, v in frames])
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = 0.05 * max(hi - lo) if max(hi - lo) > 0 else 1.0
    vmin, vmax = float(values.min()), float(values.max())
    if vmin == vmax:
        vmin, vmax = vmin - 0.5, vmax + 0.5

    out_dir = os.path.join(folder, "pictures")
    os.makedirs(out_dir, exist_ok=True)
    stem = field.replace(":", "_")
    for frame, (time, points, value) in zip(indices, frames):
        fig, ax = plt.subplots(figsize=(6, 5))
        size = min(20.0, max(0.2, 2e4 / len(points)))
        dots = ax.scatter(points[:, axes[0]], points[:, axes[1]], c=value, s=size, vmin=vmin, vmax=vmax, cmap="viridis",
                          linewidths=0)
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_aspect("equal")
        ax.set_xlabel(f"{plane[0]} [{units.get('Points', 'm')}]")
        ax.set_ylabel(f"{plane[1]} [{units.get('Points', 'm')}]")
        ax.set_title(f"{field}   t = {time:.6g}")
        cax = make_axes_locatable(ax).append_axes("right", size="4%", pad=0.1)  # as tall as the axes
        fig.colorbar(dots, cax=cax, label=colour_label(name, component, magnitude, names, units))
        fig.tight_layout()
        path = os.path.join(out_dir, f"{stem}_{frame:04d}.png")
        fig.savefig(path, dpi=100)
        plt.close(fig)
        print(path)


if __name__ == "__main__":
    if len(sys.argv) not in (4, 5):
        fail("usage: render.py DIR FIELD EVERY")
    main(*sys.argv[1:5])
