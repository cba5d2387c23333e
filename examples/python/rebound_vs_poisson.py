#!/usr/bin/env python3
"""A parameter study from Python: an elastic block dropped on a floor (examples/block-on-floor), its rebound and the
floor's peak force against Poisson's ratio. Six runs to t = 0.6 s, about 10 s in all on two cores.

    PYTHONPATH=build/python python3 examples/python/rebound_vs_poisson.py [--out rebound.png]

Writes the plot (rebound.png: the block's centre height against time for each ratio, and the rebound and peak
floor force against the ratio) and prints the table.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import mpm

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "block-on-floor", "scene.toml")
DROP = 0.1  # the block's bottom starts 0.1 m above the floor
LANDING = np.sqrt(2 * DROP / 9.81)  # the free fall's end, t = 0.143 s
REST = 0.1  # the centre's height when the block rests on the floor (its half height, neglecting its sag)


def drop(nu, end_time=0.6, every=0.002):
    """The block's centre height [m] and the floor's vertical force [N/m] every `every` seconds."""
    scene = mpm.Scene.from_toml(SCENE, overrides={"materials.0.nu": nu, "simulation.end_time": end_time})
    sim = mpm.Simulation(scene)
    mass = sim.particles["mass"]
    times, heights, forces = [], [], []

    def record(s):
        times.append(s.time)
        heights.append(np.dot(mass, s.particles["x"][:, 1]) / mass.sum())
        forces.append(s.reactions["y-min"][1])

    record(sim)
    sim.run(every=every, callback=record)
    return np.array(times), np.array(heights), np.array(forces)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="rebound.png", help="the plot to write (PNG)")
    parser.add_argument("--ratios", default="0,0.1,0.2,0.3,0.4,0.45", help="Poisson's ratios, comma-separated")
    args = parser.parse_args()
    ratios = [float(v) for v in args.ratios.split(",")]

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    rebounds, peaks = [], []
    print(f"{'nu':>6} {'rebound':>10} {'peak force':>12}")
    for nu in ratios:
        t, h, f = drop(nu)
        # The highest point of the centre within 0.25 s of the landing, above its height resting on the floor (its
        # half height, 0.1 m), as a fraction of the drop.
        window = (t > LANDING) & (t < LANDING + 0.25)
        rebound = (h[window].max() - REST) / DROP
        rebounds.append(rebound)
        peaks.append(f.max())
        print(f"{nu:6.2f} {rebound:10.3f} {f.max():12.1f}")
        left.plot(t, h, label=f"nu = {nu:g}")
    left.axvline(LANDING, color="0.6", lw=0.8, ls="--")
    left.set(xlabel="time [s]", ylabel="centre height [m]", title="block dropped 0.1 m onto a fixed floor")
    left.legend(fontsize=8)
    right.plot(ratios, rebounds, "o-", color="C0")
    right.set(xlabel="Poisson's ratio", ylabel="rebound height / drop height", title="rebound and peak floor force")
    twin = right.twinx()
    twin.plot(ratios, peaks, "s--", color="C3")
    twin.set_ylabel("peak floor force [N/m]", color="C3")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
