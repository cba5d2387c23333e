#!/usr/bin/env python3
"""Draw docs/contact/inclined-block.png: the acceleration of examples/contact/inclined-block.toml along its plane
(theta = 30 degrees) for friction coefficients 0 to 0.8, measured by the real engine, against the Coulomb line
g (sin theta - mu cos theta) (zero from mu = tan theta on, where the block sticks); and the same block on the stiff
elastic plate of examples/contact/block-on-plate.toml (contact between two bodies).

Usage (after building): /usr/bin/python3 scripts/contact-inclined-block.py [--mpm build/bin/mpm]
Needs Debian's python3-matplotlib. The runs go to out/contact-inclined-block/ (about 0.4 s each on one core for the
wall, 8 s for the plate, whose stiffness takes a 12 times smaller step).
The acceleration is measured as tests/regression/test_contact_walls.cpp measures it: the change of momentum over
mass and time after the load's ramp (t >= 0.15 s).
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
SCENE = ROOT / "examples/contact/inclined-block.toml"
PLATE = ROOT / "examples/contact/block-on-plate.toml"
MASS = 1000 * 0.4 * 0.2  # [kg/m]
G, THETA = 9.81, math.radians(30)


def measured(mpm, mu, out, scene=SCENE):
    subprocess.run([mpm, "run", str(scene), "--quiet", "--out", str(out), "--set", f"constants.mu={mu}"],
                   check=True, stdout=subprocess.DEVNULL)
    rows = list(csv.DictReader(open(out / "history.csv")))
    after = [r for r in rows if float(r["time"]) >= 0.15]
    t0, p0 = float(after[0]["time"]), float(after[0]["momentum_x"])
    t1, p1 = float(after[-1]["time"]), float(after[-1]["momentum_x"])
    return (p1 - p0) / MASS / (t1 - t0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mpm", default=str(ROOT / "build/bin/mpm"))
    args = parser.parse_args()
    mus = [0.1 * k for k in range(9)]
    a = [measured(args.mpm, mu, ROOT / f"out/contact-inclined-block/mu{mu:.1f}") for mu in mus]
    on_plate = [measured(args.mpm, mu, ROOT / f"out/contact-inclined-block/plate-mu{mu:.1f}", PLATE) for mu in mus]
    line = [k / 100 for k in range(81)]
    fig, ax = plt.subplots(figsize=(5.5, 3.6))
    ax.plot(line, [max(G * (math.sin(THETA) - mu * math.cos(THETA)), 0) for mu in line], "-", color="0.3",
            label="Coulomb: g (sin θ − μ cos θ), 0 beyond tan θ")
    ax.plot(mus, a, "o", color="C0", label="mpm, on a Coulomb wall")
    ax.plot(mus, on_plate, "x", color="C3", ms=8, label="mpm, on a stiff elastic plate ([[contact]])")
    ax.axvline(math.tan(THETA), color="0.7", ls=":", lw=1)
    ax.set_xlabel("friction coefficient μ")
    ax.set_ylabel("acceleration along the plane [m/s²]")
    ax.set_title("Block on a plane inclined by 30°")
    ax.legend(frameon=False)
    fig.tight_layout()
    fig.savefig(ROOT / "docs/contact/inclined-block.png", dpi=110)
    for mu, value, plate in zip(mus, a, on_plate):
        exact = max(G * (math.sin(THETA) - mu * math.cos(THETA)), 0)
        print(f"mu {mu:.1f}: wall {value:.4f} m/s^2, plate {plate:.4f} m/s^2, Coulomb {exact:.4f}")


if __name__ == "__main__":
    main()
