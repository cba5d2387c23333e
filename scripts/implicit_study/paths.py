"""Where the study finds the scenes, writes the runs and writes the page and its figures."""
import pathlib

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
SCENES = pathlib.Path("examples") / "implicit"          # relative to ROOT: the binary runs in ROOT
OUT = pathlib.Path("out") / "implicit-study"
DOC = ROOT / "docs" / "implicit.md"
FIGS = ROOT / "docs" / "implicit"
