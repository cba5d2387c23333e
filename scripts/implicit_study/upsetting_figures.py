"""The figures of the upsetting section: load against deflection, the equivalent plastic strain by mesh and the
final shapes by time step."""
import math

import matplotlib.pyplot as plt
import numpy as np

from mpm_output import read_vtp

from .figures import save
from .paper import PAPER_LOAD_KN


def load_figure(curves, references, title, name):
    """Load on the platen against deflection: curves [(deflection mm, load kN, label)], and horizontal lines at the
    paper's loads, references [(load kN, line style, line width, label)]."""
    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    for x, load, label in curves:
        ax.plot(x, load, lw=1, label=label)
    for load, style, width, label in references:
        ax.axhline(load, color="gray", ls=style, lw=width, label=label)
    ax.set_ylim(bottom=min(0, ax.get_ylim()[0]), top=max(ax.get_ylim()[1], 1.08 * PAPER_LOAD_KN))
    ax.set_xlabel("deflection (mm)")
    ax.set_ylabel("load on the platen (kN)")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save(fig, name)


def plastic_strain_figure(done):
    """Equivalent plastic strain in the last frame of each finished run [(run, h mm)], one colour scale."""
    states = [(r, h, r.last_frame()) for r, h in done]
    vmax = max(float(s["plastic_strain"].max()) for _, _, s in states)
    fig, axes = plt.subplots(1, len(states), figsize=(3.3 * len(states) + 1.2, 2.8), squeeze=False,
                             layout="constrained")
    for ax, (r, h, s) in zip(axes[0], states):
        p = s["points"] * 1e3
        sc = ax.scatter(p[:, 0], p[:, 1], c=s["plastic_strain"], s=14 * h ** 2, vmin=0, vmax=vmax, cmap="jet",
                        linewidths=0)
        ax.set_aspect("equal")
        ax.set_xlim(0, 20)
        ax.set_ylim(0, 8)
        ax.set_title(f"h = {h} mm ({r.name}), max {s['plastic_strain'].max():.2f}", fontsize=8)
        ax.set_xlabel("r (mm)")
    axes[0, 0].set_ylabel("z (mm)")
    fig.colorbar(sc, ax=list(axes[0]), label="equiv. plastic strain", shrink=0.9)
    fig.suptitle("Upsetting at 60%, step 1000x the coarse explicit step (paper Fig. 11)", fontsize=9)
    return save(fig, "upsetting_plastic_strain.png")


def shapes_figure(shown):
    """The particles in the first frame of the first finished run and the last frame of each, with the platen."""
    panels = [("initial", read_vtp(shown[0].frames()[0][1]), 0.0)] + \
             [(f"{r.name} ({r.target_dt:.2g} s)", r.last_frame(), r.summary["time"]) for r in shown]
    ncol = min(4, len(panels))
    nrow = math.ceil(len(panels) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(2.6 * ncol, 2.5 * nrow + 0.3), squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    for ax, (title, s, t) in zip(axes.flat, panels):
        p = s["points"] * 1e3
        ax.plot(p[:, 0], p[:, 1], ".", ms=2, color="k")
        ax.axhline(15.0 - 1.0 * t * 1e3, color="tab:red", lw=1)   # the platen's face
        ax.set_xticks(np.arange(0, 25, 1), minor=True)
        ax.set_yticks(np.arange(0, 19, 1), minor=True)
        ax.grid(which="minor", lw=0.3, color="0.85")
        ax.set_aspect("equal")
        ax.set_xlim(0, 20)
        ax.set_ylim(0, 16)
        ax.tick_params(labelsize=6)
        ax.set_title(title + (f", r = {p[:, 0].max():.2f} mm" if t > 0 else ""), fontsize=7)
    fig.suptitle("Upsetting: particles at 60% reduction by time step (paper Fig. 10), mm; red: platen",
                 fontsize=9)
    fig.tight_layout()
    return save(fig, "upsetting_shapes.png")
