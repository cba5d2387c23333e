"""What the elastic and the elastic-plastic bar share: the bar's data, its runs, the final stress of the
particles against the analytic uniaxial stress, and the figure of sigma_xx along the bar."""
import matplotlib.pyplot as plt
import numpy as np

from mpm_output import read_vtp

from .figures import save
from .report import num, pct
from .runs import EXPLICIT, Run

# Bar data (Sec. 3.1.1): rigid body speed v, strained length l, E, nu, initial height.
BAR_V, BAR_L, BAR_E, BAR_NU, BAR_HEIGHT = 0.001, 0.3, 1000.0, 0.3, 0.3
FOOT = {1: "a", 10: "b", 100: "c"}   # the paper's footnotes: first step 1, 10 or 100 x the explicit step


def bar_runs(problem, scene):
    """The explicit run and the paper's six implicit runs (1x a to 100x c) of one bar."""
    runs = [Run(problem, "explicit", scene, EXPLICIT)]
    for s, f in [(1, 1), (1, 10), (10, 10), (1, 100), (10, 100), (100, 100)]:
        name = f"{f}x {FOOT[s]}"
        runs.append(Run(problem, name, scene, [f"implicit.step_factor={f}", f"implicit.start_factor={s}"]))
    return runs


def cg_runs(problem, scene):
    """The paper's Newton-CG runs of one bar (Tables 1 and 3): the velocity formulation and the unscaled residual
    (Sec. 3.2.2: only its Newton-GMRES runs use the dimensionless form), with the scene's tolerances."""
    common = ["implicit.solver=newton-cg", "implicit.formulation=velocity", "implicit.residual=unscaled"]
    return [Run(problem, f"CG {f}x {FOOT[s]}", scene, common + [f"implicit.step_factor={f}", f"implicit.start_factor={s}"])
            for s, f in [(1, 1), (1, 10), (10, 10), (1, 100), (10, 100), (100, 100)]]


def final_sigma(run):
    """(mean, max |deviation|) of sigma_xx over the particles in the last frame."""
    if not run.ok:
        return None, None
    sxx = run.last_frame()["stress"][:, 0]
    return float(sxx.mean()), float(np.abs(sxx - sxx.mean()).max())


def reaction_stress(run):
    """The puller's reaction at the last step over the bar's initial height (a nominal stress)."""
    return -float(run.history()["reaction_puller_x"][-1]) / BAR_HEIGHT


def sigma_rows(runs, analytic):
    rows = []
    for r in runs:
        if not r.ok:
            rows.append([r.name, r.status] + ["–"] * 5)
            continue
        mean, dev = final_sigma(r)
        a = analytic(r.summary["time"])
        rows.append([r.name, num(r.summary["time"], ".4g"), num(mean, ".4g"), num(dev, ".2g"), num(a, ".4g"),
                     pct(mean, a), num(reaction_stress(r), ".4g")])
    return rows


SIGMA_HEAD = ["run", "final t", "sigma_xx mean", "max abs(sigma_xx - mean)", "analytic", "error of mean",
              "puller reaction / 0.3 (nominal)"]


def stress_figure(run, analytic, title, name):
    fig, ax = plt.subplots(figsize=(6.0, 3.8))
    frames = run.frames()
    cmap = plt.get_cmap("viridis")
    tmax = frames[-1][0]
    for t, path in frames[1:]:
        d = read_vtp(path)
        x, sxx = d["points"][:, 0], d["stress"][:, 0]
        c = cmap(t / tmax)
        ax.plot(x, sxx, "o", ms=3.5, color=c, mfc="none")
        ax.hlines(analytic(t), x.min(), x.max(), colors=[c], linestyles="--", lw=0.8)
        ax.annotate(f"t={t:.3g}", (x.max(), analytic(t)), xytext=(3, 0), textcoords="offset points", fontsize=6,
                    va="center")
    ax.set_xlabel("x of the particle")
    ax.set_ylabel("sigma_xx of the particle")
    ax.set_title(title, fontsize=9)
    ax.plot([], [], "o", mfc="none", color="gray", label="particles (each frame)")
    ax.plot([], [], "--", color="gray", label="analytic")
    ax.legend(fontsize=7, loc="upper left")
    ax.margins(x=0.12)
    fig.tight_layout()
    return save(fig, name)
