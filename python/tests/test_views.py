"""Particle and grid fields: read-only views of the engine's arrays where the layout allows, copies otherwise."""
import numpy as np
import pytest

import mpm
from conftest import DISKS


def address(a):
    return a.__array_interface__["data"][0]


@pytest.fixture
def sim():
    s = mpm.Simulation(mpm.Scene.from_toml(DISKS, overrides={"simulation.end_time": 0.2}))
    s.run(until=0.1)
    return s


def test_views_are_the_engines_storage(sim):
    n = len(sim.particles["id"])
    for name, shape in [("x", (n, 2)), ("X", (n, 2)), ("velocity", (n, 2)), ("F", (n, 2, 2)), ("volume", (n,)),
                        ("mass", (n,)), ("material", (n,)), ("id", (n,))]:
        a, b = sim._s.particle_field(name), sim._s.particle_field(name)
        assert a.shape == shape and not a.flags.writeable, name
        assert address(a) == address(b) and a.base is b.base, name  # the same memory twice: no copy
    # F's rows and columns: J from the view equals the J field (a copy, computed by the engine).
    F = sim.particles["F"]
    assert np.array_equal(F[:, 0, 0] * F[:, 1, 1] - F[:, 0, 1] * F[:, 1, 0], sim.particles["J"])
    # The copies: a fresh array each time.
    for name, shape in [("displacement", (n, 2)), ("stress", (n, 6)), ("J", (n,))]:
        a, b = sim._s.particle_field(name), sim._s.particle_field(name)
        assert a.shape == shape and address(a) != address(b) and np.array_equal(a, b), name
    assert np.array_equal(sim.particles["displacement"], sim.particles["x"] - sim.particles["X"])
    with pytest.raises(ValueError, match="read-only"):
        sim.particles["x"][0, 0] = 1.0


def test_grid_fields(sim):
    grid, shape = sim.grid, sim.grid_shape
    # 20 cells per axis and one ghost layer each side (linear kernel): 23 nodes per axis, axis 0 fastest.
    assert shape == (23, 23)
    assert grid["position"].shape == (23 * 23, 2) and grid["mass"].shape == (23 * 23,)
    assert np.allclose(grid["position"][1], [0.0, -0.05]) and np.allclose(grid["position"][23], [-0.05, 0.0])
    assert grid["velocity"].strides[0] == grid["mass"].strides[0] > 8  # strided views of the node records
    # The last step's projection keeps the mass of the particles it started from (all inside the grid).
    assert grid["mass"].sum() == pytest.approx(sim.particles["mass"].sum(), rel=1e-13)


def test_setting_velocities(sim):
    v = np.array(sim.particles["v"])
    sim.set_velocities(np.zeros_like(v))
    assert np.array_equal(sim.particles["v"], np.zeros_like(v))
    assert sim.energies["kinetic"] == 0
    sim.set_velocities(v)
    assert np.array_equal(sim.particles["v"], v)
    # Stopped bodies under no load stay where they are (no stress yet at t = 0.1: the disks have not met).
    x = np.array(sim.particles["x"])
    ids = np.array(sim.particles["id"])
    sim.set_velocities(np.zeros_like(v))
    sim.step()
    order = np.argsort(sim.particles["id"])
    assert np.array_equal(sim.particles["id"][order], np.sort(ids))
    assert np.abs(sim.particles["x"][order] - x[np.argsort(ids)]).max() < 1e-12
