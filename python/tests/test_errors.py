"""Bad input raises ValueError with the one line `mpm` prints before exit status 2; a numerical failure raises
SimulationFailure (a RuntimeError) and the outputs say so, as the command's do."""
import json

import numpy as np
import pytest

import mpm
from conftest import DISKS, cli


@pytest.mark.parametrize("key,value,text", [("simulation.end_time", -1, "-1"), ("grid.cells", [20], "[20]"),
                                            ("simulation.kernel", "quintic", '"quintic"'),
                                            ("simulation.no_such_key", 1, "1")])
def test_a_bad_value_is_the_commands_message(key, value, text):
    done = cli("run", DISKS, "--dry-run", "--set", f"{key}={text}", check=False)
    assert done.returncode == 2
    with pytest.raises(ValueError) as raised:
        mpm.Scene.from_toml(DISKS, overrides={key: value})
    assert "mpm: " + str(raised.value) + "\n" == done.stderr


def test_from_dict_names_the_key():
    with pytest.raises(ValueError, match=r"^<dict>:1: simulation: expected a table, got 3$"):
        mpm.Scene.from_dict({"simulation": 3})
    with pytest.raises(ValueError, match=r"simulation\.end_time: expected a number, string, list or dict, got a value of type object$"):
        mpm.Scene.from_dict({"simulation": {"end_time": object()}})


def test_from_dict_refuses_a_dict_that_contains_itself_or_nests_too_deep():
    # Both overflowed the stack and ended Python (issue 47, item 6); the limit is the reader's 64 levels.
    looped = {"simulation": {}}
    looped["simulation"]["again"] = looped
    with pytest.raises(ValueError, match=r"nested deeper than 64 levels \(a dict or list that contains itself\?\)$"):
        mpm.Scene.from_dict(looped)
    listed = []
    listed.append(listed)
    with pytest.raises(ValueError, match=r"^simulation\.x\[0\]\[0\].*\.\.\.: nested deeper than 64 levels"):
        mpm.Scene.from_dict({"simulation": {"x": listed}})
    deep = {}
    for _ in range(20000):
        deep = {"k": deep}
    with pytest.raises(ValueError, match="nested deeper than 64 levels"):
        mpm.Scene.from_dict(deep)
    with pytest.raises(ValueError, match="nested deeper than 64 levels"):
        mpm.Scene.from_toml(DISKS, overrides={"simulation.x": deep})


def test_messages_name_the_key_not_the_cpp():
    # A huge integer was "Unable to cast Python instance to C++ type", a scene too large for the machine
    # "vector::reserve" (issue 47, item 8); Simulation now refuses what `mpm run` refuses, with its message.
    with pytest.raises(ValueError, match=r"^bodies\[0\]\.ppc: expected an integer of at most 64 bits .*, got 10{30}$"):
        mpm.Scene.from_dict({"bodies": [{"ppc": 10**30}]})
    huge = mpm.Scene.from_toml(DISKS, overrides={"grid.cells": [40000, 40000], "bodies.0.ppc": 4})
    with pytest.raises(ValueError, match=r"bodies\[0\] \(lower-left\): seeds about .* particles"):
        mpm.Simulation(huge)


def test_missing_file():
    with pytest.raises(ValueError, match="no-such.toml: cannot open the scene file"):
        mpm.Scene.from_toml("no-such.toml")


def test_a_failed_run_raises_and_says_so(tmp_path):
    # The disks bounce apart and leave the unit square at t = 3.56 (step 241), before the end time 4.
    scene = mpm.Scene.from_toml(DISKS, overrides={"simulation.end_time": 4.0})
    cli_done = cli("run", DISKS, "--set", "simulation.end_time=4", "--out", tmp_path / "cli", check=False)
    assert cli_done.returncode == 1
    sim = mpm.Simulation(scene, out=tmp_path / "py")
    with pytest.raises(mpm.SimulationFailure) as raised:
        sim.run()
    assert isinstance(raised.value, RuntimeError)
    last = tmp_path / "cli" / "particles_fail.vtp"
    assert cli_done.stderr == f"mpm: simulation failed: {raised.value}; its last state: {last}\n"
    sim.close()
    with open(tmp_path / "py" / "summary.json") as f:
        summary = json.load(f)
    assert summary["status"] == "failed" and summary["failure"] == str(raised.value)
    assert summary["failure_frame"] == "particles_fail.vtp"
    assert str(raised.value).startswith("step 241, t = 3.56") and "left the grid" in str(raised.value)
    # The last state (issue 46, item 7), the same from both: every particle as the failed step left it, the one
    # the message names marked, and only the particles outside the unit square marked with it.
    for folder in ("cli", "py"):
        points, fields = mpm.read_vtp(tmp_path / folder / "particles_fail.vtp")
        assert len(points) == 416
        outside = (points[:, :2] < 0).any(axis=1) | (points[:, :2] > 1).any(axis=1)
        named = int(str(raised.value).split("particle ")[1].split(":")[0])
        assert fields["failed"][fields["id"] == named][0] == 1 and outside[fields["id"] == named][0]
        assert ((fields["failed"] == 1) == outside).all()
    with pytest.raises(mpm.SimulationFailure, match="the run failed earlier"):
        sim.step()


def test_stepping_past_the_end():
    sim = mpm.Simulation(mpm.Scene.from_toml(DISKS, overrides={"simulation.end_time": 0.02}))
    sim.run()
    with pytest.raises(ValueError, match="step: the scene ended at end_time"):
        sim.step()


def test_a_closed_simulation_does_not_advance(tmp_path):
    # After close() the calls that advance or write were accepted and ran on (issue 47, item 7).
    sim = mpm.Simulation(mpm.Scene.from_toml(DISKS), out=tmp_path / "out")
    sim.step()
    sim.close()
    velocities = np.zeros(sim.particles["x"].shape)
    for name, call in [("step", sim.step), ("step", sim.run), ("checkpoint", lambda: sim.checkpoint(tmp_path / "c.h5")),
                       ("set_velocities", lambda: sim.set_velocities(velocities))]:
        with pytest.raises(ValueError, match=f"^{name}: the simulation is closed"):
            call()
    assert sim.steps == 1 and not (tmp_path / "c.h5").exists()
    sim.close()  # a second close does nothing
    with open(tmp_path / "out" / "summary.json") as f:
        assert json.load(f)["steps"] == 1


def test_a_callback_that_closes_ends_the_run():
    sim = mpm.Simulation(mpm.Scene.from_toml(DISKS))
    with pytest.raises(ValueError, match="^step: the simulation is closed"):
        sim.run(callback=lambda s: s.close())
    assert sim.steps == 1


def test_run_until_nan_is_refused():
    sim = mpm.Simulation(mpm.Scene.from_toml(DISKS))
    with pytest.raises(ValueError, match="^until: expected a time \\[s\\], got nan$"):
        sim.run(until=float("nan"))
    assert sim.steps == 0


def test_bad_options():
    scene = mpm.Scene.from_toml(DISKS)
    with pytest.raises(ValueError, match="threads: expected a non-negative count"):
        mpm.Simulation(scene, threads=-1)
    with pytest.raises(ValueError, match="threads: expected a non-negative count of at most 512 .*, got 100000"):
        mpm.Simulation(scene, threads=100000)
    with pytest.raises(ValueError, match="checkpoint_every: the checkpoints go into the output folder"):
        mpm.Simulation(scene, checkpoint_every=5)
    with pytest.raises(ValueError, match="^--restart: checkpoint no-such.h5: no such file$"):
        mpm.Simulation(scene, restart="no-such.h5")
    with pytest.raises(ValueError, match="velocities: expected"):
        mpm.Simulation(scene).set_velocities([[1.0, 2.0]])
