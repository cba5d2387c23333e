"""Section 3 of docs/implicit.md: the elastic-plastic bar in tension (Sec. 3.1.2 and 3.2.6, Tables 3 and 5,
Fig. 4)."""
from .bars import BAR_E, BAR_L, BAR_V, SIGMA_HEAD, bar_runs, cg_runs, final_sigma, reaction_stress, sigma_rows, stress_figure
from .paper import PAPER_PLASTIC, PAPER_PLASTIC_CG
from .paths import SCENES
from .report import COST_HEAD, PAPER_HEAD, cost_rows, diff_lines, esc, md_table, pct
from .runs import EXPLICIT, Run

TAU0, C1 = 6.0, 5000.0   # Sec. 3.1.2: yield stress and linear hardening modulus


def plastic_bar(args):
    scene = SCENES / "plastic-bar.toml"
    runs = bar_runs("plastic-bar", scene)
    pc = args.preconditioner
    improved = [Run("plastic-bar", f"100x c + {pc}", scene, ["implicit.step_factor=100", "implicit.start_factor=100",
                                                             f"implicit.preconditioner={pc}"], optional=True)]
    long = [Run("plastic-bar", "t=100 explicit", scene, ["simulation.end_time=100"] + EXPLICIT),
            Run("plastic-bar", "t=100 100x c", scene,
                ["simulation.end_time=100", "implicit.step_factor=100", "implicit.start_factor=100"])]
    cg = cg_runs("plastic-bar", scene)
    for r in runs + improved + long + cg:
        r.execute(args, args.repeat)
    ex = runs[0]

    def stress(t):
        eps = BAR_V * t / BAR_L
        return (TAU0 + C1 * eps) / (1 + C1 / BAR_E)

    fig = stress_figure(runs[4], stress, "Elastic-plastic bar, 100x a: sigma_xx at each frame (paper Fig. 4)",
                        "plastic_bar_stress.png") if runs[4].ok else None
    cost = md_table(COST_HEAD + [PAPER_HEAD], cost_rows(runs, ex, PAPER_PLASTIC))
    cost2 = md_table(COST_HEAD, cost_rows(improved, ex, None))
    cost_cg = md_table(COST_HEAD + [PAPER_HEAD], cost_rows(cg, ex, PAPER_PLASTIC_CG))
    cost_long = md_table(COST_HEAD, cost_rows(long[1:], long[0], None))
    acc = md_table(SIGMA_HEAD, sigma_rows(runs + improved + long, stress))
    d = []
    if ex.ok:
        d.append(f"- Explicit step: ours {ex.explicit_dt:.4g} vs the paper's 0.0047 ({pct(ex.explicit_dt, 0.0047)}); "
                 f"explicit steps {ex.steps} vs 5024 ({pct(ex.steps, 5024)}).")
    d.append(diff_lines(runs, ex, PAPER_PLASTIC))
    t_paper = (68.5 * (1 + C1 / BAR_E) - TAU0) / C1 * BAR_L / BAR_V
    means = [(r.name, final_sigma(r)[0]) for r in runs if r.ok]
    if means:
        errs = [abs(m / stress(24.0) - 1) * 100 for _, m in means]
        d.append(f"- Final sigma_xx at t = 24: means from {min(m for _, m in means):.4g} to "
                 f"{max(m for _, m in means):.4g} vs the analytic {stress(24.0):.4g} (largest error "
                 f"{max(errs):.2f}%). The paper's expected 68.5 is the same formula at t = {t_paper:.2f}.")
    for r in long:
        if r.ok:
            m, dev = final_sigma(r)
            sxx = r.last_frame()["stress"][:, 0]
            d.append(f"- {r.name}: mean sigma_xx {m:.4g} vs {stress(100.0):.4g} at eps = 1/3 ({pct(m, stress(100.0))}); "
                     f"the particles range from {sxx.min():.4g} to {sxx.max():.4g}, and the puller reaction / 0.3 is "
                     f"{reaction_stress(r):.4g} ({pct(reaction_stress(r), stress(100.0))}). The paper reports only "
                     "that Newton-CG and Newton-GMRES complete it, with the same results explicit and implicit.")
        else:
            d.append(f"- {r.name}: {r.status} ({esc(r.failure)}); the paper completes this run.")
    d.append("- Counts: with the paper's parameters (epsilon = 1e-6, gamma = 1e-4, h = 1e-5) our Newton counts are "
             "12-19% above the paper's at 100x, 2.7x at 10x (about one iteration per step where the paper often "
             "needs none) and 2.5x at 1x, and our GMRES takes 7 iterations per Newton step against the paper's 4. "
             "At the paper's step the 100x c counts of steps and Newton iterations are the paper's to 3% (Sec. 6); "
             "the GMRES count, as for the elastic bar, has no cause among those tested; the frozen-Jacobian row "
             "takes one GMRES iteration per Newton step.")
    d.append("- t = 100: the stress is not uniform, for two causes that `tests/verification/test_bar_variants.cpp` "
             "asserts (`PlasticBarAtOneHundred.*`). (1) Cell crossing with linear shape functions: the x-force on a "
             "free node is (sum of sigma_xx V over the cell to its right - the same over the cell to its left) / h, "
             "so quasi-static equilibrium makes sum sigma_xx V equal in every cell, not the stress. After two "
             "columns cross into new cells the cells hold 6, 12, 6 and 12 particles; the four sums agree to 1e-4 "
             "while the particles in the crowded cells carry half the stress, unload elastically and stop "
             "straining for good (Steffen et al. 2008, Sec. 4.2: the O(1) quadrature error of linear MPM). "
             "With `--set simulation.kernel=\"cpgimp\"`, whose particle domains tile the stretched bar, every "
             "particle more than a cell from the puller is within 5% of the uniaxial value (269.5-288.3 against "
             "278.8). (2) The grip: the puller prescribes its velocity on every node it touches, and that "
             "reaches one cell beyond its edge (the node x = 0.4 throughout), so the strained gauge is the fixed "
             "0.4 < x < 0.7 (hence eps = v t / 0.3, not the ln(4/3) of a bar stretched along its whole length, "
             "which would give 240.7), and material dragged into the cell between the puller's edge and that "
             "node stops straining: with cpGIMP the first column at 64.7-70.5, the second at 241-246. A "
             "particle whose stencil holds only prescribed nodes has no velocity gradient, and a grip moving "
             "through the grid always drags material into such a cell, so with this loading no kernel makes "
             "every particle uniaxial. The example keeps the linear kernel of the paper, whose t = 24 run ends "
             "before any particle leaves its cell. The paper reports no stress at t = 100.")
    text = f"""## 3. Elastic-plastic bar in tension (Sec. 3.1.2 and 3.2.6, Tables 3 and 5, Fig. 4)

Scene `examples/implicit/plastic-bar.toml`: the bar of Sec. 1 with von Mises plasticity, yield stress
tau0 = 6 and linear hardening c1 = 5000, plane stress, run to t = 24 (eps = 8%). Analytic uniaxial stress
(tau0 + c1 eps) / (1 + c1 / E) with eps = v t / l: {stress(24.0):.4g} at t = 24, {stress(100.0):.4g} at t = 100.

### Cost (paper Table 5)

{cost}

### Cost with Newton-CG (paper Table 3)

The paper's Newton-CG runs: `--set implicit.solver=newton-cg --set implicit.formulation=velocity
--set implicit.residual=unscaled` (its CG runs measure the residual in force x time, Sec. 3.2.2), with the
tolerances of the scene; the Krylov column counts CG iterations.

{cost_cg}

Improvement (not in the paper) at 100x c, same explicit reference: `+ {pc}` =
`--set implicit.preconditioner={pc}`.

{cost2}

Run to t = 100 (`--set simulation.end_time=100`, 33% strain; two columns of particles cross into new cells):

{cost_long}

### Final stress

{acc}

{"![Elastic-plastic bar: sigma_xx vs x](" + fig + ")" if fig else "(figure not drawn: the 100x a run did not finish)"}

### Where we differ from the paper, and why

{chr(10).join(x for x in d if x)}
"""
    return text, {"elastic-plastic bar": runs + improved}
