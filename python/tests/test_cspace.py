"""tactus.ConfigurationSpace: a space built by `tactus precompute` on a small block, read
back and queried. At its grid points the interpolators give the stored forces (both are
interpolating); halfway along a grid edge trilinear gives the two ends' mean; bad input raises.
A probe space of the same block is queried with the probe's direction."""
import os
import subprocess

import numpy as np
import pytest

import tactus

SCENE = """
[materials.tissue]
model = "stvk"
young_modulus = 5.0e3
poisson_ratio = 0.3
density = 1000.0

[bodies.block]
kind = "fem"
material = "tissue"
solver = "cholesky"

[bodies.block.mesh]
generator = "box"
size = [0.04, 0.04, 0.02]
cells = [4, 4, 2]

[[bodies.block.fixed]]
side = "z_min"

[precompute]
contact_point = [0.0, 0.0, 0.01]
spacing = 0.003
min = [-0.003, -0.003, 0.004]
max = [0.003, 0.003, 0.013]
"""


def built_by_the_command(folder, scene):
    """The space of `scene` built by `tactus precompute` on one thread, in `folder`."""
    binary = os.environ.get("TACTUS_BINARY")
    if not binary:
        pytest.skip("TACTUS_BINARY is not set")
    (folder / "scene.toml").write_text(scene)
    subprocess.run([binary, "-q", "precompute", "scene.toml", "-o", "space.h5", "--threads", "1"],
                   cwd=folder, check=True, capture_output=True, env={**os.environ, "CI": "1"})
    return folder / "space.h5"


@pytest.fixture(scope="module")
def space_file(tmp_path_factory):
    return built_by_the_command(tmp_path_factory.mktemp("cspace"), SCENE)


def test_the_grid_and_its_stored_forces(space_file):
    space = tactus.ConfigurationSpace(space_file)
    assert space.body == "block"
    assert space.method == "trilinear"
    assert space.spacing == pytest.approx(0.003)
    assert list(space.counts) == [3, 3, 4]
    assert space.points.shape == (36, 3)
    assert space.solved.all()
    # Pressing down on the block: it pushes the tool back up, more the deeper the point.
    forces = space.point_forces
    assert forces.shape == (36, 3)
    deepest = np.argmin(space.points[:, 2])
    assert forces[deepest, 2] > 0.0


@pytest.mark.parametrize("method", ["trilinear", "rbf_cubic", "tricubic_hermite", "rbf_hermite"])
def test_queries_at_grid_points_give_the_stored_forces(space_file, method):
    space = tactus.ConfigurationSpace(str(space_file), method)
    forces, valid = space.force(space.points)
    assert valid.all()
    scale = np.abs(space.point_forces).max()
    np.testing.assert_allclose(forces, space.point_forces, rtol=0, atol=1e-9 * scale)


def test_trilinear_halfway_along_an_edge_is_the_mean_of_its_ends(space_file):
    space = tactus.ConfigurationSpace(space_file)
    points, stored = space.points, space.point_forces
    # Points 0 and 1 are neighbours along x (x runs fastest).
    np.testing.assert_allclose(points[1] - points[0], [0.003, 0.0, 0.0], atol=1e-12)
    force, valid = space.force(0.5 * (points[0] + points[1]))
    assert valid.all() and force.shape == (1, 3)
    np.testing.assert_allclose(force[0], 0.5 * (stored[0] + stored[1]), rtol=1e-12, atol=1e-15)
    # The shape query gives the same force, and a displacement per node of the 5 x 5 x 3 block.
    shaped, displacement, ok = space.shape(0.5 * (points[0] + points[1]))
    assert ok
    np.testing.assert_allclose(shaped, force, rtol=1e-12, atol=1e-15)
    assert displacement.shape == (75, 3)
    assert np.isfinite(displacement).all() and np.abs(displacement).max() > 0.0


def test_bad_input_raises(space_file, tmp_path):
    with pytest.raises(tactus.InputError) as missing:
        tactus.ConfigurationSpace(tmp_path / "nowhere.h5")
    assert "nowhere.h5" in str(missing.value)
    garbage = tmp_path / "garbage.h5"
    garbage.write_text("not a space")
    with pytest.raises(tactus.InputError):
        tactus.ConfigurationSpace(garbage)
    with pytest.raises(tactus.InputError):
        tactus.ConfigurationSpace(space_file, "nearest")
    space = tactus.ConfigurationSpace(space_file)
    with pytest.raises(ValueError):
        space.force(np.zeros((4, 2)))
    with pytest.raises(ValueError):
        space.shape(np.zeros((2, 3)))


def test_build_space_from_python_equals_the_command_line(space_file, tmp_path):
    model = tactus.parse_scene(SCENE, str(tmp_path / "block.toml"))
    out = tmp_path / "python_space.h5"
    stats = tactus.build_space(model, out, threads=1)
    assert stats["points"] == 36 and stats["solved"] == 36 and stats["threads"] == 1
    ours, theirs = tactus.ConfigurationSpace(out), tactus.ConfigurationSpace(space_file)
    assert np.array_equal(ours.points, theirs.points)
    assert np.array_equal(ours.point_forces, theirs.point_forces)  # one thread: the same solves, bit for bit
    _, u_ours, _ = ours.shape(ours.points[5])
    _, u_theirs, _ = theirs.shape(theirs.points[5])
    assert np.array_equal(u_ours, u_theirs)


def test_build_space_needs_a_precompute_table(tmp_path):
    with pytest.raises(tactus.InputError, match="no \\[precompute\\] table"):
        tactus.build_space(tactus.default_scene(), tmp_path / "x.h5")


# The block under a probe leaning up to 12 degrees either way, its end the contact node and
# its neighbours 1 cm away: 9 levels (leans) of 27 points, pressed at most 3 mm.
PROBE_SCENE = SCENE.replace("min = [-0.003, -0.003, 0.004]\nmax = [0.003, 0.003, 0.013]\n",
                            "min = [-0.003, -0.003, 0.007]\nmax = [0.003, 0.003, 0.013]\npatch_radius = 0.0105\n"
                            "probe_axis = [0.0, 0.0, -1.0]\nprobe_tilt = 12.0\n")


@pytest.fixture(scope="module")
def probe_file(tmp_path_factory):
    return built_by_the_command(tmp_path_factory.mktemp("probe"), PROBE_SCENE)


def test_a_probe_space_is_queried_with_the_probes_direction(probe_file):
    space = tactus.ConfigurationSpace(probe_file, "tricubic_hermite")
    assert space.level_count == 9
    probe = space.probe
    assert probe["tilt_levels"] == 3 and probe["max_tilt"] == pytest.approx(np.radians(12.0))
    np.testing.assert_allclose(probe["axis"], [[0.0, 0.0, -1.0]])
    directions = probe["directions"]
    assert directions.shape == (9, 3)
    np.testing.assert_allclose(directions[4], [0.0, 0.0, -1.0], atol=1e-15)  # the middle lean: the axis
    np.testing.assert_allclose(np.degrees(np.arccos(-directions[5, 2])), 12.0, rtol=1e-12)
    # At each level's own lean and its grid points, the stored forces.
    for k in range(9):
        level = space.level(k)
        assert level.probe is None and level.level_count == 1 and level.solved.all()
        forces, valid = space.force(level.points, directions[k])
        assert valid.all()
        scale = np.abs(level.point_forces).max()
        assert scale > 0.1
        np.testing.assert_allclose(forces, level.point_forces, rtol=0, atol=1e-12 * scale)
    # Halfway between two leans along the first tangent axis (6 degrees toward +x), the
    # quadratic Lagrange weights over that row of leans, -1/8, 3/4, 3/8.
    between = np.array([np.sin(np.radians(6.0)), 0.0, -np.cos(np.radians(6.0))])
    row = [space.level(k).point_forces for k in (3, 4, 5)]
    forces, valid = space.force(space.level(4).points, between)
    assert valid.all()
    np.testing.assert_allclose(forces, -0.125 * row[0] + 0.75 * row[1] + 0.375 * row[2], rtol=0, atol=1e-12)
    # One direction per point, and the direction's length does not matter.
    points = space.level(4).points[:2]
    one_each, _ = space.force(points, np.array([directions[5], 3.0 * directions[5]]))
    np.testing.assert_allclose(one_each, space.level(5).point_forces[:2], rtol=0, atol=1e-12)
    force, displacement, ok = space.shape(points[1], directions[5])
    assert ok and displacement.shape == (75, 3)
    np.testing.assert_allclose(force[0], space.level(5).point_forces[1], rtol=0, atol=1e-12)


def test_a_probe_space_gives_the_torque_on_the_probe(probe_file, space_file):
    space = tactus.ConfigurationSpace(probe_file, "tricubic_hermite")
    directions = space.probe["directions"]
    # At a leaning level's grid points, its stored torques; a leaning probe bends the block,
    # so they are not round-off.
    level = space.level(5)
    torques, valid = space.torque(level.points, directions[5])
    assert valid.all()
    scale = np.abs(level.point_torques).max()
    assert scale > 1e-4
    np.testing.assert_allclose(torques, level.point_torques, rtol=0, atol=1e-12 * scale)
    # Between leans, the same Lagrange weights as the force's.
    between = np.array([np.sin(np.radians(6.0)), 0.0, -np.cos(np.radians(6.0))])
    row = [space.level(k).point_torques for k in (3, 4, 5)]
    torques, valid = space.torque(space.level(4).points, between)
    assert valid.all()
    np.testing.assert_allclose(torques, -0.125 * row[0] + 0.75 * row[1] + 0.375 * row[2], rtol=0, atol=1e-12 * scale)
    # A patch of one node has no lever: the point space's torques are zero.
    point = tactus.ConfigurationSpace(space_file)
    torques, valid = point.torque(point.points)
    assert valid.all()
    np.testing.assert_array_equal(torques, 0.0)
    with pytest.raises(ValueError, match="needs the probe's direction"):
        space.torque(level.points[0])


def test_a_probe_space_refuses_queries_without_a_direction(probe_file, space_file):
    space = tactus.ConfigurationSpace(probe_file)
    x = space.level(4).points[0]
    with pytest.raises(ValueError, match="needs the probe's direction"):
        space.force(x)
    with pytest.raises(ValueError, match="finite and not zero"):
        space.force(x, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="one per point"):
        space.force(np.array([x, x]), np.zeros((3, 3)) + [0.0, 0.0, -1.0])
    with pytest.raises(ValueError, match="per lean"):
        space.point_forces
    with pytest.raises(IndexError):
        space.level(9)
    with pytest.raises(ValueError, match="takes no probe direction"):
        tactus.ConfigurationSpace(space_file).force(x, [0.0, 0.0, -1.0])


def test_probe_and_two_point_spaces_are_built_by_the_command(space_file, tmp_path):
    # build_space writes one level: a table with a probe or a second point is refused by name,
    # and a two-point file in ConfigurationSpace.
    probe = PROBE_SCENE
    with pytest.raises(tactus.InputError, match="has a probe: build_space builds point spaces"):
        tactus.build_space(tactus.parse_scene(probe, str(tmp_path / "probe.toml")), tmp_path / "p.h5")
    pair = SCENE.replace("max = [0.003, 0.003, 0.013]\n", "max = [0.003, 0.003, 0.013]\n"
                         "second_point = [0.02, 0.0, 0.01]\nsecond_min = [0.017, -0.003, 0.004]\n"
                         "second_max = [0.023, 0.003, 0.0101]\n")
    with pytest.raises(tactus.InputError, match="has a second point: build_space builds point spaces"):
        tactus.build_space(tactus.parse_scene(pair, str(tmp_path / "pair.toml")), tmp_path / "q.h5")
    assert not (tmp_path / "p.h5").exists() and not (tmp_path / "q.h5").exists()
    binary = os.environ["TACTUS_BINARY"]
    (tmp_path / "pair.toml").write_text(pair)
    subprocess.run([binary, "-q", "precompute", "pair.toml", "-o", "pair.h5", "--threads", "2"],
                   cwd=tmp_path, check=True, capture_output=True, env={**os.environ, "CI": "1"})
    with pytest.raises(tactus.InputError, match="a two-point space"):
        tactus.ConfigurationSpace(tmp_path / "pair.h5")


def test_stiffness_is_the_slope_of_the_hermite_force(space_file):
    # The stored ∂F/∂x against central differences of the tricubic Hermite force 1 µm either
    # side of an interior grid point: the Hermite interpolant takes the stored slope there.
    space = tactus.ConfigurationSpace(space_file, "tricubic_hermite")
    stiffness = space.point_stiffness
    assert stiffness.shape == (36, 3, 3)
    centre = 1 + 3 * (1 + 3 * 2)  # grid point (1, 1, 2)
    x = space.points[centre]
    slope = np.empty((3, 3))
    for k in range(3):
        d = np.zeros(3)
        d[k] = 1e-6
        plus, _ = space.force(x + d)
        minus, _ = space.force(x - d)
        slope[:, k] = (plus[0] - minus[0]) / 2e-6
    np.testing.assert_allclose(slope, stiffness[centre], rtol=0, atol=1e-5 * np.abs(stiffness[centre]).max())
    # Pressing down stiffens: the vertical force grows as the point goes down.
    assert stiffness[centre][2, 2] < 0.0


def test_a_refined_space_lists_its_added_points(tmp_path):
    model = tactus.parse_scene(SCENE + "refine_points = 19\n", str(tmp_path / "block.toml"))
    stats = tactus.build_space(model, tmp_path / "refined.h5", threads=1)
    assert stats["points"] == 36 + 19 and stats["solved"] == 36 + 19
    space = tactus.ConfigurationSpace(tmp_path / "refined.h5", "tricubic_hermite")
    assert space.points.shape == (55, 3) and space.point_forces.shape == (55, 3)
    assert space.point_stiffness.shape == (55, 3, 3)
    # The added points lie half a spacing off the grid.
    added = space.points[36:]
    offsets = (added - space.points[0]) / (0.5 * space.spacing)
    np.testing.assert_allclose(offsets, np.round(offsets), atol=1e-9)
    assert (np.abs(np.round(offsets)) % 2 == 1).any(axis=1).all()
