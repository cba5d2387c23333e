#!/usr/bin/python3
"""Plot the kinetic, strain and total energy of an `mpm run` against time from its history.csv.

Usage: /usr/bin/python3 plot_energy.py OUT/history.csv PICTURE.png [TITLE] [--mark TIME:LABEL ...]
--mark draws a dashed vertical line at TIME with LABEL in the legend.
Needs matplotlib (Debian: apt-get install python3-matplotlib).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

args, marks = [], []
argv = sys.argv[1:]
while argv:
    a = argv.pop(0)
    if a == "--mark" and argv:
        time, _, label = argv.pop(0).partition(":")
        marks.append((float(time), label))
    else:
        args.append(a)
if len(args) < 2:
    sys.exit(__doc__)
with open(args[0], newline="") as f:
    rows = list(csv.DictReader(f))
t = [float(r["time"]) for r in rows]
fig, ax = plt.subplots(figsize=(6, 3.6))
for key, label in (("kinetic_energy", "kinetic"), ("internal_energy", "strain"), ("total_energy", "total")):
    ax.plot(t, [float(r[key]) for r in rows], label=label)
for (time, label), style in zip(marks, (":", "--", "-.")):
    ax.axvline(time, color="gray", linestyle=style, linewidth=1, label=label)
ax.set_xlabel("time [s]")
ax.set_ylabel("energy [J per m of thickness]")
ax.set_title(args[2] if len(args) > 2 else args[0])
ax.set_ylim(bottom=0)
ax.grid(alpha=0.3)
ax.legend(loc="center right", fontsize="small")
fig.tight_layout()
fig.savefig(args[1], dpi=100)
print(args[1])
