"""tactus.Simulation: a lockstep run stepped frame by frame, devices posed from Python, the
newest frames as live views."""
import numpy as np
import pytest

import tactus


def test_stepping_gives_the_frames_of_a_whole_run_bit_for_bit(scenes):
    model = tactus.load_scene(scenes / "femoral_s2_palpation.toml")
    whole = tactus.run(model, 5.0)
    sim = tactus.Simulation(model, keep_frames=True)
    hand = sim.devices.index("hand")
    forces = sim.forces  # a live view: each step overwrites it in place
    for _ in range(5001):
        sim.step()
    assert sim.frame == 5001 and sim.time == 5.0
    np.testing.assert_array_equal(forces[hand], whole.frames("hand")["force"][-1])
    stepped = sim.finish()
    for name in whole.devices:
        assert np.array_equal(stepped.frames(name)["force"], whole.frames(name)["force"])
        assert np.array_equal(stepped.frames(name)["proxy"], whole.frames(name)["proxy"])
    assert whole.frames("hand")["contact"].sum() > 1000


def test_a_device_posed_from_python_replays_a_run_bit_for_bit():
    model = tactus.default_scene()
    recorded = tactus.run(model, 1.5).frames("hand")
    sim = tactus.Simulation(model, controlled=["hand"], keep_frames=True)
    assert sim.is_controlled("hand")
    for position, q in zip(recorded["position"], recorded["orientation_xyzw"]):
        sim.set_device_pose("hand", position, orientation_wxyz=(q[3], q[0], q[1], q[2]))
        sim.step()
    replayed = sim.finish()
    assert replayed.device_reports[0]["kind"] == "controlled"
    assert np.array_equal(replayed.frames("hand")["force"], recorded["force"])
    assert recorded["contact"].sum() > 500


def test_pressing_deeper_pushes_back_harder():
    model = tactus.default_scene()
    sim = tactus.Simulation(model, controlled=["hand"])
    start = model.body("block").surface_vertices[:, 2].max() + 0.002  # above the block's top
    depths, forces = [], []
    for k in range(1200):
        depth = 0.006 * k / 1200
        sim.set_device_pose(0, (0.0, 0.0, start - depth))
        sim.step()
        if k % 100 == 99:
            depths.append(depth)
            forces.append(sim.forces[0, 2])
    assert sim.contacts[0] == 1
    assert forces[-1] > 0.5
    assert all(b >= a for a, b in zip(forces[4:], forces[5:]))


def test_live_views_and_copies():
    model = tactus.default_scene()
    sim = tactus.Simulation(model)
    forces, contacts = sim.forces, sim.contacts
    assert forces.shape == (1, 3) and contacts.shape == (1,)
    assert not forces.flags.writeable
    assert np.shares_memory(forces, sim.forces)
    before = sim.body_positions("block")
    np.testing.assert_array_equal(before, model.bodies[0].rest_positions)
    sim.step(2000)
    assert contacts[0] == 1 and forces[0, 2] > 0.1  # the same arrays, updated in place
    after = sim.body_positions(0)
    assert not np.shares_memory(before, after)
    assert np.abs(after - before).max() > 1e-4
    del sim
    assert forces[0, 2] > 0.1  # the view keeps the run alive


def test_the_deformed_surface_follows_the_nodes():
    model = tactus.default_scene()
    body = model.bodies[0]
    sim = tactus.Simulation(model)
    np.testing.assert_array_equal(sim.surface_positions(0), body.surface_vertices)  # at rest
    sim.step(2000)  # the finger is pressed in
    surface, nodes = sim.surface_positions("block"), sim.body_positions("block")
    assert surface.shape == body.surface_vertices.shape
    # Each surface vertex is the body node at its rest place (a volumetric body's boundary).
    rest = {tuple(p): i for i, p in enumerate(body.rest_positions)}
    index = np.array([rest[tuple(p)] for p in body.surface_vertices])
    np.testing.assert_array_equal(surface, nodes[index])
    top = body.surface_vertices[:, 2].max()
    assert (body.surface_vertices[:, 2] - surface[:, 2])[body.surface_vertices[:, 2] == top].max() > 1e-3  # dented


def test_simulation_refuses_what_it_cannot_do():
    model = tactus.default_scene()
    with pytest.raises(tactus.InputError, match="no device 'foot'"):
        tactus.Simulation(model, controlled=["foot"])
    sim = tactus.Simulation(model)
    with pytest.raises(ValueError, match="not controlled"):
        sim.set_device_pose("hand", (0, 0, 0))
    with pytest.raises(KeyError):
        sim.body_positions("liver")
    sim.step()
    sim.finish()
    with pytest.raises(RuntimeError, match="finished"):
        sim.step()


def test_simulation_writes_a_recording(tmp_path):
    rec = tmp_path / "stepped.rec"
    sim = tactus.Simulation(tactus.default_scene(), record=rec)
    sim.step(100)
    result = sim.finish()
    assert rec.stat().st_size == result.recording_bytes > 0
