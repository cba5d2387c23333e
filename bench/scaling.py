#!/usr/bin/env python3
"""Throughput and memory of `mpm bench` against the particle count (docs/performance.md, "Scaling with size").

Usage: bench/scaling.py MPM [--threads 2] [--sizes 1e4 1e5 1e6 1e7] [--plot FILE.png] [--json FILE]

Runs the reference block in 2-D and 3-D with the linear and cpGIMP kernels at each size, 5 runs each (the
bench's median), with fewer steps at larger sizes so that a run takes about the same time. Prints a Markdown
table: particle-steps/s, particle-node interactions/s, the simulation's own bytes per particle and the peak
resident memory of the process net of a 100-particle run, per particle.
"""
import argparse
import json
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

NODES = {"linear": 2, "cpgimp": 3}  # stencil nodes per axis


def bench(mpm, threads, dim, kernel, particles, steps, repeat):
    out = subprocess.run([mpm, "bench", "--json", "--dim", str(dim), "--kernel", kernel, "--particles",
                          str(particles), "--steps", str(steps), "--repeat", str(repeat), "--threads", str(threads)],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mpm")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sizes", type=float, nargs="+", default=[1e4, 1e5, 1e6, 1e7])
    ap.add_argument("--plot")
    ap.add_argument("--json")
    a = ap.parse_args()
    rows = []
    print("| dim | kernel | particles | steps | M particle-steps/s | M interactions/s | B/particle (count) "
          "| B/particle (resident, net) |")
    print("|---|---|---|---|---|---|---|---|")
    for dim in (2, 3):
        for kernel in ("linear", "cpgimp"):
            tiny = bench(a.mpm, a.threads, dim, kernel, 100, 1, 1)["peak_resident_bytes"]
            for size in a.sizes:
                n = int(size)
                work = 2e7 if dim == 2 else 6e6  # particle-steps per run, about a second
                steps = int(min(200, max(5, round(work / n * (1 if kernel == "linear" else 0.4)))))
                r = bench(a.mpm, a.threads, dim, kernel, n, steps, 5)
                rate = r["particle_steps_per_second"]
                inter = rate * NODES[kernel] ** dim
                net = (r["peak_resident_bytes"] - tiny) / r["particles"]
                rows.append({**r, "interactions_per_second": inter, "resident_bytes_per_particle": net})
                print(f"| {dim} | {kernel} | {r['particles']:,} | {steps} | {rate / 1e6:.1f} | {inter / 1e6:.0f} "
                      f"| {r['bytes_per_particle']:.0f} | {net:.0f} |", flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)
    if a.plot:
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        for dim in (2, 3):
            for kernel in ("linear", "cpgimp"):
                sel = [r for r in rows if r["dim"] == dim and r["kernel"] == kernel]
                x = [r["particles"] for r in sel]
                style = "-o" if dim == 2 else "--s"
                ax[0].plot(x, [r["interactions_per_second"] / 1e6 for r in sel], style, label=f"{dim}-D {kernel}")
                ax[1].plot(x, [r["resident_bytes_per_particle"] for r in sel], style, label=f"{dim}-D {kernel}")
        ax[0].set_ylabel("M particle-node interactions / s")
        ax[1].set_ylabel("resident bytes / particle (net of a tiny run)")
        for axis in ax:
            axis.set_xscale("log")
            axis.set_xlabel("particles")
            axis.grid(True, which="both", alpha=0.3)
            axis.legend()
        ax[0].set_ylim(bottom=0)
        ax[1].set_ylim(bottom=0)
        fig.suptitle(f"mpm bench, reference block, {a.threads} threads")
        fig.tight_layout()
        fig.savefig(a.plot, dpi=90)


if __name__ == "__main__":
    main()
