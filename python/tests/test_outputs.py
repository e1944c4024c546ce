"""Outputs people open: `tactus run --vtk` read back with VTK's own reader (Debian's
python3-vtk9) and `tactus export --hdf5` read back with h5py (Debian's python3-h5py),
compared with what the engine reports through the Python module and the CSV export."""
import csv
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import tactus
from conftest import BINARY

# Readers nobody here wrote, installed by scripts/setup (python3-vtk9, python3-h5py): a
# machine without them fails here rather than skipping the checks.
import h5py
import vtkmodules.vtkIOXML as vtk
from vtkmodules.util import numpy_support

DURATION = 0.5
RATE = 30.0


def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    assert grid.GetNumberOfPoints() > 0, path
    points = numpy_support.vtk_to_numpy(grid.GetPoints().GetData())
    point_data = {grid.GetPointData().GetArrayName(i): numpy_support.vtk_to_numpy(grid.GetPointData().GetArray(i))
                  for i in range(grid.GetPointData().GetNumberOfArrays())}
    cell_data = {grid.GetCellData().GetArrayName(i): numpy_support.vtk_to_numpy(grid.GetCellData().GetArray(i))
                 for i in range(grid.GetCellData().GetNumberOfArrays())}
    cells = [[grid.GetCell(c).GetPointId(k) for k in range(grid.GetCell(c).GetNumberOfPoints())]
             for c in range(grid.GetNumberOfCells())]
    return points, point_data, cell_data, cells, [grid.GetCellType(c) for c in range(grid.GetNumberOfCells())]


def read_pvd(path):
    """[(timestep, block name, file)] in the file's order."""
    root = ET.parse(path).getroot()
    assert root.get("type") == "Collection"
    return [(float(d.get("timestep")), d.get("name"), path.parent / d.get("file")) for d in root.iter("DataSet")]


@pytest.fixture(scope="module")
def default_series(tmp_path_factory):
    if not BINARY.exists():
        pytest.skip(f"no tactus binary at {BINARY}")
    out = tmp_path_factory.mktemp("vtk")
    run = subprocess.run([BINARY, "run", "--lockstep", "--duration", str(DURATION), "--vtk", out / "series",
                          "--vtk-rate", str(RATE)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return out / "series"


def test_run_vtk_is_a_time_series_of_every_body_and_device(default_series):
    model = tactus.default_scene()
    entries = read_pvd(default_series / "default.pvd")
    blocks = [b.name for b in model.bodies] + model_device_names(model)
    times = sorted({t for t, _, _ in entries})
    # One frame per 1/30 s of simulated time, 0 to 0.5 s inclusive, each at the first
    # simulation step at or past it.
    period = 1.0 / model.rates["simulation"]
    assert len(times) == int(DURATION * RATE) + 1
    for k, t in enumerate(times):
        assert k / RATE - 1e-9 <= t < k / RATE + period + 1e-9
    for t in times:
        assert sorted(name for tt, name, _ in entries if tt == t) == sorted(blocks)
    for _, _, file in entries:
        points, point_data, cell_data, _, _ = read_vtu(file)
        for name, values in {**point_data, **cell_data}.items():
            assert np.isfinite(values).all(), f"{file}: {name}"
        assert np.isfinite(points).all()


def model_device_names(model):
    return [d.name for d in model.devices]


def test_run_vtk_body_matches_the_engine(default_series):
    model = tactus.default_scene()
    body = model.bodies[0]
    assert body.volumetric
    entries = [(t, f) for t, name, f in read_pvd(default_series / "default.pvd") if name == body.name]
    t_last, file = entries[-1]
    points, point_data, cell_data, cells, types = read_vtu(file)
    # The mesh: every node, every tetrahedron (VTK type 10), in the scene's numbering.
    assert points.shape == (body.node_count, 3)
    assert set(types) == {10}
    np.testing.assert_array_equal(np.array(cells), body.tets)
    # The nodes where the engine has them at that simulation step: a lockstep run from
    # Python, stepped to the haptic period of that step (its simulation step comes first).
    sim = tactus.Simulation(model)
    sim.step(int(round(t_last * model.rates["haptic"])) + 1)
    x = np.array(sim.body_positions(0))
    assert np.array_equal(points, x)  # shortest round-trip decimals: the same doubles
    assert np.array_equal(point_data["displacement"], x - body.rest_positions)
    assert np.abs(point_data["displacement"]).max() > 1e-4  # the hand pressed: not a rest mesh
    # The volume ratio against tetrahedron volumes computed here.
    def volumes(p):
        a, b, c, d = (p[body.tets[:, k]] for k in range(4))
        return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0
    np.testing.assert_allclose(cell_data["volume_ratio"], volumes(points) / volumes(body.rest_positions), rtol=1e-9)
    assert {"velocity", "contact_force"} <= set(point_data)
    assert {"green_strain_von_mises", "von_mises_stress"} <= set(cell_data)
    assert (cell_data["von_mises_stress"] >= 0).all() and cell_data["von_mises_stress"].max() > 0


def test_run_vtk_device_block_holds_the_frame(default_series):
    model = tactus.default_scene()
    device = model.devices[0]
    result = tactus.run(model, DURATION)
    frames = result.frames(device.name)
    entries = [(t, f) for t, name, f in read_pvd(default_series / "default.pvd") if name == device.name]
    pressed = 0
    for _, file in entries[1:]:
        points, point_data, _, _, types = read_vtu(file)
        assert points.shape == (2, 3) and set(types) == {1}
        # The newest frame drained when the frame was written, named by its time.
        k = int(np.flatnonzero(frames["t"] == point_data["t_frame"][0])[0])
        assert np.array_equal(points[0], frames["proxy"][k])
        assert np.linalg.norm(point_data["force"][0]) == pytest.approx(np.linalg.norm(frames["force"][k]), rel=1e-12)
        assert point_data["contact"][0] == frames["contact"][k]
        pressed += int(frames["contact"][k])
    assert pressed > 0


def test_export_vtk_replays_the_recording(tmp_path, tactus_binary, default_series):
    rec = tmp_path / "run.tacrec"
    subprocess.run([tactus_binary, "run", "--lockstep", "--duration", str(DURATION), "--record", rec],
                   check=True, capture_output=True)
    out = subprocess.run([tactus_binary, "export", rec, "--vtk", tmp_path / "replayed"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    run_entries = read_pvd(default_series / "default.pvd")
    replay_entries = read_pvd(tmp_path / "replayed" / "default.pvd")
    assert [(t, n) for t, n, _ in replay_entries] == [(t, n) for t, n, _ in run_entries]
    # The body as the run had it, bit for bit (a lockstep recording replays exactly).
    for (_, name, a), (_, _, b) in zip(run_entries, replay_entries):
        if name == "block":
            assert np.array_equal(read_vtu(a)[0], read_vtu(b)[0])


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_export_hdf5_matches_the_csv_export(tmp_path, tactus_binary, scenes):
    rec = tmp_path / "run.tacrec"
    subprocess.run([tactus_binary, "run", scenes / "needle_block.toml", "--lockstep", "--duration", "2", "--record",
                    rec], check=True, capture_output=True)
    h5, frames_csv, steps_csv, events_csv = (tmp_path / n for n in ("out.h5", "f.csv", "s.csv", "e.csv"))
    subprocess.run([tactus_binary, "export", rec, "--hdf5", h5, "--csv", frames_csv, "--steps", steps_csv, "--events",
                    events_csv], check=True, capture_output=True)
    with h5py.File(h5, "r") as f:
        assert f.attrs["mode"] == "lockstep" and f.attrs["complete"][0] == 1
        devices = [d.decode() for d in f["devices"][()]]
        fr = f["frames"]
        assert fr["force"].attrs["units"] == "N" and fr["t"].attrs["units"] == "s"
        assert fr["compute_ns"].attrs["units"] == "ns" and fr["proxy"].attrs["units"] == "m"
        rows = read_csv(frames_csv)
        assert len(rows) == fr["t"].shape[0] > 0
        # Bit for bit: the CSV's shortest round-trip decimals read back to the same doubles.
        col = lambda name: np.array([float(r[name]) for r in rows])
        assert np.array_equal(fr["t"][()], col("t"))
        assert [devices[d] for d in fr["device"][()]] == [r["device"] for r in rows]
        assert np.array_equal(fr["frame"][()], col("frame"))
        for k, axis in enumerate("xyz"):
            assert np.array_equal(fr["position"][:, k], col(axis))
            assert np.array_equal(fr["force"][:, k], col("f" + axis))
            assert np.array_equal(fr["torque"][:, k], col("t" + axis))
            assert np.array_equal(fr["proxy"][:, k], col("proxy_" + axis))
        for k, name in enumerate(("qw", "qx", "qy", "qz")):
            assert np.array_equal(fr["orientation"][:, k], col(name))
        for name in ("contact", "flags", "buttons"):
            assert np.array_equal(fr[name][()], col(name))
        assert np.array_equal(fr["compute_ns"][()] / 1000.0, col("compute_us"))
        assert np.array_equal(fr["late_ns"][()] / 1000.0, col("late_us"))
        assert fr["contact"][()].sum() > 0

        st, rows = f["steps"], read_csv(steps_csv)
        assert len(rows) == st["t"].shape[0] > 0
        assert np.array_equal(st["t"][()], np.array([float(r["t"]) for r in rows]))
        assert np.array_equal(st["step"][()], np.array([int(r["step"]) for r in rows]))
        assert np.array_equal(st["solver_iterations"][()], np.array([int(r["solver_iterations"]) for r in rows]))
        assert np.array_equal(st["compute_ns"][()] / 1000.0, np.array([float(r["compute_us"]) for r in rows]))

        ev, rows = f["events"], read_csv(events_csv)
        assert len(rows) == ev["t"].shape[0] > 0
        assert np.array_equal(ev["t"][()], np.array([float(r["t"]) for r in rows]))
        assert [k.decode() for k in ev["kind_name"][()]] == [r["kind"] for r in rows]
        assert np.array_equal(ev["value"][()], np.array([float(r["value"]) for r in rows]))
        assert [t.decode() for t in ev["text"][()]] == [r["text"] for r in rows]
        assert "rupture" in [r["kind"] for r in rows]


def one_error_line(result):
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 1, result.stderr
    assert len(lines) == 1, result.stderr
    return lines[0]


def test_unwritable_vtk_folder_is_one_located_error(tmp_path, tactus_binary):
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    out = subprocess.run([tactus_binary, "run", "--lockstep", "--duration", "0.1", "--vtk", blocker / "series"],
                         capture_output=True, text=True)
    line = one_error_line(out)
    assert str(blocker / "series") in line and "cannot create the folder" in line


def test_truncated_recording_export_hdf5(tmp_path, tactus_binary):
    rec = tmp_path / "run.tacrec"
    subprocess.run([tactus_binary, "run", "--lockstep", "--duration", "0.5", "--record", rec],
                   check=True, capture_output=True)
    data = rec.read_bytes()
    # Cut inside the header chunk: nothing to export, one line naming the file and byte.
    cut = tmp_path / "cut.tacrec"
    cut.write_bytes(data[:40])
    out = subprocess.run([tactus_binary, "export", cut, "--hdf5", tmp_path / "cut.h5"], capture_output=True, text=True)
    line = one_error_line(out)
    assert str(cut) in line and "byte" in line
    # Cut after the first frames chunk (256 frames of 160 bytes): what was kept is
    # exported, the HDF5 file says where it stopped.
    cut.write_bytes(data[: data.index(b"TRCK", data.index(b"TRCK") + 1) + 16 + 256 * 160 + 4 + 50])
    out = subprocess.run([tactus_binary, "export", cut, "--hdf5", tmp_path / "half.h5"], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    with h5py.File(tmp_path / "half.h5", "r") as f:
        assert f.attrs["complete"][0] == 0 and "byte" in f.attrs["truncation"][0]
        assert 0 < f["frames/t"].shape[0] < 501


def test_unwritable_hdf5_file_is_one_located_error(tmp_path, tactus_binary):
    rec = tmp_path / "run.tacrec"
    subprocess.run([tactus_binary, "run", "--lockstep", "--duration", "0.1", "--record", rec],
                   check=True, capture_output=True)
    target = tmp_path / "missing_folder" / "out.h5"
    line = one_error_line(subprocess.run([tactus_binary, "export", rec, "--hdf5", target], capture_output=True,
                                         text=True))
    assert str(target) in line and "cannot create" in line
