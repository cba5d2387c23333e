"""A scene run from Python writes the same bits as `mpm run` of the same scene: history, frames and summary."""
import json
import os
import subprocess

import numpy as np
import pytest

import mpm
from conftest import BAR, BINARY, DISKS, MPIEXEC, cli

# summary.json's keys that measure the machine rather than the run
MACHINE = {"wall_seconds", "compute_seconds", "memory"}


def same_outputs(a, b):
    """Every file of output folder a equals b's byte for byte, summary.json up to the machine's measurements."""
    assert sorted(os.listdir(a)) == sorted(os.listdir(b))
    for name in os.listdir(a):
        with open(os.path.join(a, name), "rb") as fa, open(os.path.join(b, name), "rb") as fb:
            da, db = fa.read(), fb.read()
        if name == "summary.json":
            ja, jb = json.loads(da), json.loads(db)
            assert {k: v for k, v in ja.items() if k not in MACHINE} == {k: v for k, v in jb.items() if k not in MACHINE}
        else:
            assert da == db, name


@pytest.mark.parametrize("scene,end", [(DISKS, 0.5), (BAR, 2.0)], ids=["explicit-musl", "implicit"])
def test_python_run_equals_the_command(tmp_path, scene, end):
    cli("run", scene, "--out", tmp_path / "cli", "--set", f"simulation.end_time={end}", "--threads", 2)
    sim = mpm.Simulation(mpm.Scene.from_toml(scene, overrides={"simulation.end_time": end}), threads=2,
                         out=tmp_path / "py")
    sim.run()
    assert sim.finished
    same_outputs(tmp_path / "cli", tmp_path / "py")
    out = mpm.read_output(tmp_path / "cli")
    assert out.summary["status"] == "ok" and out.summary["steps"] == sim.steps
    # The last frame holds the particles' state: the views equal it to the bit.
    last = out.frame(-1)
    ours, theirs = np.argsort(sim.particles["id"]), np.argsort(last["id"])
    assert np.array_equal(last["id"][theirs], sim.particles["id"][ours])
    assert np.array_equal(last["x"][theirs, :2], sim.particles["x"][ours])
    assert np.array_equal(last["velocity"][theirs, :2], sim.particles["v"][ours])
    # Frames hold F by columns (VTK's order): component a + 3 c is F(a, c).
    assert np.array_equal(last["F"].reshape(-1, 3, 3).transpose(0, 2, 1)[theirs, :2, :2], sim.particles["F"][ours])
    assert np.array_equal(last["stress"][theirs], sim.particles["stress"][ours])
    # history.csv's last row is the attributes' values (written with 6 significant digits).
    assert out.history["step"][-1] == sim.steps
    assert out.history["total_energy"][-1] == pytest.approx(sim.energies["total"], rel=1e-5)


def test_from_dict_runs_as_the_file(tmp_path):
    tomllib = pytest.importorskip("tomllib")
    with open(DISKS, "rb") as f:
        table = tomllib.load(f)
    table["simulation"]["end_time"] = 0.3
    a = mpm.Simulation(mpm.Scene.from_dict(table))
    b = mpm.Simulation(mpm.Scene.from_toml(DISKS, overrides={"simulation.end_time": 0.3}))
    a.run()
    b.run()
    assert a.steps == b.steps > 10
    for name in ("x", "velocity", "F", "stress"):
        assert np.array_equal(a.particles[name], b.particles[name]), name


def test_without_an_output_folder_nothing_is_written(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    mpm.Simulation(mpm.Scene.from_toml(DISKS, overrides={"simulation.end_time": 0.05})).run()
    assert os.listdir(tmp_path) == []


@pytest.mark.skipif(not MPIEXEC, reason="an mpm built without MPI")
def test_read_output_joins_the_pieces_of_a_divided_run(tmp_path):
    cli("run", DISKS, "--out", tmp_path / "one", "--set", "simulation.end_time=0.5", "--threads", 1)
    env = {**os.environ, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMP_NUM_THREADS": "1"}
    subprocess.run([MPIEXEC, "--oversubscribe", "-np", "2", BINARY, "run", DISKS, "--out", tmp_path / "two", "--set",
                    "simulation.end_time=0.5", "--threads", "1"], check=True, capture_output=True, env=env)
    one, two = mpm.read_output(tmp_path / "one"), mpm.read_output(tmp_path / "two")
    assert two.summary["ranks"] == 2 and len(one) == len(two) == 6 and np.array_equal(one.times, two.times)
    a, b = one.frame(-1), two.frame(-1)
    assert len(a["id"]) == len(b["id"]) == 416
    ia, ib = np.argsort(a["id"]), np.argsort(b["id"])
    for name in ("x", "velocity", "F", "stress", "mass"):
        assert np.array_equal(a[name][ia], b[name][ib]), name  # one process and two ranks: the same bits
