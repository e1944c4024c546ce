"""tactus.read_recording: a recording's records as NumPy views, the same values bit for bit
as `tactus export --csv`, and damaged files reported as the command line reports them."""
import csv
import gc
import subprocess

import numpy as np
import pytest

import tactus


@pytest.fixture
def recording(tmp_path, tactus_binary, scenes):
    rec = tmp_path / "run.tacrec"
    subprocess.run([tactus_binary, "run", scenes / "needle_block.toml", "--lockstep", "--duration", "2", "--record",
                    rec], check=True, capture_output=True)
    return rec


def exported(binary, rec, tmp_path):
    paths = [tmp_path / n for n in ("f.csv", "s.csv", "e.csv")]
    subprocess.run([binary, "export", rec, "--csv", paths[0], "--steps", paths[1], "--events", paths[2]],
                   check=True, capture_output=True)
    tables = []
    for p in paths:
        with open(p, newline="") as f:
            tables.append(list(csv.DictReader(f)))
    return tables


def test_read_recording_matches_the_csv_export(recording, tactus_binary, tmp_path, scenes):
    r = tactus.read_recording(recording)
    model = tactus.load_scene(scenes / "needle_block.toml")
    frames_csv, steps_csv, events_csv = exported(tactus_binary, recording, tmp_path)
    assert r["mode"] == "lockstep" and r["complete"] and r["truncation"] == ""
    assert r["scene_name"] == model.name and r["scene_text"] == model.text
    assert r["haptic_rate"] == model.rates["haptic"] and r["devices"] == [d.name for d in model.devices]
    fr = r["frames"]
    col = lambda rows, name: np.array([float(row[name]) for row in rows])  # shortest round trip: exact
    assert fr["t"].shape == (len(frames_csv),) and len(frames_csv) > 0
    assert np.array_equal(fr["t"], col(frames_csv, "t"))
    assert [r["devices"][d] for d in fr["device"]] == [row["device"] for row in frames_csv]
    for k, axis in enumerate("xyz"):
        assert np.array_equal(fr["position"][:, k], col(frames_csv, axis))
        assert np.array_equal(fr["force"][:, k], col(frames_csv, "f" + axis))
        assert np.array_equal(fr["proxy"][:, k], col(frames_csv, "proxy_" + axis))
    assert np.array_equal(fr["orientation_xyzw"][:, 3], col(frames_csv, "qw"))
    assert np.array_equal(fr["contact"], col(frames_csv, "contact"))
    assert np.array_equal(fr["compute_ns"] / 1000.0, col(frames_csv, "compute_us"))
    assert fr["contact"].sum() > 0
    st = r["steps"]
    assert np.array_equal(st["t"], col(steps_csv, "t")) and len(steps_csv) > 0
    assert np.array_equal(st["solver_iterations"], col(steps_csv, "solver_iterations"))
    ev = r["events"]
    assert ev["kind_name"] == [row["kind"] for row in events_csv] and "rupture" in ev["kind_name"]
    assert np.array_equal(ev["value"], col(events_csv, "value"))
    assert ev["text"] == [row["text"] for row in events_csv]


def test_recording_arrays_are_views_that_keep_the_records_alive(recording):
    r = tactus.read_recording(recording)
    force, t = r["frames"]["force"], r["frames"]["t"]
    assert not force.flags.writeable and not force.flags.owndata
    with pytest.raises(ValueError):
        force[0, 0] = 1.0
    snapshot = force.copy(), t.copy()
    del r
    gc.collect()
    np.testing.assert_array_equal(force, snapshot[0])
    np.testing.assert_array_equal(t, snapshot[1])


def test_damaged_recordings(recording, tmp_path):
    data = recording.read_bytes()
    cut = tmp_path / "cut.tacrec"
    cut.write_bytes(data[:30])  # inside the header chunk
    with pytest.raises(tactus.InputError) as e:
        tactus.read_recording(cut)
    assert e.value.file == str(cut) and e.value.byte_offset is not None
    # Cut after the first frames chunk: what was kept, and where reading stopped.
    cut.write_bytes(data[: data.index(b"TRCK", data.index(b"TRCK") + 1) + 16 + 256 * 160 + 4 + 50])
    r = tactus.read_recording(cut)
    assert not r["complete"] and "byte" in r["truncation"]
    assert r["frames"]["t"].shape[0] >= 256
    with pytest.raises(tactus.InputError):
        tactus.read_recording(tmp_path / "absent.tacrec")
