"""mpm from Python: scenes, runs, particle and grid fields, and the verification studies (docs/python.md).

    import mpm
    sim = mpm.Simulation(mpm.Scene.from_toml("examples/colliding-disks/scene.toml"))
    sim.run(every=0.5, callback=lambda s: print(s.time, s.energies["total"]))
    x = sim.particles["x"]          # a read-only view, valid until the next step
"""
import json
import math
from collections.abc import Mapping

import numpy as np

from . import _core
from ._core import OutputError, Scene, SimulationFailure, __version__
from .output import Output, read_output, read_vtp

__all__ = ["Scene", "Simulation", "SimulationFailure", "OutputError", "verify", "converge", "read_output",
           "read_vtp", "Output"]


class Fields(Mapping):
    """Named arrays of the particles or the grid, read when asked (and once per step). Views into the engine are
    read-only and valid until the next step, which may reorder the particles: keep a copy (np.array(a)) to keep
    values."""

    def __init__(self, names, read, aliases=None):
        self._names, self._read, self._aliases = list(names), read, aliases or {}
        self._cache = {}

    def __getitem__(self, name):
        name = self._aliases.get(name, name)
        if name not in self._names:
            raise KeyError(f"{name!r}: expected one of {', '.join(self._names)}")
        if name not in self._cache:
            self._cache[name] = self._read(name)
        return self._cache[name]

    def __iter__(self):
        return iter(self._names)

    def __len__(self):
        return len(self._names)

    def __repr__(self):
        return f"Fields({', '.join(self._names)})"


class Simulation:
    """A scene run on the engine it names, stepped from Python.

    threads: 0 takes the scene's setting (0 there too: every core). out: an output folder written exactly as
    `mpm run --out` writes it (frames, history.csv, summary.json); None writes nothing. restart: a checkpoint of
    this scene to continue from. checkpoint_every: steps between checkpoints (out/checkpoint.h5).
    """

    def __init__(self, scene, threads=0, out=None, restart=None, checkpoint_every=0):
        self._s = _core.Session(scene, threads=threads, out=out, restart=restart, checkpoint_every=checkpoint_every)
        self._fields = None  # (steps, particle fields, grid fields) of the current step

    # The clock.
    dim = property(lambda self: self._s.dim)
    time = property(lambda self: self._s.time, doc="simulated time [s]")
    steps = property(lambda self: self._s.steps, doc="steps taken since t = 0")
    end_time = property(lambda self: self._s.end_time, doc="the scene's end time [s]")
    dt = property(lambda self: self._s.next_dt, doc="the step the next step() will try [s]")
    finished = property(lambda self: self._s.time >= self._s.end_time * (1 - 1e-14))

    @property
    def energies(self):
        """kinetic, strain, total, external_work and friction_dissipation [J], and momentum, over the particles."""
        return self._s.totals()

    @property
    def reactions(self):
        """The force each constraint (face, region, rigid body) applied in the last step, by name [N]."""
        return self._s.reactions()

    def _current(self):
        if self._fields is None or self._fields[0] != self.steps:
            self._fields = (self.steps,
                            Fields(self._s.particle_field_names(), self._s.particle_field, {"v": "velocity"}),
                            None)
        return self._fields

    @property
    def particles(self):
        """Particle fields by the frames' names (x, X, velocity or v, displacement, stress as xx yy zz xy yz xz, F as
        dim x dim, J, volume, mass, material, id, ...), one row per particle in the engine's current order."""
        return self._current()[1]

    @property
    def grid(self):
        """Grid fields of the last step, one row per node with the ghost layers, axis 0 fastest (grid_shape):
        position (a copy), mass and velocity (views)."""
        steps, particles, grid = self._current()
        if grid is None:
            fields = self._s.grid_fields()
            grid = Fields(fields.keys(), fields.__getitem__)
            self._fields = (steps, particles, grid)
        return grid

    @property
    def grid_shape(self):
        """Nodes per axis of the grid fields' rows, axis 0 first (it varies fastest)."""
        return tuple(self._s.grid_shape())

    def set_velocities(self, v):
        """Replace the particles' velocities: an array of particles x dim, rows in the order of particles."""
        self._s.set_velocities(np.asarray(v, dtype=float))
        self._fields = None

    def step(self):
        """One whole step (with its outputs). Raises SimulationFailure on a numerical failure."""
        self._s.step()

    def run(self, until=None, every=None, callback=None):
        """Step to `until` (default: the scene's end time) in whole steps, the last possibly past it: the steps are
        those of `mpm run`, whatever `until` and `every`. callback(sim) is called after every step, or with `every`
        after the step that passes each multiple of it (t = k every, as [output] every places frames) and after the
        last step. The GIL is released while it steps; Ctrl-C (KeyboardInterrupt) stops it after a whole step, in a
        state to inspect, checkpoint or continue. Reaching the end time closes the outputs (summary.json). A callback
        that calls close() ends the run with a ValueError at the next step: a closed simulation does not advance."""
        target = self.end_time if until is None else float(until)
        if math.isnan(target):
            raise ValueError("until: expected a time [s], got nan")
        if every is not None and not every > 0:
            raise ValueError(f"every: expected a positive time, got {every}")

        def next_multiple():
            return (math.floor(self.time / every * (1 + 1e-12)) + 1) * every

        next_call = None if every is None else next_multiple()
        called, first = None, self.steps
        while self.time < target * (1 - 1e-14) and not self.finished:
            if callback is None:
                self._s.advance(target)
            elif every is None:
                self._s.advance(target, max_steps=1)
                callback(self)
            else:
                self._s.advance(min(target, next_call))
                if self.time >= next_call * (1 - 1e-12):
                    callback(self)
                    called, next_call = self.steps, next_multiple()
        if every is not None and callback is not None and self.steps != first and called != self.steps:
            callback(self)
        if self.finished:
            self.close()
        return self

    def checkpoint(self, path):
        """Write a checkpoint of this state; Simulation(scene, restart=path) continues from it, bitwise."""
        self._s.checkpoint(path)

    def close(self):
        """Finish the outputs: the last frame, summary.json (status ok, stopped or failed). Later calls do nothing;
        step(), run(), checkpoint() and set_velocities() then raise ValueError (the state may still be read)."""
        self._s.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def verify(case, threads=0, **options):
    """Run a manufactured solution as `mpm verify CASE` does: options by the command's names with underscores
    (kernel, integrator, transfer, cells, ppc, cfl, cfl_speed, error, start, constrained_acceleration, amplitude,
    nu, theta, dim, end_time). Returns the row of `mpm verify --json` as a dict (linf, l1, l2, steps, dt, ...)."""
    return json.loads(_core.verify(case, threads, **options))


def converge(case, vary, values, series="", threads=0, **options):
    """A convergence study as `mpm converge CASE --vary VARY --values ... [--series ...]` runs it. Returns a dict:
    "rows", the rows of `--json` (each past a series' first with its observed "order"), and the same as arrays
    over all rows: VARY (cells or cfl), "linf", "l1", "l2" and "order" (NaN at each series' first point)."""
    rows = json.loads(_core.converge(case, vary, [float(v) for v in values], series, threads, **options))
    table = {"rows": rows}
    for key in (vary, "linf", "l1", "l2", "order"):
        table[key] = np.array([row.get(key, np.nan) for row in rows], dtype=float)
    return table
