"""Saving the study's figures into docs/implicit/."""
import matplotlib.pyplot as plt

from .paths import FIGS
from .progress import log

DPI = 100


def save(fig, name):
    path = FIGS / name
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    log(f"wrote docs/implicit/{name} ({path.stat().st_size // 1024} KB)")
    return f"implicit/{name}"
