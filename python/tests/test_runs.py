"""Stepping and callbacks, energies and reactions, and a run interrupted (Ctrl-C) and restarted from its checkpoint,
bitwise equal to one uninterrupted run."""
import _thread
import os
import re

import numpy as np
import pytest

import mpm
from conftest import BAR, BLOCK, DISKS, SOURCE, cli


def test_run_until_takes_whole_steps():
    sim = mpm.Simulation(mpm.Scene.from_toml(DISKS))
    sim.run(until=0.25)
    dt = sim.dt  # a fixed CFL step while the disks fly free
    assert sim.time >= 0.25 and sim.time - dt < 0.25
    assert not sim.finished


def test_callbacks():
    sim = mpm.Simulation(mpm.Scene.from_toml(DISKS, overrides={"simulation.end_time": 0.5}))
    every_step, every_tenth = [], []
    sim.run(until=0.1, callback=lambda s: every_step.append((s.steps, s.time)))
    assert [k for k, _ in every_step] == list(range(1, sim.steps + 1))
    sim.run(every=0.1, callback=lambda s: every_tenth.append(s.time))
    assert len(every_tenth) == 4  # past t = 0.2, 0.3, 0.4 and at the end time 0.5
    assert all(0 <= t - 0.1 * (k + 2) < sim.dt for k, t in enumerate(every_tenth))
    assert every_tenth[-1] == sim.time == 0.5 and sim.finished


def test_energy_and_momentum():
    sim = mpm.Simulation(mpm.Scene.from_toml(DISKS, overrides={"simulation.end_time": 0.1}))
    e0 = sim.energies
    # two disks of radius 0.2, density 1000, speed 0.1 sqrt(2): kinetic 2 * 1/2 m v^2, opposite momenta
    mass = sim.particles["mass"].sum()
    assert e0["kinetic"] == pytest.approx(0.5 * mass * 0.02, rel=1e-14)
    assert np.abs(e0["momentum"]).max() < 1e-14 * mass
    sim.run()
    assert sim.energies["total"] == pytest.approx(e0["total"], rel=1e-12)  # free flight


def test_reactions_of_the_implicit_bar(tmp_path):
    sim = mpm.Simulation(mpm.Scene.from_toml(BAR, overrides={"simulation.end_time": 1.0}), out=tmp_path)
    sim.run()
    reactions = sim.reactions
    assert list(reactions) == ["x-max", "puller"]  # the symmetry face, then the rigid body
    # The history's reaction columns of the same run (6 significant digits), name by name.
    history = mpm.read_output(tmp_path).history
    for name, force in reactions.items():
        assert force.shape == (2,)
        for d, axis in enumerate("xy"):
            assert force[d] == pytest.approx(history[f"reaction_{name}_{axis}"][-1], rel=1e-5, abs=1e-12)
    assert reactions["puller"][0] < 0  # the force the body applies to the bar: it pulls it towards -x


def test_interrupted_and_restarted_is_bitwise(tmp_path):
    scene = mpm.Scene.from_toml(DISKS, overrides={"simulation.end_time": 1.0})
    whole = mpm.Simulation(scene)
    whole.run()

    sim = mpm.Simulation(scene)
    seen = []

    def ctrl_c(s):  # what Ctrl-C in a terminal or a notebook does: SIGINT to the main thread
        seen.append(s.steps)
        if s.time > 0.4:
            _thread.interrupt_main()

    with pytest.raises(KeyboardInterrupt):
        sim.run(callback=ctrl_c)
    assert sim.steps == seen[-1] and 0.4 < sim.time < 1.0  # stopped after the whole step of the callback
    sim.checkpoint(tmp_path / "checkpoint.h5")
    again = mpm.Simulation(scene, restart=tmp_path / "checkpoint.h5")
    assert again.steps == sim.steps and again.time == sim.time
    again.run()
    assert again.steps == whole.steps
    for name in ("x", "velocity", "F", "stress", "id"):
        a, b = whole.particles[name], again.particles[name]
        assert np.array_equal(a[np.argsort(whole.particles["id"])], b[np.argsort(again.particles["id"])]), name


def test_sigint_while_stepping_stops_after_a_step():
    # A run of many thousand steps; SIGINT comes from another thread, which runs only because the steps release
    # the GIL, and the run stops within one slice of steps (about 0.2 s) after it.
    import os
    import signal
    import threading
    import time

    sim = mpm.Simulation(mpm.Scene.from_toml(BLOCK, overrides={"simulation.end_time": 1000.0}), threads=1)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.run()
    timer.join()
    assert 0 < sim.steps and sim.time < 1000.0
    assert time.monotonic() - start < 5.0  # measured about 0.3-0.5 s; far below the whole run's minutes
    steps = sim.steps
    sim.step()  # the state is a whole step's: it goes on
    assert sim.steps == steps + 1


def test_version_is_the_builds():
    """mpm.__version__ is the version `mpm --version` names (the project's, CMakeLists.txt)."""
    with open(os.path.join(SOURCE, "CMakeLists.txt")) as f:
        project = re.search(r"project\(mpm LANGUAGES CXX VERSION ([0-9.]+)\)", f.read()).group(1)
    assert mpm.__version__ == project
    assert cli("--version").stdout.startswith(f"mpm {project} (commit ")
