#!/usr/bin/env python3
"""Write particles.csv: the quarter ring 0.5 <= R <= 1, X, Y >= 0, seeded exactly as
`mpm verify expanding-ring` seeds it (include/mpm/verification/expanding_ring.hpp, ExpandingRing::seed):
a lattice of spacing h/ppc filling [0, 1]^2, one particle at the centre of each sub-cell, x fastest, kept
when its centre lies in the ring.

Usage: python3 make_particles.py [CELLS [PPC [FILE]]]
(default: 32 cells across R_O = 1, 2 particles per cell per axis, FILE = particles.csv next to this script)

The scene's own shape = "ring" cannot model the quarter ring: the reader requires the whole ring
(centre +- radius) to lie inside the grid, and the grid of the quarter model starts at the symmetry planes.
"""
import math
import os
import sys

cells = int(sys.argv[1]) if len(sys.argv) > 1 else 32
ppc = int(sys.argv[2]) if len(sys.argv) > 2 else 2
R_I, R_O = 0.5, 1.0
h = R_O / cells
s = h / ppc
n = math.floor(R_O / s + 1e-9)  # as fill_box counts the lattice
out = sys.argv[3] if len(sys.argv) > 3 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "particles.csv")
with open(out, "w") as f:
    f.write("x,y,volume\n")
    kept = 0
    for j in range(n):
        y = (j + 0.5) * s
        for i in range(n):
            x = (i + 0.5) * s
            R = math.sqrt(x * x + y * y)  # as Eigen norm() computes it
            if R_I <= R <= R_O:
                f.write(f"{x!r},{y!r},{s * s!r}\n")
                kept += 1
print(f"{out}: {kept} particles, spacing {s!r}")
