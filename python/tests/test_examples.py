"""The Python examples run and write what they say."""
import os
import re
import subprocess
import sys

import numpy as np

import tactus
from conftest import SOURCE_DIR

PNG = b"\x89PNG\r\n\x1a\n"


def run_example(name, *args, env=None):
    """Runs examples/python/NAME with this interpreter and returns what it printed."""
    script = SOURCE_DIR / "examples/python" / name
    done = subprocess.run([sys.executable, script, *args], check=True, capture_output=True, text=True,
                          env={**os.environ, "MPLBACKEND": "Agg", **(env or {})})
    return done.stdout


def test_force_indentation_example_writes_a_png(tmp_path):
    out = tmp_path / "curve.png"
    stdout = run_example("force_indentation.py", out)
    assert out.read_bytes()[:8] == PNG
    assert "peak force" in stdout


def test_stiffness_sweep_force_grows_with_the_modulus(tmp_path):
    out = tmp_path / "sweep.png"
    stdout = run_example("stiffness_sweep.py", out)
    assert out.read_bytes()[:8] == PNG
    # "5 kPa: 0.6136 N, 10 kPa: 1.1996 N, ..." in the order of the sweep
    found = [(float(e), float(f)) for e, f in re.findall(r"([\d.]+) kPa: ([-\d.]+) N", stdout)]
    assert [e for e, _ in found] == [5.0, 10.0, 20.0, 40.0]
    forces = [f for _, f in found]
    assert forces[0] > 0.0
    assert all(b > a for a, b in zip(forces, forces[1:])), forces


def test_palpation_replay_gives_the_recorded_forces_bit_for_bit(tmp_path):
    out = tmp_path / "replay.png"
    stdout = run_example("palpation_replay.py", out)
    assert out.read_bytes()[:8] == PNG
    difference = re.search(r"max difference (\S+) N", stdout)
    assert difference and float(difference.group(1)) == 0.0, stdout
    assert "bit for bit" in stdout and "NOT identical" not in stdout
    # The recording it compared against has the finger pressing in most of the time.
    frames = tactus.read_recording(out.with_suffix(".tacrec"))["frames"]
    assert f"{len(frames['t'])} frames" in stdout
    assert frames["contact"].sum() > len(frames["t"]) // 2
    assert np.linalg.norm(frames["force"], axis=1).max() > 1.0


def test_cspace_surface_queries_give_the_stored_forces_at_the_grid_points(tmp_path, tactus_binary):
    out = tmp_path / "surface.png"
    stdout = run_example("cspace_surface.py", out, env={"TACTUS_BINARY": str(tactus_binary)})
    assert out.read_bytes()[:8] == PNG
    space = tactus.ConfigurationSpace(out.with_suffix(".h5"))
    assert space.points.shape == (196, 3) and space.solved.all()
    # What the script printed for each interpolator ...
    printed = dict(re.findall(r"(\w+) at the 196 grid points: max relative difference (\S+), 196 valid", stdout))
    assert sorted(printed) == ["rbf_cubic", "trilinear"], stdout
    assert all(float(value) <= 1e-9 for value in printed.values()), printed
    # ... and the same queries here, on a space that presses back (z up, deeper harder).
    stored = space.point_forces
    for method in printed:
        forces, valid = tactus.ConfigurationSpace(out.with_suffix(".h5"), method).force(space.points)
        assert valid.all()
        np.testing.assert_allclose(forces, stored, rtol=0, atol=1e-9 * np.abs(stored).max())
    deepest = np.argmin(space.points[:, 2])
    assert stored[deepest, 2] > 0.05
