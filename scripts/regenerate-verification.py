#!/usr/bin/python3
"""Regenerate docs/verification.md and its plots from the convergence studies of Wallstedt & Guilkey (2008),
Sec. 6, run by the real engine through `mpm converge`.

Usage (after building): /usr/bin/python3 scripts/regenerate-verification.py [--quick] [--mpm build/bin/mpm]
Needs Debian's python3-matplotlib. The full run takes several minutes on 2 cores; --quick uses coarser sweeps.
"""
import argparse
import json
import pathlib
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
SERIES = [  # (kernel, integrator): the combinations of the paper's Figs 3-7, plus the B-splines
    ("cpgimp", "usf"), ("cpgimp", "usl"), ("cpgimp", "cd"), ("ugimp", "cd"), ("linear", "musl"),
    ("bspline2", "cd"), ("bspline3", "cd"),
]


def converge(mpm, case, vary, values, kernel, integrator, extra=()):
    cmd = [mpm, "converge", case, "--vary", vary, "--values", ",".join(str(v) for v in values),
           "--kernel", kernel, "--integrator", integrator, "--json", *extra]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def label(kernel, integrator):
    names = {"cpgimp": "cpGIMP", "ugimp": "uGIMP", "linear": "MPM", "bspline2": "B2", "bspline3": "B3"}
    return f"{'UVF' if integrator == 'musl' else integrator.upper()}-{names[kernel]}"


def plot(results, vary, title, path):
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for (kernel, integrator), rows in results.items():
        xs = [1 / r["cells"] if vary == "cells" else r["cfl"] for r in rows]
        ax.loglog(xs, [r["linf"] for r in rows], marker="o", label=label(kernel, integrator))
    ax.set_xlabel("cell size h" if vary == "cells" else "CFL number")
    ax.set_ylabel("L-infinity displacement error (1 = failed)")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def table(results, vary):
    head = f"| series | " + " | ".join(f"{vary} {r[vary]}" for r in next(iter(results.values()))) + " |"
    lines = [head, "|" + "---|" * (len(next(iter(results.values()))) + 1)]
    for (kernel, integrator), rows in results.items():
        cells = []
        for r in rows:
            text = "failed" if r["status"] != "ok" else f"{r['linf']:.3g}"
            if "order" in r and r["status"] == "ok":
                text += f" ({r['order']:.2f})"
            cells.append(text)
        lines.append(f"| {label(kernel, integrator)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mpm", default=str(ROOT / "build" / "bin" / "mpm"))
    ap.add_argument("--quick", action="store_true", help="coarser sweeps (about a minute)")
    args = ap.parse_args()
    start = time.time()
    cfls = [0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8] if not args.quick else [0.1, 0.4, 0.8]
    cells = [8, 16, 32, 64, 128] if not args.quick else [8, 16, 32]
    studies = [  # (case, vary, values, fixed options, title, file)
        ("axis-aligned", "cfl", cfls, ["--cells", "56" if not args.quick else "16"],
         "Axis-aligned: temporal convergence (paper Fig. 3)", "axis_aligned_cfl.png"),
        ("axis-aligned", "cells", cells, ["--cfl", "0.4"],
         "Axis-aligned: spatial convergence (paper Fig. 4)", "axis_aligned_cells.png"),
        ("expanding-ring", "cfl", cfls, ["--cells", "56" if not args.quick else "16"],
         "Expanding ring: temporal convergence (paper Fig. 6)", "ring_cfl.png"),
        ("expanding-ring", "cells", cells, ["--cfl", "0.4"],
         "Expanding ring: spatial convergence (paper Fig. 7)", "ring_cells.png"),
        ("bar-1d", "cells", [8, 16, 32, 64, 128, 256], ["--cfl", "0.4", "--amplitude", "0.01"],
         "1-D bar, A = 0.01: spatial convergence", "bar_cells.png"),
    ]
    sections = []
    for case, vary, values, fixed, title, file in studies:
        results = {}
        for kernel, integrator in SERIES:
            results[(kernel, integrator)] = converge(args.mpm, case, vary, values, kernel, integrator, fixed)
        plot(results, vary, title, ROOT / "docs" / "verification" / file)
        sections.append(f"### {title}\n\n`mpm converge {case} --vary {vary} --values "
                        f"{','.join(map(str, values))} {' '.join(fixed)} --kernel K --integrator I`\n\n"
                        f"![{title}](verification/{file})\n\n"
                        f"L-infinity error, observed order in brackets:\n\n{table(results, vary)}\n")
        print(f"{title}: done ({time.time() - start:.0f} s)", file=sys.stderr)
    doc = ROOT / "docs" / "verification.md"
    text = doc.read_text() if doc.exists() else ""
    marker = "<!-- generated below by scripts/regenerate-verification.py -->"
    head = text.split(marker)[0] if marker in text else "# Verification\n\n"
    doc.write_text(head + marker + "\n\n" + "\n".join(sections) +
                   f"\nGenerated in {time.time() - start:.0f} s{' (--quick)' if args.quick else ''}.\n")


if __name__ == "__main__":
    main()
