#!/usr/bin/env python3
"""A scripted palpation of the default scene's tissue block, recorded and replayed.

A controlled device presses the sphere finger into the block, slides it sideways and lifts
it, in a Simulation that records the run. The script reads the recording back and replays it:
a second Simulation whose controlled device is given the recorded device poses frame by frame.
The replayed forces equal the recorded ones bit for bit; the script prints the largest
difference and plots recorded and replayed force magnitude against time as PNG (the
recording is kept next to it, OUT.tacrec).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/palpation_replay.py [OUT.png]

docs/python.md describes the API, docs/recording-format.md the recording.
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import tactus  # noqa: E402


def palpation_path(model, depth=0.005, slide=0.03):
    """Finger centre per haptic frame in scene coordinates [m]: press, slide along x, lift."""
    top = model.bodies[0].surface_vertices[:, 2].max()  # the block's top face, scene z
    above = top + model.tools[0].radius + 0.002  # finger 2 mm above the surface
    pressed = above - 0.002 - depth  # finger `depth` into the undeformed surface
    x0, x1 = -slide / 2, slide / 2
    # (time [s], x, z) waypoints, linear in between
    waypoints = np.array([(0.0, x0, above), (0.7, x0, pressed), (1.0, x0, pressed),
                          (2.5, x1, pressed), (2.8, x1, pressed), (3.3, x1, above)])
    t = np.arange(int(waypoints[-1, 0] * model.rates["haptic"])) / model.rates["haptic"]
    x = np.interp(t, waypoints[:, 0], waypoints[:, 1])
    z = np.interp(t, waypoints[:, 0], waypoints[:, 2])
    return np.column_stack([x, np.zeros_like(x), z])


def record(model, path, recording):
    """Drives the first device along path (scene coordinates) and records the run."""
    device = model.devices[0]
    sim = tactus.Simulation(model, controlled=[device.name], record=recording)
    # set_device_pose takes device coordinates: p_scene = offset + scale * p_device
    # (the default scene's device has no rotation).
    for point in (path - np.array(device.offset)) / device.scale:
        sim.set_device_pose(device.name, point)
        sim.step()
    sim.finish()  # closes the recording


def replay(model, frames):
    """Forces [N] of a run whose device is given the recorded poses, one per frame."""
    device = model.devices[0]
    sim = tactus.Simulation(model, controlled=[device.name], keep_frames=True)
    # The recording holds device coordinates (position) and x, y, z, w quaternions; they go
    # back unchanged, reordered to w, x, y, z.
    for position, q, buttons in zip(frames["position"], frames["orientation_xyzw"], frames["buttons"]):
        sim.set_device_pose(device.name, position, orientation_wxyz=(q[3], q[0], q[1], q[2]),
                            buttons=int(buttons))
        sim.step()
    return sim.finish().frames(device.name)


def main():
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "palpation_replay.png")
    recording = out.with_suffix(".tacrec")
    model = tactus.default_scene()
    name = model.devices[0].name
    record(model, palpation_path(model), recording)

    rec = tactus.read_recording(recording)
    assert rec["complete"], rec["truncation"]
    mine = rec["frames"]["device"] == rec["devices"].index(name)
    recorded = {key: values[mine] for key, values in rec["frames"].items()}
    replayed = replay(model, recorded)

    assert len(replayed["force"]) == len(recorded["force"])
    difference = np.abs(replayed["force"] - recorded["force"]).max()
    identical = np.array_equal(replayed["force"], recorded["force"])

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6, 5), sharex=True)
    device = model.devices[0]
    finger = np.array(device.offset) + device.scale * recorded["position"]  # scene coordinates
    top.plot(recorded["t"], 1e3 * finger[:, 0], label="x")
    top.plot(recorded["t"], 1e3 * finger[:, 2], label="z")
    top.set_ylabel("finger centre, scene [mm]")
    top.set_title(f"{model.name}: press, slide 30 mm, lift; recorded and replayed")
    top.legend()
    bottom.plot(recorded["t"], np.linalg.norm(recorded["force"], axis=1), label="recorded", linewidth=3)
    bottom.plot(replayed["t"], np.linalg.norm(replayed["force"], axis=1), "--", label="replayed")
    bottom.set_xlabel("time [s]")
    bottom.set_ylabel("|force| [N]")
    bottom.legend()
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"{out}: {len(recorded['t'])} frames, {int(recorded['contact'].sum())} in contact, "
          f"peak |force| {np.linalg.norm(recorded['force'], axis=1).max():.3f} N; "
          f"replayed vs recorded force: max difference {difference!r} N, "
          f"{'bit for bit' if identical else 'NOT identical'}")


if __name__ == "__main__":
    main()
