"""The numbers of Sulsky & Kaul (2004) that the study compares with."""

# The paper's numbers (Newton-GMRES, momentum formulation, unless said otherwise).
# (time step, steps, Newton, Krylov, cost ratio), keyed by our run names.
PAPER_BAR = {  # Table 4
    "explicit": (0.0048, 2108, None, None, 1.0),
    "1x a": (0.0050, 2041, 126, 243, 1.9796), "10x a": (0.0500, 214, 89, 177, 0.3625),
    "10x b": (0.0500, 205, 83, 166, 0.3434), "100x a": (0.5000, 42, 30, 60, 0.0966),
    "100x b": (0.5000, 30, 26, 52, 0.0782), "100x c": (0.5000, 22, 21, 42, 0.0611),
}
PAPER_BAR_CG = {  # Table 1: Newton-CG, velocity formulation, unscaled residual
    "CG 1x a": (0.0050, 2041, 87, 433, 1.7294), "CG 10x a": (0.0500, 214, 66, 423, 0.3444),
    "CG 10x b": (0.0500, 205, 65, 424, 0.3376), "CG 100x a": (0.5000, 42, 30, 193, 0.1149),
    "CG 100x b": (0.5000, 30, 29, 192, 0.1052), "CG 100x c": (0.5000, 22, 23, 156, 0.0834),
}
PAPER_PLASTIC_CG = {  # Table 3: Newton-CG, velocity formulation, unscaled residual
    "CG 1x a": (0.0050, 4802, 221, 1381, 1.8600), "CG 10x a": (0.0500, 490, 127, 1450, 0.4241),
    "CG 10x b": (0.0500, 481, 136, 1563, 0.4405), "CG 100x a": (0.5000, 70, 80, 915, 0.1843),
    "CG 100x b": (0.5000, 58, 71, 841, 0.1704), "CG 100x c": (0.5000, 49, 72, 922, 0.1844),
}
PAPER_DISKS = {  # Table 2: Newton-CG, velocity formulation (the paper has no Newton-GMRES table for the disks)
    "explicit": (0.02438, 6152, None, None, 1.0), "1x": (0.02438, 6151, 428, 12524, 3.2347),
    "10x a": (0.2438, 625, 359, 21158, 2.8845), "100x a": (2.438, 83, 58, 3934, 0.5265),
}
PAPER_PLASTIC = {  # Table 5
    "explicit": (0.0047, 5024, None, None, 1.0),
    "1x a": (0.0050, 4802, 278, 688, 1.9495), "10x a": (0.0500, 490, 211, 1001, 0.5636),
    "10x b": (0.0500, 481, 207, 1014, 0.5668), "100x a": (0.5000, 70, 65, 214, 0.1059),
    "100x b": (0.5000, 58, 57, 197, 0.0971), "100x c": (0.5000, 49, 48, 186, 0.0909),
}
PAPER_UPSET = {  # Table 6 (the paper's explicit step is 9.5e-8 s; its steps are 1e-7 ... 1e-3 s)
    "explicit": (9.5e-8, 99388, None, None, 1.0), "1x": (1e-7, 95003, 51629, 128738, 3.0120),
    "10x": (1e-6, 9503, 9952, 102068, 1.1707), "100x": (1e-5, 953, 1659, 26982, 0.2998),
    "1000x": (1e-4, 98, 298, 5344, 0.0587), "10000x": (1e-3, 16, 58, 1040, 0.0115),
}
PAPER_RADIUS_MM = 16.5     # Sec. 3.2.7: explicit final radius, "approximately 16.5 mm"
PAPER_LOAD_KN = 1050.0     # final load on the 1 mm mesh, explicit to 1000x, "about 1050 kN"
PAPER_LOAD_CONVERGED_KN = 800.0   # with mesh refinement, "a predicted final load of 800 kN"
