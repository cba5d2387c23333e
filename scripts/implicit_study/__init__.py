"""The implicit study behind scripts/implicit-study.py: the examples of Sulsky & Kaul (2004), Sec. 3, run by the
real engine and written up in docs/implicit.md and docs/implicit/*.png.

Modules: paths (where runs, scenes and the page live), progress (the log), runs (one `mpm run`), paper (the
paper's numbers), report (number and table formatting shared by the sections), figures (saving a figure),
bars (what the two bar problems share), elastic_bar, disks, plastic_bar, upsetting and upsetting_figures (one
section of the page each), document (the page around the sections).
"""
import matplotlib

matplotlib.use("Agg")   # before any module of the package imports pyplot: the study draws without a display
