"""The section of docs/implicit.md that sets the paper's statements beside what we measure, each row naming the
ctest that asserts it (tests/verification/*.cpp) or saying that only this study shows it."""

STATEMENTS = """## The paper's statements beside what we measure

Each row names the ctest that asserts it; "study only" rows are shown by the tables of this document alone.

| paper (Sulsky & Kaul 2004) | measured here | agrees | test |
|---|---|---|---|
| Elastic bar: uniform stress sigma_xx = Y v t / L, Eq. (3.1.1) (Sec. 3.1.1) | 33.33 at t = 10 to 2e-6 with the example's roller end, implicit and explicit, plane stress and strain | yes | `ElasticBar.*`, `NewtonDirect.ElasticBarReachesTheAnalyticStressWithoutKrylovIterations` |
| Elastic bar with the paper's no-slip right end | sigma_xx spreads from 32.10 to 36.26: the clamp holds the end's width while the bar contracts laterally; with nu = 0 the clamped bar is uniaxial to 2e-5 | the spread is the clamp's, not the method's | `ElasticBarNoSlip.ClampRestrainsPoissonContractionAndOnlyThat` |
| Elastic-plastic bar: final stress 68.5 at t = 24, uniform (Sec. 3.1.2, Fig. 4) | 67.67, the bilinear law at eps = 8% (68.5 is the law at t = 24.3), uniform to 2% | yes | `PlasticBar.FollowsTheBilinearLawAtTwentyFour` |
| Elastic-plastic bar to t = 100 (33% strain): completes, explicit and implicit alike (Sec. 3.1.2) | both complete; neither is uniform. Linear MPM after cell crossing makes sum sigma_xx V equal per cell (4 cell sums agree to 1e-4, particles from 95 to 298); cpGIMP is uniaxial outside the puller's grip cell (269.5-288.3 against 278.8) but not inside it (64.7-245.9), which no kernel avoids with a node-prescribed grip | completes: yes; uniform: no, for the two causes shown | `PlasticBarAtOneHundred.*` |
| Eq. (2.4.1): conditionally stable for 0 <= mu < 1, unconditionally for mu = 1, dissipative for mu != 0 (Sec. 2.4.1) | a standing shear wave loses energy at the one-mode rate log(1 + mu w^2) a step for every mu > 0 (within 2%) and none at mu = 0; at w far above 2: stable and dissipative for mu = 0.5, 0.75 and 1, unstable for mu = 0.25 | dissipative: yes; stability: unconditional from mu = 1/2 on (w^2 (1 - 2 mu) <= 4), not only at mu = 1 | `ImplicitTheta.*` |
| Newton converges quadratically when the linear systems are solved exactly (Secs 2.4.3 and 3.2.2, Fig. 5) | with the direct sparse solve (`solver = "newton-direct"`): ||F_{n+1}|| <= 0.26 ||F_n||^2 while ||F|| > 1e-5, then linear at a contraction of 0.04 or less, the assembled tangent's accuracy | yes, down to the tangent's accuracy | `NewtonDirect.PlasticBarConvergesQuadratically` |
| Tables 4 and 5: steps, Newton and GMRES iterations of the bars | the cost tables below | steps 0-16% above the paper's (our explicit step is 8-15% smaller); Newton and GMRES counts above them (see each section) | `Tables1And3And4And5/CostTable.*` (the counts of the tables below, to 10%) |
| Tables 1 and 3: the bars with Newton-CG (velocity formulation, unscaled residual) | the Newton-CG tables below: Newton and CG iterations 0.8-1.9x the paper's, except the plastic bar at 10x (4.1-4.4x: about one Newton iteration a step where the paper's often needs none, as with GMRES) | at 100x within 20% for the plastic bar, 10-30% above for the elastic bar | `Tables1And3And4And5/CostTable.*` (CG rows at 1x a and 100x c) |
| Colliding disks: more energy lost with larger steps (Sec. 3.1.1, Fig. 3) | total energy kept at t = 150 in the table below, falling from 0.997 (explicit) to 0.12 (100x) | yes | `CollidingDisks.EnergyKeptFallsWithTheStepAsDocumented` (10x a and 100x a) |
| Upsetting: final radius about 16.5 mm, load about 1050 kN (Figs 10, 12a) | radius 16.66 mm; load in the table below | radius: yes (1%); load: 11-21% low, cause not found | `Upsetting.RadiusAndLoadAreTheDocs` (1000x and 10000x) |

Not reproduced yet: Figs 5-8 as the paper draws them (residual
histories and cost against epsilon, gamma and h with Newton-GMRES), Fig. 9 (the line search on two plastic-bar
steps), the variants of Sec. 3.1.2 (compression into one column, plane-stress tension to 75% strain,
plane-stress compression), the upsetting with the platen starting above the billet, on the 0.25 mm mesh, with
its temperature, and the consistent mass matrix of Eq. (2.2.6).
"""
