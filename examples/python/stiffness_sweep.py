#!/usr/bin/env python3
"""Force-indentation curves of the default scene's tissue block for several Young's moduli.

A Model is immutable, so each stiffness is a new scene: the default scene with its block
material's `young_modulus` changed (Model.with_changes). A controlled device presses
the sphere finger straight down into each block at constant speed; the script plots force
against indentation, one curve per modulus, saves the figure as PNG and prints the force at
a fixed depth for each modulus.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/stiffness_sweep.py [OUT.png]

docs/python.md describes the API, docs/scene-format.md the scene keys.
"""
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import tactus  # noqa: E402

MODULI = [5e3, 10e3, 20e3, 40e3]  # Young's moduli to try [Pa]
DEPTH = 0.008  # how far the finger presses in [m]
REPORT_DEPTH = 0.005  # the depth at which the forces are compared [m]


def press(model, depth=DEPTH, speed=0.01):
    """Indentation [m] and vertical force [N] per haptic frame while pressing in."""
    device = model.devices[0]
    top = model.bodies[0].surface_vertices[:, 2].max()  # the block's top face, scene z
    # The finger's lowest point starts 2 mm above the surface and goes down at constant speed.
    start_z = top + model.tools[0].radius + 0.002
    frames = int(round((depth + 0.002) / speed * model.rates["haptic"]))
    path = np.linspace(start_z, start_z - depth - 0.002, frames)
    offset = np.array(device.offset)
    sim = tactus.Simulation(model, controlled=[device.name])
    forces = sim.forces  # live view of the newest frames
    force = []
    for z in path:
        # Scene point to device coordinates (offset and scale; no rotation in this scene).
        sim.set_device_pose(0, (np.array([0.0, 0.0, z]) - offset) / device.scale)
        sim.step()
        force.append(forces[0, 2])
    return start_z - 0.002 - path, np.array(force)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "stiffness_sweep.png"
    base = tactus.default_scene()
    body = base.bodies[0]
    material = base.material_of(body).name
    fig, ax = plt.subplots(figsize=(6, 4))
    summary = []
    for modulus in MODULI:
        model = base.with_changes({f"materials.{material}.young_modulus": modulus})
        assert model.material_of(model.bodies[0]).young_modulus == modulus
        indentation, force = press(model)
        ax.plot(1e3 * indentation, force, label=f"E = {modulus / 1e3:g} kPa")
        summary.append(f"{modulus / 1e3:g} kPa: {np.interp(REPORT_DEPTH, indentation, force):.4f} N")
    ax.axvline(1e3 * REPORT_DEPTH, color="grey", linestyle=":", linewidth=1)
    ax.set_xlabel("indentation [mm]")
    ax.set_ylabel("force felt, z [N]")
    ax.set_title(f"{base.name}: {body.name}, {base.material_of(body).model}, pressed at 10 mm/s")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"{out}: force at {1e3 * REPORT_DEPTH:g} mm: " + ", ".join(summary))


if __name__ == "__main__":
    main()
