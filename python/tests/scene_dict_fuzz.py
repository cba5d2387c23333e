"""A mutation fuzzer for mpm.Scene.from_dict, the Python scene conversion (libFuzzer cannot drive it: it needs the
interpreter). It reads the example scenes as dicts, changes them at random (a value replaced by a hostile one: huge
integers and floats, NaN, deep or self-containing lists and dicts, odd types; a key dropped or added) and converts
each. A ValueError is the contract; any other exception is a finding, and a crash ends the process.

    PYTHONPATH=build/python python3 python/tests/scene_dict_fuzz.py SECONDS [SEED]

scripts/fuzz.sh runs it in CI; test_scene_dict_fuzz.py replays a fixed number of mutations with a fixed seed."""
import copy
import glob
import math
import os
import random
import sys
import time
import tomllib

import numpy as np

import mpm

SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def example_scenes():
    scenes = []
    for path in sorted(glob.glob(os.path.join(SOURCE, "examples", "**", "*.toml"), recursive=True)):
        with open(path, "rb") as f:
            scenes.append(tomllib.load(f))
    return scenes


def hostile(rng, depth=0):
    """A value a caller might pass by mistake or malice."""
    nested = {}
    for _ in range(rng.choice([1, 70, 2000])):
        nested = {"k": nested}
    looped = []
    looped.append(looped)
    choices = [10**30, -10**30, 2**63, 2**63 - 1, 1.7e308, -1.7e308, 1e154, 5e-324, math.nan, math.inf, -math.inf,
               0, -1, 0.0, "", "x" * 10000, "nan", "1e999", None, True, b"bytes", object(), np.int64(2**62),
               np.float32(1e38), np.array([1.0, 2.0]), np.float64("nan"), [], {}, [1, "a", None], nested, looped,
               {1: 2}, set([1]), complex(1, 2)]
    if depth < 2:
        choices += [[hostile(rng, depth + 1)], {"x": hostile(rng, depth + 1)}]
    return rng.choice(choices)


def places(value, depth=0):
    """Every (container, key) of a scene dict down to 6 levels (not into the deep values hostile() made), depth
    first."""
    if depth > 6:
        return
    if isinstance(value, dict):
        for k, v in value.items():
            yield value, k
            yield from places(v, depth + 1)
    elif isinstance(value, list):
        for k, v in enumerate(value):
            yield value, k
            yield from places(v, depth + 1)


def mutate(rng, scene):
    scene = copy.deepcopy(scene)
    for _ in range(rng.randint(1, 3)):
        spots = list(places(scene))
        if not spots:
            break
        container, key = rng.choice(spots)
        action = rng.random()
        if action < 0.7:
            container[key] = hostile(rng)
        elif action < 0.85 and isinstance(container, dict):
            del container[key]
        elif isinstance(container, dict):
            container[rng.choice(["threads", "ppc", "velocity", "E", "extra", "cells"])] = hostile(rng)
    return scene


def fuzz(seconds=None, iterations=None, seed=0):
    """Convert mutated scenes until `seconds` pass or `iterations` are done. Returns (converted, refused)."""
    rng = random.Random(seed)
    scenes = example_scenes()
    start, done, refused = time.monotonic(), 0, 0
    while (iterations is None or done < iterations) and (seconds is None or time.monotonic() - start < seconds):
        scene = mutate(rng, rng.choice(scenes))
        try:
            mpm.Scene.from_dict(scene)
        except ValueError as e:
            refused += 1
            if "\n" in str(e) or len(str(e)) > 2000:
                raise AssertionError(f"iteration {done} (seed {seed}): not one line: {str(e)[:300]!r}") from None
        except Exception as e:
            raise AssertionError(f"iteration {done} (seed {seed}): {type(e).__name__}: {str(e)[:300]}") from e
        done += 1
    return done - refused, refused


if __name__ == "__main__":
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 60
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else int(time.time())
    converted, refused = fuzz(seconds=seconds, seed=seed)
    print(f"scene_dict_fuzz: seed {seed}: {converted + refused} scenes, {refused} refused with a ValueError, "
          f"{converted} converted; no other exception")
