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
# Linear MPM with USF and USL, which Sec. 6.1.1 ranks against UVF-MPM without plotting them.
LINEAR_MPM = [("linear", "usf"), ("linear", "usl")]
# APIC (docs/transfers.md) beside FLIP: (kernel, integrator, transfer).
APIC = [("cpgimp", "usl", "flip"), ("cpgimp", "usl", "apic"), ("cpgimp", "cd", "flip"), ("cpgimp", "cd", "apic"),
        ("bspline2", "cd", "flip"), ("bspline2", "cd", "apic"), ("bspline3", "cd", "flip"), ("bspline3", "cd", "apic")]
# CPDI and CPDI2 (docs/kernels.md) beside GIMP: (kernel, integrator).
CPDI = [("cpgimp", "cd"), ("ugimp", "cd"), ("cpdi", "cd"), ("cpdi", "usl"), ("cpdi2", "cd")]
# The paper's CFL number: dt = CFL h / c with c^2 = E / rho0, the wave speed of its manufactured solutions.
PAPER_CFL = ["--cfl-speed", "reference"]


def converge(mpm, case, vary, values, extra, title, png, series_list):
    """Every series of one study through `mpm converge`, which also draws the plot; rows grouped by series."""
    series = ",".join(":".join(s) for s in series_list)
    cmd = [mpm, "converge", case, "--vary", vary, "--values", ",".join(str(v) for v in values),
           "--series", series, "--plot", str(png), "--title", title, "--json", *extra]
    rows = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    results = {}
    for r in rows:
        results.setdefault((r["kernel"], r["integrator"], r["transfer"]), []).append(r)
    return results


def label(kernel, integrator, transfer):
    names = {"cpgimp": "cpGIMP", "ugimp": "uGIMP", "linear": "MPM", "bspline2": "B2", "bspline3": "B3", "cpdi": "CPDI",
             "cpdi2": "CPDI2"}
    name = f"{'UVF' if integrator == 'musl' else integrator.upper()}-{names[kernel]}"
    return name + ("-APIC" if transfer == "apic" else "")


KERNEL_NAMES = {"linear": "linear (MPM)", "cpgimp": "GIMP", "bspline2": "quadratic B-spline",
                "bspline3": "cubic B-spline"}


def density_section(mpm, path):
    """Seed 001 Fig. 7: projected density of a unit bar on [0, 1] in a grid on [-0.2, 1.2], h = 0.1."""
    runs = {k: json.loads(subprocess.run([mpm, "density-1d", "--kernel", k, "--json"], check=True,
                                         capture_output=True, text=True).stdout) for k in KERNEL_NAMES}
    fig, ax = plt.subplots(figsize=(5.5, 3.5))
    ax.plot([-0.2, 0, 0, 1, 1, 1.2], [0, 0, 1, 1, 0, 0], "k-", lw=1, label="true density")
    for k in ["linear", "bspline2", "bspline3"]:
        ax.plot(runs[k]["sample_x"], runs[k]["sample_density"], label=f"{KERNEL_NAMES[k]} basis")
    ax.plot(runs["linear"]["particle_x"], [0] * len(runs["linear"]["particle_x"]), "o", ms=3, mfc="none",
            label="particle positions")
    ax.set_xlabel("x")
    ax.set_ylabel("projected density")
    ax.set_ylim(-0.5, 1.5)
    ax.legend(fontsize=7)
    ax.set_title("Projected density (Steffen et al. 2008, Fig. 7)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    rows = ["| kernel | density nonzero on | L1 error over the grid | L1 error / h |", "|---|---|---|---|"]
    for k, r in runs.items():
        rows.append(f"| {KERNEL_NAMES[k]} | [{r['support_lo']:.3g}, {r['support_hi']:.3g}] | "
                    f"{r['l1_error']:.4g} | {r['l1_error'] / r['h']:.4g} |")
    return ("### Projected density of a constant-density bar (Steffen et al. 2008, Sec. 4.3, Fig. 7)\n\n"
            "`mpm density-1d --kernel K` (10 cells per unit length, 3 particles per cell)\n\n"
            f"![Projected density](verification/{path.name})\n\n" + "\n".join(rows) + "\n\n"
            "Inside the body every kernel reproduces the density exactly (each loaded node has m_i / V_i = 1 "
            "and the bases are partitions of unity). Outside, the field spreads one cell for linear MPM and "
            "GIMP (whose grid basis is the linear hat) and 2.5 and 3 cells for the quadratic and cubic "
            "B-splines. The L1 errors are the closed forms h, h, (3 - 1/24) h and (3 - 1/12) h (the B-spline "
            "tails are cut by the grid end at -0.2); `tests/verification/test_projected_density.cpp` asserts "
            "them and the O(h) scaling the paper states.\n")


def table(results, vary):
    head = f"| series | " + " | ".join(f"{vary} {r[vary]}" for r in next(iter(results.values()))) + " |"
    lines = [head, "|" + "---|" * (len(next(iter(results.values()))) + 1)]
    for (kernel, integrator, transfer), rows in results.items():
        cells = []
        for r in rows:
            text = "failed" if r["status"] != "ok" else f"{r['linf']:.3g}"
            if "order" in r and r["status"] == "ok":
                text += f" ({r['order']:.2f})"
            cells.append(text)
        lines.append(f"| {label(kernel, integrator, transfer)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mpm", default=str(ROOT / "build" / "bin" / "mpm"))
    ap.add_argument("--quick", action="store_true", help="coarser sweeps (about a minute)")
    args = ap.parse_args()
    start = time.time()
    cfls = [0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0] if not args.quick else [0.1, 0.4, 0.8]
    cells = [8, 16, 32, 64, 128] if not args.quick else [8, 16, 32]
    fine = [64, 128, 256] if not args.quick else [16, 32]
    cells56 = ["--cells", "56" if not args.quick else "16"]
    studies = [  # (case, vary, values, fixed options, series, title, file)
        ("axis-aligned", "cfl", cfls, cells56 + PAPER_CFL, SERIES + LINEAR_MPM,
         "Axis-aligned: temporal convergence (paper Fig. 3)", "axis_aligned_cfl.png"),
        ("axis-aligned", "cells", cells, ["--cfl", "0.4"] + PAPER_CFL, SERIES,
         "Axis-aligned: spatial convergence (paper Fig. 4)", "axis_aligned_cells.png"),
        ("expanding-ring", "cfl", cfls, cells56 + PAPER_CFL, SERIES + LINEAR_MPM,
         "Expanding ring: temporal convergence (paper Fig. 6)", "ring_cfl.png"),
        ("expanding-ring", "cells", cells, ["--cfl", "0.4"] + PAPER_CFL, SERIES,
         "Expanding ring: spatial convergence (paper Fig. 7)", "ring_cells.png"),
        ("expanding-ring", "cells", fine, ["--cfl", "0.4"] + PAPER_CFL, [("cpgimp", "cd"), ("ugimp", "cd")],
         "Expanding ring: uGIMP against cpGIMP on the finest meshes", "ring_fine.png"),
        ("axis-aligned", "cells", cells[:4], ["--cfl", "0.4", "--error", "nodal"] + PAPER_CFL, [("cpgimp", "cd")],
         "Axis-aligned: nodal acceleration error (paper App. A), A = 0.1", "axis_aligned_nodal.png"),
        ("axis-aligned", "cells", cells[:4], ["--cfl", "0.4", "--error", "nodal", "--amplitude", "0.001"] + PAPER_CFL,
         [("cpgimp", "cd")], "Axis-aligned: nodal acceleration error (paper App. A), A = 0.001",
         "axis_aligned_nodal_small.png"),
        ("bar-1d", "cells", [8, 16, 32, 64, 128, 256], ["--cfl", "0.4", "--amplitude", "0.01"] + PAPER_CFL,
         SERIES, "1-D bar, A = 0.01: spatial convergence", "bar_cells.png"),
        ("axis-aligned", "cells", cells[:4], ["--cfl", "0.4"] + PAPER_CFL, APIC,
         "Axis-aligned: APIC against FLIP (issue 20, docs/transfers.md)", "axis_aligned_cells_apic.png"),
        ("expanding-ring", "cells", cells[:4], ["--cfl", "0.4"] + PAPER_CFL, APIC,
         "Expanding ring: APIC against FLIP (issue 20, docs/transfers.md)", "ring_cells_apic.png"),
        ("axis-aligned", "cells", cells[:4], ["--cfl", "0.4"] + PAPER_CFL, CPDI,
         "Axis-aligned: CPDI against GIMP (issue 20, docs/kernels.md)", "axis_aligned_cells_cpdi.png"),
        ("expanding-ring", "cells", cells[:4], ["--cfl", "0.4"] + PAPER_CFL, CPDI,
         "Expanding ring: CPDI against GIMP (issue 20, docs/kernels.md)", "ring_cells_cpdi.png"),
        ("shear-wave", "cells", cells[:4], ["--cfl", "0.4", "--amplitude", "0.1"], CPDI,
         "Diagonal shear wave, A = 0.1 (largest shear 0.89): CPDI against GIMP", "shear_wave_cells.png"),
        ("shear-wave", "cells", cells[:4], ["--cfl", "0.4", "--amplitude", "0.3"], CPDI[1:],
         "Diagonal shear wave, A = 0.3 (largest shear 2.67, cpGIMP cannot start): CPDI against uGIMP",
         "shear_wave_large_cells.png"),
    ]
    sections = []
    for case, vary, values, fixed, series, title, file in studies:
        results = converge(args.mpm, case, vary, values, fixed, title, ROOT / "docs" / "verification" / file,
                           series)
        sections.append(f"### {title}\n\n`mpm converge {case} --vary {vary} --values "
                        f"{','.join(map(str, values))} {' '.join(fixed)} --series "
                        f"{','.join(':'.join(s) for s in series)} --plot {file}`\n\n"
                        f"![{title}](verification/{file})\n\n"
                        f"L-infinity error, observed order in brackets:\n\n{table(results, vary)}\n")
        print(f"{title}: done ({time.time() - start:.0f} s)", file=sys.stderr)
    sections.append(density_section(args.mpm, ROOT / "docs" / "verification" / "density_1d.png"))
    doc = ROOT / "docs" / "verification.md"
    text = doc.read_text() if doc.exists() else ""
    marker = "<!-- generated below by scripts/regenerate-verification.py -->"
    head = text.split(marker)[0] if marker in text else "# Verification\n\n"
    doc.write_text(head + marker + "\n\n" + "\n".join(sections) +
                   f"\nGenerated in {time.time() - start:.0f} s{' (--quick)' if args.quick else ''}.\n")


if __name__ == "__main__":
    main()
