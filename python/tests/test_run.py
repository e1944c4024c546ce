"""Lockstep runs from Python: the frames as views into the run, and the same forces bit for
bit as `tactus run SCENE --lockstep` exported with `tactus export`."""
import csv
import gc
import subprocess

import numpy as np
import pytest

import tactus


def exported_frames(binary, scene, duration, tmp_path):
    """{device name: {column: array}} of `tactus run --lockstep --record` then `tactus export`."""
    rec, out = tmp_path / "run.rec", tmp_path / "frames.csv"
    subprocess.run([binary, "run", scene, "--lockstep", "--duration", str(duration), "--record", rec],
                   check=True, capture_output=True)
    subprocess.run([binary, "export", rec, "--csv", out], check=True, capture_output=True)
    rows = {}
    with open(out, newline="") as f:
        for row in csv.DictReader(f):
            rows.setdefault(row["device"], []).append(row)
    # Shortest round-trip decimal text: float() gives back the very double.
    return {device: {key: np.array([float(r[key]) for r in rs]) for key in rs[0] if key != "device"}
            for device, rs in rows.items()}


# femoral.toml is scenario S4 of seed 003, the whole 35 s of it.
@pytest.mark.parametrize("scene,duration", [("femoral_s2_palpation.toml", 5.0), ("femoral_s3_needle.toml", 6.0),
                                            ("femoral.toml", 35.0)])
def test_python_run_matches_the_command_line_bit_for_bit(scenes, tactus_binary, tmp_path, scene, duration):
    model = tactus.load_scene(scenes / scene)
    result = tactus.run(model, duration)
    expected = exported_frames(tactus_binary, scenes / scene, duration, tmp_path)
    assert set(expected) == set(result.devices)
    touched = 0
    for name in result.devices:
        got, want = result.frames(name), expected[name]
        np.testing.assert_array_equal(got["frame"], want["frame"])
        np.testing.assert_array_equal(got["t"], want["t"])
        for axis, column in enumerate("xyz"):
            # Exact equality: lockstep runs are reproducible bit for bit.
            assert np.array_equal(got["force"][:, axis], want["f" + column]), f"{name} f{column}"
            assert np.array_equal(got["position"][:, axis], want[column])
            assert np.array_equal(got["proxy"][:, axis], want["proxy_" + column])
        np.testing.assert_array_equal(got["contact"], want["contact"])
        touched += int(got["contact"].sum())
    assert touched > 100  # the comparison covers frames in contact, not only free motion


def test_run_frames_are_views_kept_alive_by_their_arrays(scenes):
    result = tactus.run(tactus.load_scene(scenes / "femoral_s2_palpation.toml"), 0.5)
    frames = result.frames("hand")
    force, t = frames["force"], frames["t"]
    assert force.shape == (501, 3) and t.shape == (501,)
    assert not force.flags.writeable and not force.flags.owndata
    assert np.shares_memory(force, result.frames(0)["force"])
    assert np.shares_memory(force, frames["position"]) is False
    np.testing.assert_array_equal(t, np.arange(501) / 1000.0)
    snapshot = force.copy()
    del result, frames
    gc.collect()
    np.testing.assert_array_equal(force, snapshot)


def test_run_report(scenes):
    result = tactus.run(tactus.load_scene(scenes / "femoral_s2_palpation.toml"), 5.0)
    hand = result.device_reports[result.devices.index("hand")]
    assert hand["contact_frames"] > 0 and 0 < hand["max_force_sent"] <= 6.0
    assert result.simulated_time == pytest.approx(5.0, abs=1.5e-3)  # the first frame past the end
    assert result.recorded_frames == 2 * 5001
    with pytest.raises(KeyError):
        result.frames("foot")


def test_run_writes_a_recording(scenes, tmp_path):
    rec = tmp_path / "python.rec"
    result = tactus.run(tactus.load_scene(scenes / "liver.toml"), 0.1, record=rec)
    assert rec.stat().st_size == result.recording_bytes > 0


def test_a_scene_without_device_raises_input_error(scenes):
    text = (scenes / "cantilever.toml").read_text()
    model = tactus.parse_scene(text, str(scenes / "cantilever.toml"))
    if model.devices:
        pytest.skip("cantilever.toml has a device")
    with pytest.raises(tactus.InputError, match="no device"):
        tactus.run(model, 0.1)
