"""The residual histories of Sulsky & Kaul 2004, Figs 5 and 9b-d, from the runs' newton.csv (output.newton_log=on):
Fig. 5, ||F|| at each Newton iterate of the elastic-plastic bar's steps that need two or more iterations, for each
derivative step h; Fig. 9, the first step of the upsetting at 10000x with and without the line search (the bar,
the paper's Fig. 9 problem, never needs it here)."""
import matplotlib.pyplot as plt
import numpy as np

from mpm_output import read_vtp

from .figures import save
from .paths import SCENES
from .runs import Run

FIG5_H = ["1e-7", "1e-6", "1e-5", "1e-4", "1e-3", "1e-2"]
LOG = ["output.newton_log=on"]


def fig5_runs():
    scene = SCENES / "plastic-bar.toml"
    return {h: Run("parameters", f"1x t=100 gamma=1e-12 eps=1e-4 h={h}", scene,
                   ["simulation.end_time=100", "implicit.linear_tolerance=1e-12", "implicit.newton_tolerance=1e-4",
                    f"implicit.derivative_step={h}", "implicit.step_factor=1", "implicit.start_factor=1",
                    "implicit.restart=200", "implicit.max_krylov=2000"] + LOG) for h in FIG5_H}


def fig9_runs():
    scene = SCENES / "upsetting.toml"
    return {ls: Run("parameters", f"upsetting 10000x first steps, line search {ls}", scene,
                    ["implicit.step_factor=10000", "implicit.start_factor=10000", f'implicit.line_search="{ls}"',
                     "simulation.end_time=1e-3"] + LOG) for ls in ("on", "off")}


def grouped(run):
    """{step: {attempt: (dt, [||F_0||, ||F_1||, ...])}} from newton.csv, whose rows come in iteration order."""
    log = run.newton_log()
    out = {}
    for step, attempt, dt, norm in zip(log["step"].astype(int), log["attempt"].astype(int), log["dt"],
                                       log["residual_norm"]):
        out.setdefault(step, {}).setdefault(attempt, (float(dt), []))[1].append(norm)
    return out


def converged_norms(run):
    """{step: ||F|| at each iterate of its last try, the one that converged}."""
    return {step: t[max(t)][1] for step, t in grouped(run).items()}


def quadratic_constant(norms):
    """The largest ||F_(n+1)|| / ||F_n||^2 over a step's iterates."""
    return max(norms[k + 1] / norms[k] ** 2 for k in range(len(norms) - 1))


def fig5(runs):
    """Fig. 5: one panel per h, the steps that need two or more Newton iterations in every run, and the quadratic
    ||F_(n+1)|| = C ||F_n||^2 dotted, C the largest of the panel's steps. Returns the figure and a line per h: steps drawn, largest and median C."""
    norms = {h: converged_norms(r) for h, r in runs.items() if r.ok}
    if len(norms) < len(runs):
        return None, ["- Fig. 5: " + ", ".join(f"h = {h}: {r.status}" for h, r in runs.items() if not r.ok)]
    common = sorted(set.intersection(*[{s for s, n in v.items() if len(n) >= 3} for v in norms.values()]))
    if not common:
        return None, ["- Fig. 5: no step needs two or more Newton iterations in every run."]
    fig, axes = plt.subplots(2, 3, figsize=(12, 7), sharey=True)
    lines = []
    for ax, h, letter in zip(axes.flat, FIG5_H, "abcdef"):
        multi = {s: n for s, n in norms[h].items() if len(n) >= 3}
        drawn = [quadratic_constant(norms[h][s]) for s in common]
        for s in common:
            ax.semilogy(range(len(norms[h][s])), norms[h][s], "-*", markersize=4, linewidth=0.8)
        cs = [quadratic_constant(n) for n in multi.values()]
        quad = [max(norms[h][s][0] for s in common)]
        while quad[-1] > 1e-13 and len(quad) < 4:
            quad.append(max(drawn) * quad[-1] ** 2)
        ax.semilogy(range(len(quad)), quad, "k:", linewidth=1)
        ax.set_ylim(1e-14, 10)
        ax.set_xticks(range(max(len(norms[h][s]) for s in common) + 1))
        ax.set_title(f"({letter}) h = {h}: C = {max(drawn):.3g}")
        ax.set_xlabel("Newton iteration")
        lines.append(f"- h = {h}: {len(multi)} steps need two or more iterations; ||F_(n+1)|| <= C ||F_n||^2 with "
                     f"C at most {max(cs):.3g} (median {np.median(cs):.3g}).")
    for ax in axes[:, 0]:
        ax.set_ylabel("||F|| (scaled)")
    fig.suptitle(f"Elastic-plastic bar to t = 100 at the explicit step, gamma = 1e-12, epsilon = 1e-4 (paper Fig. 5):\n"
                 f"the {len(common)} steps needing two or more Newton iterations for every h; dotted: ||F_(n+1)|| = "
                 "C ||F_n||^2, C the panel's largest")
    fig.tight_layout()
    return save(fig, "residuals_fig5.png"), lines


def crossings_line(run):
    """When the bar's steps need a second Newton iteration, beside when its particles cross into new cells: a
    column of the bar (from its frames, every 2 s) or a particle row of the puller (x = 0.325 and 0.375 at t = 0,
    moving at -0.001, so crossing x = 0.3 at t = 25 and 75)."""
    log, times = run.newton_log(), run.history()["time"]
    multi = sorted({int(s) for s, k in zip(log["step"], log["iteration"]) if k >= 2})
    most = int(max(log["iteration"]))
    clusters = []
    for s in multi:
        if not clusters or times[s] - clusters[-1][-1] > 1:
            clusters.append([])
        clusters[-1].append(times[s])
    frames = run.frames()
    columns = []
    for (t0, f0), (t1, f1) in zip(frames, frames[1:]):
        moved = np.floor(read_vtp(f1)["points"][:, 0] / 0.1 + 1e-12) != np.floor(read_vtp(f0)["points"][:, 0] / 0.1 + 1e-12)
        if moved.any():
            columns.append(f"{t0:.1f} < t < {t1:.1f} ({int(moved.sum())} particles)")
    return ("- Where the bar needs a second Newton iteration (Fig. 5's run at h = 1e-5): " + ", ".join(
        f"{len(c)} steps at t = {c[0]:.2f}" + (f" to {c[-1]:.2f}" if len(c) > 1 else "") for c in clusters)
        + ". A column of the bar crosses into a new cell at " + ", ".join(columns) + ", and the puller's particle "
        "rows enter new cells at t = 25 and 75: these are the events the paper names for its Fig. 9 steps (\"the "
        "first row of the bar crosses into a new element\", \"the last row of the rigid body moves into a new "
        f"element\"), which cost it 46 and 15 Newton iterations without the line search and cost ours at most {most}.")


def fig9(runs):
    """Fig. 9b-d: ||F|| at each Newton iterate of the upsetting's first step at 10000x, every try, with and without
    the line search. Returns the figure and a line per run."""
    if not all(r.has_output for r in runs.values()):
        return None, ["- Fig. 9: " + ", ".join(f"line search {k}: {r.status}" for k, r in runs.items())]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5), sharey=True)
    lines = []
    for ax, (ls, r) in zip(axes, runs.items()):
        step1 = grouped(r)[1]
        tries = sorted(step1)  # a try that failed before its Newton solve began logs no rows
        dt0 = step1[tries[0]][0] * 2 ** tries[0]  # each try halves the step of the one before
        for a, (dt, n) in step1.items():
            ax.semilogy(range(len(n)), n, "-*", markersize=3, linewidth=0.8, label=f"try {a}: dt = dt_0 / {dt0 / dt:.0f}")
        ax.axhline(1e-4, color="k", linestyle=":", linewidth=1)
        ax.set_title(f"line search {ls}")
        ax.set_xlabel("Newton iteration")
        ax.legend(fontsize=8)
        final = step1[tries[-1]]
        if tries == [0]:
            lines.append(f"- Line search {ls}: the first step converges at dt_0 in {len(final[1]) - 1} Newton iterations.")
        else:
            earlier = [step1[a] for a in tries[:-1]]
            stall = [float(np.median(n[-10:])) for _, n in earlier]
            iterations = "/".join(sorted({str(len(n) - 1) for _, n in earlier}))
            lines.append(f"- Line search {ls}: the first step takes {tries[-1] + 1} tries; the tries at dt_0 to dt_0 / "
                         f"{dt0 / earlier[-1][0]:.0f} stop after {iterations} Newton iterations "
                         f"without reaching newton_tolerance = 1e-4, the residual stalling at {min(stall):.2g} to "
                         f"{max(stall):.2g} over their last 10; "
                         f"the last, at dt_0 / {dt0 / final[0]:.0f}, converges in {len(final[1]) - 1}.")
    axes[0].set_ylabel("||F|| (scaled)")
    fig.suptitle("Upsetting at 10000 x the explicit step, first step: Newton residuals of every try (paper Fig. 9b-d); "
                 "dotted: newton_tolerance")
    fig.tight_layout()
    return save(fig, "residuals_fig9.png"), lines


def residual_histories(args):
    """The runs, the two figures and their lines of text."""
    f5, f9 = fig5_runs(), fig9_runs()
    for r in list(f5.values()) + list(f9.values()):
        r.execute(args, 1)
    (fig5_path, fig5_lines), (fig9_path, fig9_lines) = fig5(f5), fig9(f9)
    if f5["1e-5"].ok:
        fig9_lines.append(crossings_line(f5["1e-5"]))
    return fig5_path, fig5_lines, fig9_path, fig9_lines
