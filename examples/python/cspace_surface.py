#!/usr/bin/env python3
"""The force of a precomputed configuration space over a horizontal plane and a depth line.

The script builds a small configuration space with the command line (`tactus precompute`:
a neo-Hookean block, its top centre node held at each point of a 7 x 7 x 4 grid, a few
seconds), opens it with tactus.ConfigurationSpace, checks that both interpolators give the
stored forces at the grid points, and plots the vertical force the block exerts on the tool
over a horizontal plane 4 mm below the surface (rbf_cubic, contour map) and along the depth
line through the centre (trilinear and rbf_cubic). It saves the figure as PNG and the space
next to it (OUT.h5).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/cspace_surface.py [OUT.png]

The tactus binary is $TACTUS_BINARY, or build/release/bin/tactus in this repository.
docs/python.md describes the API, docs/precompute.md the spaces.
"""
import os
import pathlib
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import tactus  # noqa: E402

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
TOP = 0.01  # the block's top face, z [m]
PLANE = 0.004  # depth of the plotted plane below the top face [m]

# A 40 x 40 x 20 mm block, 5 mm cells, fixed at its base; the grid has 2 mm spacing around
# the top centre node, from 2 mm above the surface to 4 mm below it.
SCENE = f"""
[materials.tissue]
model = "neo_hookean"
young_modulus = 5.0e3
poisson_ratio = 0.3
density = 1000.0

[bodies.block]
kind = "fem"
material = "tissue"
solver = "cholesky"
mesh = {{ generator = "box", size = [0.04, 0.04, 0.02], cells = [8, 8, 4] }}

[[bodies.block.fixed]]
side = "z_min"

[precompute]
contact_point = [0.0, 0.0, {TOP}]
spacing = 0.002
min = [-0.006, -0.006, {TOP - PLANE}]
max = [0.006, 0.006, {TOP + 0.002}]
"""


def build_space(output):
    """Runs `tactus precompute` on SCENE, writing the space to output."""
    binary = pathlib.Path(os.environ.get("TACTUS_BINARY", REPOSITORY / "build/release/bin/tactus"))
    if not binary.is_file():
        sys.exit(f"no tactus binary at {binary}: build it, or set TACTUS_BINARY")
    with tempfile.TemporaryDirectory() as folder:
        scene = pathlib.Path(folder) / "block.toml"
        scene.write_text(SCENE)
        done = subprocess.run([binary, "-q", "precompute", scene, "-o", output.resolve()],
                              capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"tactus precompute failed:\n{done.stdout}{done.stderr}")


def main():
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "cspace_surface.png")
    space_file = out.with_suffix(".h5")
    build_space(space_file)
    spaces = {method: tactus.ConfigurationSpace(space_file, method) for method in ("trilinear", "rbf_cubic")}
    space = spaces["rbf_cubic"]
    points, stored = space.points, space.point_forces

    # Both interpolators pass through the stored forces at the grid points.
    summary = []
    for method, s in spaces.items():
        forces, valid = s.force(points)
        relative = np.abs(forces - stored).max() / np.abs(stored).max()
        summary.append(f"{method} at the {len(points)} grid points: max relative difference "
                       f"{relative:.3g}, {int(valid.sum())} valid")

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    # The plane: a fine grid of queries, with the grid points on it as dots. The map is
    # symmetric about x = y but not about x = 0: the box generator splits every cube into six
    # tets around the same diagonal.
    plane_z = TOP - PLANE
    x = np.linspace(points[:, 0].min(), points[:, 0].max(), 61)
    gx, gy = np.meshgrid(x, x)
    queries = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, plane_z)])
    fz = space.force(queries)[0][:, 2].reshape(gx.shape)
    shown = left.contourf(1e3 * gx, 1e3 * gy, fz, levels=20, cmap="viridis")
    on_plane = np.isclose(points[:, 2], plane_z)
    left.plot(1e3 * points[on_plane, 0], 1e3 * points[on_plane, 1], "k.", markersize=3)
    fig.colorbar(shown, ax=left, label="force on the tool, z [N]")
    left.set_xlabel("x [mm]")
    left.set_ylabel("y [mm]")
    left.set_aspect("equal")
    left.set_title(f"rbf_cubic, tool {1e3 * PLANE:g} mm below the surface")

    # The depth line through the centre: both interpolators and the stored points.
    z = np.linspace(points[:, 2].min(), points[:, 2].max(), 200)
    line = np.column_stack([np.zeros_like(z), np.zeros_like(z), z])
    for method, s in spaces.items():
        right.plot(1e3 * (TOP - z), s.force(line)[0][:, 2], label=method)
    centre = np.isclose(points[:, 0], 0.0) & np.isclose(points[:, 1], 0.0)
    right.plot(1e3 * (TOP - points[centre, 2]), stored[centre, 2], "ko", label="stored grid points")
    right.set_xlabel("depth below the surface [mm]")
    right.set_ylabel("force on the tool, z [N]")
    right.set_title("at x = y = 0")
    right.grid(True, alpha=0.3)
    right.legend()
    fig.suptitle(f"configuration space of '{space.body}': {len(points)} points, "
                 f"spacing {1e3 * space.spacing:g} mm")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"{out}: " + "; ".join(summary) + f"; Fz on the plane {fz.min():.4f} to {fz.max():.4f} N")


if __name__ == "__main__":
    main()
