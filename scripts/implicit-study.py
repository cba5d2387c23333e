#!/usr/bin/env python3
"""Regenerate docs/implicit.md and docs/implicit/*.png: the examples of Sulsky & Kaul (2004), "Implicit dynamics
in the material-point method", Sec. 3 (Tables 1-6, Figs 1, 3-12), run by the real engine.

Usage (after building): /usr/bin/python3 scripts/implicit-study.py [--quick] [--mpm build/bin/mpm]
                        [--threads N] [--repeat N] [--timeout S] [--reuse]
                        [--problems bar,disks,plastic,upsetting,parameters,candidates,variants]
                        [--preconditioner NAME]
Needs Debian's python3-numpy and python3-matplotlib. The runs go to out/implicit-study/.
--quick skips the slow upsetting runs (1x, 10x and the finest mesh, 96 x 72, with and without the preconditioner)
and takes a few minutes on 2 cores; the full study runs them all: about an hour from scratch, of which
the finest mesh without the preconditioner takes about 35 minutes (it stops at 45).
The study itself is the package scripts/implicit_study/ (one module per problem); this file is its command line.
"""
import argparse
import pathlib
import sys
import time

from implicit_study.candidates import candidates
from implicit_study.disks import disks
from implicit_study.document import write_document
from implicit_study.elastic_bar import elastic_bar
from implicit_study.parameters import parameters
from implicit_study.paths import FIGS, OUT, ROOT
from implicit_study.plastic_bar import plastic_bar
from implicit_study.progress import log
from implicit_study.upsetting import upsetting
from implicit_study.variants import variants


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mpm", default=str(ROOT / "build" / "bin" / "mpm"), help="the mpm binary")
    ap.add_argument("--quick", action="store_true",
                    help="leave out the slow upsetting runs (1x, 10x, the 96 x 72 mesh): a few minutes on 2 cores")
    ap.add_argument("--threads", type=int, default=0, help="--threads for every run (default: the binary's: all cores)")
    ap.add_argument("--repeat", type=int, default=5,
                    help="run each timed case this many times and keep the median compute time (default 5)")
    ap.add_argument("--timeout", type=float, default=7200.0,
                    help="stop a run after this many seconds and report it as timed out (default 7200; 0: never)")
    ap.add_argument("--preconditioner", default="frozen-jacobian",
                    help="implicit.preconditioner of the elastic bar's improvement rows (default frozen-jacobian)")
    ap.add_argument("--reuse", action="store_true",
                    help="reuse a run in out/implicit-study whose command is unchanged (for editing the report)")
    ap.add_argument("--problems", default="bar,disks,plastic,upsetting,parameters,candidates,variants",
                    help="comma-separated subset of bar,disks,plastic,upsetting,parameters,candidates,variants "
                         "(default: all)")
    args = ap.parse_args()
    start = time.time()
    if not pathlib.Path(args.mpm).exists():
        raise SystemExit(f"implicit-study: no binary at {args.mpm}; build it with `cmake --build build --target mpm`")
    FIGS.mkdir(parents=True, exist_ok=True)
    (ROOT / OUT).mkdir(parents=True, exist_ok=True)
    chosen = [p.strip() for p in args.problems.split(",") if p.strip()]
    problems = {"bar": elastic_bar, "disks": disks, "plastic": plastic_bar, "upsetting": upsetting,
                "parameters": parameters, "candidates": candidates, "variants": variants}
    for p in chosen:
        if p not in problems:
            raise SystemExit(f"implicit-study: unknown problem {p!r} (expected {', '.join(problems)})")
    sections, groups = [], {}
    for p in chosen:
        log(f"== {p}")
        text, g = problems[p](args)
        sections.append(text)
        groups.update(g)

    shown = [a for k, a in enumerate(sys.argv[1:])  # the binary's path (--mpm PATH or --mpm=PATH) is left out
             if not a.startswith("--mpm") and not (k > 0 and sys.argv[k] == "--mpm")]
    command = "/usr/bin/python3 scripts/implicit-study.py" + "".join(f" {a}" for a in shown)
    elapsed = time.time() - start
    write_document(sections, groups, args, command, elapsed)


if __name__ == "__main__":
    main()
