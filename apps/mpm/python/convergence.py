"""Log-log convergence plot for `mpm converge --plot`, in the style of Wallstedt & Guilkey 2008, Figs 3-7.

Usage: python3 convergence.py ROWS.json OUT.png VARY TITLE LABELS
ROWS.json is the list `mpm converge --json` prints; one line per (kernel, integrator, transfer) series. LABELS is a
JSON object of each kernel's label in the plots, from the kernel registry (include/mpm/shape/kernel_kind.hpp).
"""
import json
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
except ImportError:
    sys.stderr.write("python3-matplotlib is not installed (Debian: apt-get install python3-matplotlib)\n")
    sys.exit(3)

def label(names, kernel, integrator, transfer):
    name = f"{'UVF' if integrator == 'musl' else integrator.upper()}-{names.get(kernel, kernel)}"
    return name + ("-APIC" if transfer == "apic" else "")


def main(rows_path, png_path, vary, title, labels):
    names = json.loads(labels)
    with open(rows_path) as f:
        rows = json.load(f)
    series = {}
    for r in rows:
        series.setdefault((r["kernel"], r["integrator"], r.get("transfer", "flip")), []).append(r)
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for (kernel, integrator, transfer), points in series.items():
        xs = [1 / r["cells"] if vary == "cells" else r["cfl"] for r in points]
        ax.loglog(xs, [r["linf"] for r in points], marker="o", label=label(names, kernel, integrator, transfer))
    ax.set_xlabel("cell size h / body extent" if vary == "cells" else "CFL number")
    ax.set_ylabel("L-infinity displacement error (1 = failed)")
    ax.set_title(title)
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png_path, dpi=120)


if __name__ == "__main__":
    main(*sys.argv[1:6])
