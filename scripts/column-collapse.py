#!/usr/bin/env python3
"""Draw docs/geomechanics/column-collapse.png: the run-out and final height of examples/geomechanics/column-collapse.toml
(a planar column of Mohr-Coulomb sand released against a frictionless wall) for aspect ratios a = 0.5, 1 and 2,
with phi = 30 degrees on a floor of friction 0.5 (the example) and phi = 35 degrees on one of 0.7, against the
laws of Lube et al. (2005); and print each deposit as tests/verification/test_column_collapse.cpp measures it.

Usage (after building): /usr/bin/python3 scripts/column-collapse.py [--mpm build/bin/mpm] [--ratios 0.5 1 2]
Needs Debian's python3-matplotlib. The runs go to out/column-collapse/ (a = 0.5 and 1 take a minute or two each,
a = 2 about 7 minutes: the particles the flow flings apart stretch, and the stable step shrinks with them).
"""
import argparse
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from mpm_output import read_vtp  # noqa: E402
SCENE = ROOT / "examples/geomechanics/column-collapse.toml"
L0 = 0.2
H = L0 / 20  # the example's cell
MATERIALS = (("phi = 30, floor 0.5", "30", "0.5"), ("phi = 35, floor 0.7", "35", "0.7"))


def deposit(xy):
    """(run-out (L - L0) / L0, height H / L0) as the test measures them."""
    top = {}
    for x, y in xy:
        k = int(x / H)
        top[k] = max(top.get(k, 0.0), y)
    last = max(k for k, t in top.items() if t > H)
    return ((last + 1) * H - L0) / L0, (top.get(0, 0.0) + H / 4) / L0


def run(mpm, a, phi, mu, out):
    end = 0.5 if a <= 0.5 else 0.75 if a <= 1 else 1.5
    width, height = L0 * (2 + 3 * a), L0 * (a + 0.5)
    cells = [round(width / H), round(height / H)]
    subprocess.run([mpm, "run", str(SCENE), "--quiet", "--out", str(out), "--set", f"constants.a={a}",
                    "--set", f"constants.phi={phi}", "--set", f"constants.mu={mu}",
                    "--set", f"simulation.end_time={end}", "--set", f"output.every={end}",
                    "--set", f"grid.hi=[{cells[0] * H},{cells[1] * H}]", "--set", f"grid.cells={cells}"],
                   check=True, stdout=subprocess.DEVNULL)
    return deposit(read_vtp(out / "particles_0001.vtp")["points"][:, :2])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mpm", default=str(ROOT / "build/bin/mpm"))
    parser.add_argument("--ratios", type=float, nargs="+", default=[0.5, 1.0, 2.0])
    args = parser.parse_args()
    fig, (ax_l, ax_h) = plt.subplots(1, 2, figsize=(9, 3.8))
    for label, phi, mu in MATERIALS:
        runouts, heights = [], []
        for a in args.ratios:
            r, hgt = run(args.mpm, a, phi, mu, ROOT / f"out/column-collapse/phi{phi}_a{a}")
            print(f"{label}: a = {a}: run-out {r:.3f} (Lube 1.2 a = {1.2 * a:.3f}), height {hgt:.3f}")
            runouts.append(r)
            heights.append(hgt)
        ax_l.plot(args.ratios, runouts, "o-", label=label)
        ax_h.plot(args.ratios, heights, "o-", label=label)
    a = [0.25 + 0.05 * k for k in range(80)]
    ax_l.plot([x for x in a if x < 1.8], [1.2 * x for x in a if x < 1.8], "k--", lw=1, label="1.2 a (a < 1.8)")
    ax_l.plot([x for x in a if x > 2.8], [1.9 * x ** (2 / 3) for x in a if x > 2.8], "k:", lw=1,
              label="1.9 a^(2/3) (a > 2.8)")
    ax_h.plot([x for x in a if x < 1.15], [x for x in a if x < 1.15], "k--", lw=1, label="a (a < 1.15)")
    ax_l.set_xlabel("a = H0 / L0")
    ax_l.set_ylabel("run-out (L - L0) / L0")
    ax_h.set_xlabel("a = H0 / L0")
    ax_h.set_ylabel("final height H / L0")
    for ax in (ax_l, ax_h):
        ax.set_xlim(0, max(args.ratios) + 0.5)
        ax.legend(fontsize=8)
    fig.suptitle("Planar granular column collapse against Lube et al. (2005), h = L0 / 20")
    fig.tight_layout()
    out = ROOT / "docs/geomechanics/column-collapse.png"
    out.parent.mkdir(exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
