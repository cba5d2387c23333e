"""Shared helpers of the Python module's tests: the command-line program beside the module, and the examples."""
import json
import os
import subprocess

import pytest

SOURCE = os.environ.get("MPM_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
BINARY = os.environ.get("MPM_BINARY", os.path.join(SOURCE, "build", "bin", "mpm"))
MPIEXEC = os.environ.get("MPM_MPIEXEC", "")  # mpirun of an MPI build
DISKS = os.path.join(SOURCE, "examples", "colliding-disks", "scene.toml")
BLOCK = os.path.join(SOURCE, "examples", "block-on-floor", "scene.toml")
BAR = os.path.join(SOURCE, "examples", "implicit", "elastic-bar.toml")


def cli(*args, check=True):
    """Run `mpm ARGS` and return the finished process (stdout and stderr as text)."""
    done = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True,
                          env={**os.environ, "OMP_NUM_THREADS": "2"})
    if check and done.returncode != 0:
        raise AssertionError(f"mpm {' '.join(map(str, args))}: exit {done.returncode}\n{done.stderr}")
    return done


def cli_json(*args):
    return json.loads(cli(*args, "--json").stdout)


@pytest.fixture
def disks():
    """The colliding disks to t = 0.5 (about 50 steps)."""
    return DISKS, {"simulation.end_time": 0.5}
