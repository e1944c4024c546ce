#!/usr/bin/env python3
"""Force-indentation curve of the default scene's tissue block, driven from Python.

A controlled device presses a sphere finger straight down into the block at constant speed,
then lifts it again; the script plots the force felt against the indentation depth (loading
and unloading) and saves the figure as PNG.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/force_indentation.py [OUT.png]

docs/python.md describes the API.
"""
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import tactus  # noqa: E402


def press(model, depth=0.008, speed=0.01):
    """Indentation [m] and vertical force [N] per haptic frame over a press and release."""
    device = model.devices[0]
    finger = model.tools[0]
    top = model.bodies[0].surface_vertices[:, 2].max()  # the block's top face, scene z
    rate = model.rates["haptic"]
    # The finger's lowest point starts 2 mm above the surface; the device maps scene to
    # device coordinates by its offset and scale (no rotation in the default scene).
    radius = finger.radius or 0.0
    start_z = top + radius + 0.002
    frames_down = int(round((depth + 0.002) / speed * rate))
    path = np.concatenate([np.linspace(start_z, start_z - depth - 0.002, frames_down),
                           np.linspace(start_z - depth - 0.002, start_z, frames_down)])
    offset = np.array(device.offset)
    sim = tactus.Simulation(model, controlled=[device.name])
    forces = sim.forces  # live view of the newest frames
    indentation, force = [], []
    for z in path:
        scene_point = np.array([0.0, 0.0, z])
        sim.set_device_pose(0, (scene_point - offset) / device.scale)
        sim.step()
        indentation.append(start_z - 0.002 - z)
        force.append(forces[0, 2])
    return np.array(indentation), np.array(force), frames_down


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "force_indentation.png"
    model = tactus.default_scene()
    indentation, force, half = press(model)
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(1e3 * indentation[:half], force[:half], label="pressing")
    ax.plot(1e3 * indentation[half:], force[half:], label="releasing")
    ax.set_xlabel("indentation [mm]")
    ax.set_ylabel("force felt, z [N]")
    ax.set_title(f"{model.name}: {model.bodies[0].name}, {model.materials[0].model}, "
                 f"E = {model.materials[0].young_modulus / 1e3:g} kPa")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"{out}: peak force {force.max():.3f} N at {1e3 * indentation[np.argmax(force)]:.2f} mm")


if __name__ == "__main__":
    main()
