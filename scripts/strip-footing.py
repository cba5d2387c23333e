#!/usr/bin/env python3
"""Draw docs/geomechanics/strip-footing.png: the load-settlement curves of examples/geomechanics/strip-footing.toml
(a rough rigid footing of width B pushed into weightless Tresca clay) at B/20, B/40 and B/80, measured by the real
engine, against Prandtl's limit pressure (2 + pi) c; and print each curve's limit pressure, the mean of
2 reaction_footing_y / (B c) over the settlements 0.0075 B to 0.0175 B, as tests/verification/test_strip_footing.cpp
measures it.

Usage (after building): /usr/bin/python3 scripts/strip-footing.py [--mpm build/bin/mpm]
Needs Debian's python3-matplotlib. The runs go to out/strip-footing/ (about 2 s, 15 s and 2 minutes on two cores).
"""
import argparse
import csv
import math
import pathlib
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENE = ROOT / "examples/geomechanics/strip-footing.toml"
B, C, V, RAMP = 1.0, 10e3, 0.05, 0.1  # the scene's constants
PRANDTL = 2 + math.pi


def settlement(t):
    return V * (t * t / (2 * RAMP) if t < RAMP else RAMP / 2 + t - RAMP)


def curve(mpm, cells, out):
    subprocess.run([mpm, "run", str(SCENE), "--quiet", "--out", str(out), "--set", f"grid.cells={cells}"],
                   check=True, stdout=subprocess.DEVNULL)
    rows = list(csv.DictReader(open(out / "history.csv")))
    s = [settlement(float(r["time"])) / B for r in rows]
    q = [-2 * float(r["reaction_footing_y"]) / (B * C) for r in rows]
    return s, q


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mpm", default=str(ROOT / "build/bin/mpm"))
    args = parser.parse_args()
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for label, cells in (("B/20", "[40,26]"), ("B/40", "[80,52]"), ("B/80", "[160,104]")):
        s, q = curve(args.mpm, cells, ROOT / "out/strip-footing" / label.replace("/", "_"))
        plateau = [qi for si, qi in zip(s, q) if 0.0075 <= si <= 0.0175]
        limit = sum(plateau) / len(plateau)
        print(f"h = {label}: limit pressure {limit:.4f} c ({100 * (limit / PRANDTL - 1):+.2f}% against Prandtl)")
        ax.plot(s, q, lw=1.2, label=f"h = {label}: {limit:.2f} c")
    ax.axhline(PRANDTL, color="k", ls="--", lw=1, label="Prandtl (2 + pi) c")
    ax.set_xlabel("settlement / B")
    ax.set_ylabel("footing pressure / c")
    ax.set_ylim(0, 6)
    ax.legend(loc="lower right")
    ax.set_title("Rough strip footing on Tresca clay (Drucker-Prager, phi = 0)")
    fig.tight_layout()
    out = ROOT / "docs/geomechanics/strip-footing.png"
    out.parent.mkdir(exist_ok=True)
    fig.savefig(out, dpi=100)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
