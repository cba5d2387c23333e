"""Log-log convergence plot for `mpm converge --plot`, in the style of Wallstedt & Guilkey 2008, Figs 3-7.

Usage: python3 convergence.py ROWS.json OUT.png VARY TITLE
ROWS.json is the list `mpm converge --json` prints; one line per (kernel, integrator, transfer) series.
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

NAMES = {"cpgimp": "cpGIMP", "ugimp": "uGIMP", "linear": "MPM", "bspline2": "B2", "bspline3": "B3",
         "bspline2-clamped": "B2c", "bspline3-clamped": "B3c", "cpdi": "CPDI", "cpdi2": "CPDI2",
         "ugimp-wide": "uGIMPw", "cpgimp-wide": "cpGIMPw"}


def label(kernel, integrator, transfer):
    name = f"{'UVF' if integrator == 'musl' else integrator.upper()}-{NAMES.get(kernel, kernel)}"
    return name + ("-APIC" if transfer == "apic" else "")


def main(rows_path, png_path, vary, title):
    with open(rows_path) as f:
        rows = json.load(f)
    series = {}
    for r in rows:
        series.setdefault((r["kernel"], r["integrator"], r.get("transfer", "flip")), []).append(r)
    fig, ax = plt.subplots(figsize=(5.5, 4))
    for (kernel, integrator, transfer), points in series.items():
        xs = [1 / r["cells"] if vary == "cells" else r["cfl"] for r in points]
        ax.loglog(xs, [r["linf"] for r in points], marker="o", label=label(kernel, integrator, transfer))
    ax.set_xlabel("cell size h / body extent" if vary == "cells" else "CFL number")
    ax.set_ylabel("L-infinity displacement error (1 = failed)")
    ax.set_title(title)
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png_path, dpi=120)


if __name__ == "__main__":
    main(*sys.argv[1:5])
