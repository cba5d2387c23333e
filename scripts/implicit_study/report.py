"""Formatting shared by the sections of docs/implicit.md: numbers, percentages, markdown tables, the cost table's
rows and the bullets that compare runs with the paper's table."""
import math


def esc(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def num(x, spec=".3g"):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    return format(x, spec)


def pct(ours, ref):
    if ours is None or ref in (None, 0) or not math.isfinite(ours):
        return "–"
    return f"{(ours / ref - 1) * 100:+.1f}%"


def md_table(head, rows):
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)


def ratios(run, ex):
    """(time ratio, eval ratio) of run against the explicit run ex; None where unavailable."""
    if not run.ok or ex is None or not ex.ok:
        return None, None
    return run.compute / ex.compute, run.evals / ex.steps


def paper_cell(p):
    if p is None:
        return "–"
    dt, steps, newton, krylov, ratio = p
    parts = [f"{dt:.4g}", str(steps), "–" if newton is None else str(newton), "–" if krylov is None else str(krylov),
             f"{ratio:.4g}"]
    return " / ".join(parts)


def cost_rows(runs, ex, paper):
    """Rows of a cost table: run, step, steps, Newton, Krylov, evals, [backtracks, retries], s, ratios, paper."""
    rows = []
    for r in runs:
        p = paper.get(r.name) if paper else None
        if r.status == "skipped":
            rows.append([r.name, f"skipped ({esc(r.skip_reason)})"] + ["–"] * 7 + ([paper_cell(p)] if paper else []))
            continue
        if not r.ok:
            rows.append([r.name, f"**{r.status}**: {esc(r.failure)}"] + ["–"] * 7 + ([paper_cell(p)] if paper else []))
            continue
        tr, er = ratios(r, ex)
        rows.append([r.name, num(r.target_dt, ".4g"), r.steps, r.imp("newton_iterations"), r.imp("krylov_iterations"),
                     r.evals, num(r.compute, ".3g"), num(tr, ".3f"), num(er, ".3f")] + ([paper_cell(p)] if paper else []))
    return rows


COST_HEAD = ["run", "time step", "steps", "Newton", "GMRES", "evaluation units", "compute s", "cost ratio (time)",
             "cost ratio (evals)"]
PAPER_HEAD = "paper: step / steps / Newton / GMRES / cost ratio"


def diff_lines(runs, ex, paper):
    """Measured differences against the paper, one bullet per run that has a paper row."""
    out = []
    for r in runs:
        p = paper.get(r.name)
        if r.name == "explicit":   # each section states the explicit step on its own line
            continue
        if p is None or not r.ok:
            if p is not None and r.status in ("failed", "timeout"):
                out.append(f"- {r.name}: {r.status} ({esc(r.failure)}); the paper completes it.")
            continue
        dt, steps, newton, krylov, ratio = p
        tr, er = ratios(r, ex)
        parts = [f"time step {r.target_dt:.4g} vs {dt:.4g} ({pct(r.target_dt, dt)})",
                 f"steps {r.steps} vs {steps} ({pct(r.steps, steps)})"]
        if newton is not None:
            parts.append(f"Newton {r.imp('newton_iterations')} vs {newton} ({pct(r.imp('newton_iterations'), newton)})")
            parts.append(f"GMRES {r.imp('krylov_iterations')} vs {krylov} ({pct(r.imp('krylov_iterations'), krylov)})")
            parts.append(f"cost ratio {num(tr, '.3f')} (time) and {num(er, '.3f')} (evals) vs {ratio:.3g}")
        out.append(f"- {r.name}: " + "; ".join(parts) + ".")
    return "\n".join(out)
