"""tactus.solve: the static and dynamic solves of `tactus solve` as arrays."""
import csv
import subprocess

import numpy as np
import pytest

import tactus


def test_static_cantilever_matches_the_command_line(scenes, tactus_binary, tmp_path):
    model = tactus.load_scene(scenes / "cantilever.toml")
    (beam,) = tactus.solve(model, static=True)
    assert beam["body"] == "beam" and beam["failure"] == ""
    assert beam["probe_names"] == ["tip"] and beam["region_names"] == ["clamp"]
    rows = beam["time"].shape[0]
    assert beam["probe_displacements"].shape == (rows, 1, 3)
    assert beam["reactions"].shape == (rows, 1, 3)
    assert beam["final_positions"].shape == (model.bodies[0].node_count, 3)
    assert beam["converged"].all() and beam["time"][-1] == 1.0

    out = tmp_path / "beam.csv"
    subprocess.run([tactus_binary, "solve", scenes / "cantilever.toml", "--static", "--csv", out],
                   check=True, capture_output=True)
    with open(out, newline="") as f:
        last = list(csv.DictReader(f))[-1]
    tip = beam["probe_displacements"][-1, 0]
    clamp = beam["reactions"][-1, 0]
    # The CSV holds nine significant digits.
    for axis, c in enumerate("xyz"):
        assert tip[axis] == pytest.approx(float(last[f"tip_u{c}"]), rel=1e-8, abs=1e-15)
        assert clamp[axis] == pytest.approx(float(last[f"clamp_f{c}"]), rel=1e-8, abs=1e-15)
    # The tip bends down under its load; the final positions are the rest ones moved.
    assert tip[2] < 0
    moved = beam["final_positions"] - model.bodies[0].rest_positions
    assert np.abs(moved).max() == pytest.approx(np.abs(tip).max(), rel=0.5)


def test_dynamic_solve_reports_rows_over_time(scenes):
    model = tactus.load_scene(scenes / "cantilever.toml")
    (beam,) = tactus.solve(model, static=False, until=0.05, every=0.01)
    assert beam["time"].shape[0] >= 5
    assert np.all(np.diff(beam["time"]) > 0)
    assert beam["probe_displacements"].shape[1:] == (1, 3)
