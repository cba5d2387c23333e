#!/usr/bin/env python3
"""Draw docs/geomechanics/absorbing-column.png and docs/geomechanics/vertical-cut.png from runs of the real engine:
the energy in the 1-D column of examples/geomechanics/absorbing-column.toml as its P-wave pulse reaches an
absorbing face (explicit and implicit) or a free one, and the crest displacement of the vertical cut of
examples/geomechanics/vertical-cut.toml against time for cohesions from 80 kPa (it stands) to 40 kPa (it fails).

Usage (after building): /usr/bin/python3 scripts/geomechanics-plots.py [--mpm build/bin/mpm]
Needs Debian's python3-matplotlib. The runs go to out/geomechanics-plots/ (about 3 minutes on two cores).
"""
import argparse
import pathlib
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from mpm_output import read_history, read_pvd, read_vtp  # noqa: E402

OUT = ROOT / "out/geomechanics-plots"
FIGURES = ROOT / "docs/geomechanics"


def run(mpm, scene, out, *sets):
    args = [mpm, "run", str(ROOT / "examples/geomechanics" / scene), "--quiet", "--out", str(out)]
    for s in sets:
        args += ["--set", s]
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
    return out


def absorbing_column(mpm):
    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    for label, sets in (("absorbing, USL", ()), ("free, USL", ('grid.faces.x-max="free"',)),
                        ("absorbing, implicit", ('simulation.integrator="implicit"',)),
                        ("free, implicit", ('simulation.integrator="implicit"', 'grid.faces.x-max="free"'))):
        h = read_history(run(mpm, "absorbing-column.toml", OUT / label.replace(", ", "_"), *sets) / "history.csv")
        incident = h["total_energy"][h["time"] <= 0.1][-1]
        ax.plot(h["time"], h["total_energy"] / incident, lw=1.2, label=label)
        print(f"absorbing column, {label}: {h['total_energy'][-1] / incident:.4f} of the incident energy left")
    ax.axvline(0.545, color="k", ls=":", lw=1)
    ax.text(0.55, 0.5, "pulse reaches x-max", fontsize=8)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("energy in the column / incident")
    ax.set_title("P-wave pulse into an absorbing face (Lysmer & Kuhlemeyer 1969)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIGURES / "absorbing-column.png", dpi=110)


def crest_displacement(out):
    """(times, |u| of the particle seeded nearest the cut's top edge (15 m, 20 m)) over the frames."""
    times, sizes = [], []
    for t, frame in read_pvd(out / "particles.pvd"):
        d = read_vtp(frame)
        X = d["points"][:, :2] - d["displacement"][:, :2]
        k = np.argmin(np.hypot(X[:, 0] - 15, X[:, 1] - 20))
        times.append(t)
        sizes.append(np.hypot(*d["displacement"][k, :2]))
    return times, sizes


def vertical_cut(mpm):
    fig, ax = plt.subplots(figsize=(6.4, 3.8))
    for c in (80e3, 60e3, 45e3, 40e3):
        out = run(mpm, "vertical-cut.toml", OUT / f"cut_{int(c / 1e3)}kPa", f"constants.c={c}", "output.every=0.25")
        t, u = crest_displacement(out)
        ax.plot(t, u, "o-", ms=3, lw=1.2, label=f"c = {c / 1e3:.0f} kPa (safety factor {c / 52e3:.2f})")
        print(f"vertical cut, c = {c / 1e3:.0f} kPa: crest displacement {u[-1]:.3f} m at t = {t[-1]:.2f} s")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("crest displacement [m]")
    ax.set_yscale("log")
    ax.set_title("Vertical cut H = 10 m in Tresca clay, critical c = gamma H / 3.77 = 52 kPa", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(FIGURES / "vertical-cut.png", dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mpm", default=str(ROOT / "build/bin/mpm"))
    args = parser.parse_args()
    FIGURES.mkdir(exist_ok=True)
    absorbing_column(args.mpm)
    vertical_cut(args.mpm)
    print(f"wrote {FIGURES / 'absorbing-column.png'} and {FIGURES / 'vertical-cut.png'}")


if __name__ == "__main__":
    main()
