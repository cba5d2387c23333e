"""The study's progress log on stderr, each line stamped with the seconds since the study started."""
import sys
import time


def log(msg, start=[time.time()]):  # noqa: B006 (the default holds the start time)
    print(f"[{time.time() - start[0]:7.1f} s] {msg}", file=sys.stderr, flush=True)
