"""mpm.verify and mpm.converge return the figures of `mpm verify --json` and `mpm converge --json`, to the digit."""
import numpy as np
import pytest

import mpm
from conftest import cli_json


def test_verify_is_the_command():
    ours = mpm.verify("bar-1d", kernel="linear", integrator="usl", cells=16)
    assert ours == cli_json("verify", "bar-1d", "--kernel", "linear", "--integrator", "usl", "--cells", 16)
    assert ours["status"] == "ok" and ours["steps"] > 0 and ours["linf"] > 0


def test_converge_is_the_command():
    ours = mpm.converge("bar-1d", "cells", [8, 16, 32], series="cpgimp:cd,linear:usl")
    rows = cli_json("converge", "bar-1d", "--vary", "cells", "--values", "8,16,32", "--series", "cpgimp:cd,linear:usl")
    assert ours["rows"] == rows
    assert np.array_equal(ours["cells"], [8, 16, 32, 8, 16, 32])
    assert np.isnan(ours["order"][0]) and np.isnan(ours["order"][3])
    # cpGIMP with CD converges at second order in space (measured 2.60 and 1.84 on 8 / 16 / 32 cells)
    assert (ours["order"][[1, 2]] > 1.8).all()


def test_bad_study_options():
    with pytest.raises(ValueError, match="^--cfl-speed: expected particles or reference, got 'fast'$"):
        mpm.verify("bar-1d", cfl_speed="fast")
    with pytest.raises(ValueError, match="colour: not an option of the studies"):
        mpm.verify("bar-1d", colour="red")
    with pytest.raises(ValueError, match="^cells: expected an integer, got 'many'$"):
        mpm.verify("bar-1d", cells="many")
    # A huge integer was "expected a number, got a int" (issue 47, item 8).
    with pytest.raises(ValueError, match="^cells: expected an integer of at most 2147483647, got 100000000000000000000$"):
        mpm.verify("bar-1d", cells=10**20)
    with pytest.raises(ValueError, match="^cfl: expected a number, got 'x'$"):
        mpm.verify("bar-1d", cfl="x")
    with pytest.raises(ValueError, match="^--cells: expected at least 2 cells per axis$"):
        mpm.verify("bar-1d", cells=1)
    with pytest.raises(ValueError, match="^--vary: expected cells or cfl"):
        mpm.converge("bar-1d", "ppc", [1, 2])
