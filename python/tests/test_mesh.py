"""Meshes read and written from Python with the engine's readers and writers."""
import numpy as np
import pytest

import tactus

# A unit cube split into five positively oriented tets, two regions.
CUBE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 1, 1]],
                dtype=float) * 0.01
TETS = np.array([[0, 1, 2, 4], [1, 3, 2, 7], [1, 2, 4, 7], [1, 7, 4, 5], [2, 4, 7, 6]])


def signed_volumes(vertices, tets):
    a, b, c, d = (vertices[tets[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6.0


@pytest.mark.parametrize("suffix", [".vtu", ".vtk", ".msh", ".node"])
def test_a_volume_written_reads_back_the_same(tmp_path, suffix):
    assert (signed_volumes(CUBE, TETS) > 0).all()
    path = tmp_path / ("cube" + suffix)
    tactus.write_mesh(path, CUBE, tets=TETS, regions=[1, 1, 2, 2, 2])
    mesh = tactus.read_mesh(path)
    volume = mesh["volume"]
    assert volume is not None
    np.testing.assert_array_equal(volume["vertices"], CUBE)  # these writers keep every digit
    np.testing.assert_array_equal(volume["tets"], TETS)
    assert signed_volumes(volume["vertices"], volume["tets"]).sum() == pytest.approx(1e-6, rel=1e-12)
    if suffix != ".vtk":  # legacy VTK carries no regions in this writer
        np.testing.assert_array_equal(volume["regions"], [1, 1, 2, 2, 2])


def test_a_surface_written_reads_back(tmp_path):
    triangles = np.array([[0, 1, 2], [0, 2, 3]])
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    for suffix in (".obj", ".stl", ".ply", ".off"):
        path = tmp_path / ("square" + suffix)
        tactus.write_mesh(path, square, triangles=triangles)
        surface = tactus.read_mesh(path)["surface"]
        assert surface["triangles"].shape == (2, 3), suffix
        assert np.allclose(surface["vertices"][surface["triangles"]].reshape(-1, 3).sum(axis=0),
                           square[triangles].reshape(-1, 3).sum(axis=0)), suffix


def test_arrays_are_read_only_views_that_keep_the_mesh_alive(tmp_path):
    path = tmp_path / "cube.vtu"
    tactus.write_mesh(path, CUBE, tets=TETS)
    tets = tactus.read_mesh(path)["volume"]["tets"]  # the dict is dropped at once
    assert tets.dtype == np.int32 and not tets.flags.writeable and not tets.flags.owndata
    with pytest.raises(ValueError):
        tets[0, 0] = 3
    np.testing.assert_array_equal(tets, TETS)


def test_a_bundled_mesh_reads(scenes):
    meshes = sorted((scenes / "meshes").glob("*"))
    readable = [m for m in meshes if m.suffix in (".msh", ".vtu", ".vtk", ".obj", ".stl", ".ply", ".off")]
    assert readable, "no bundled mesh to read"
    mesh = tactus.read_mesh(readable[0])
    assert mesh["volume"] is not None or mesh["surface"] is not None


def test_bad_files_raise_input_error_with_the_place(tmp_path):
    bad = tmp_path / "bad.msh"
    bad.write_text("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n")
    with pytest.raises(tactus.InputError) as e:
        tactus.read_mesh(bad)
    assert e.value.file.endswith("bad.msh")
    with pytest.raises(tactus.InputError):
        tactus.read_mesh(tmp_path / "mesh.unknown")
    with pytest.raises(tactus.InputError):
        tactus.read_mesh(tmp_path / "missing.vtu")


def test_bad_arrays_raise_before_anything_is_written(tmp_path):
    path = tmp_path / "out.vtu"
    with pytest.raises(IndexError):
        tactus.write_mesh(path, CUBE, tets=[[0, 1, 2, 99]])
    with pytest.raises(ValueError):
        tactus.write_mesh(path, CUBE, tets=TETS[:, [1, 0, 2, 3]])  # every tet turned inside out
    with pytest.raises(ValueError):
        tactus.write_mesh(path, CUBE[:, :2], tets=TETS)
    with pytest.raises(ValueError):
        tactus.write_mesh(path, CUBE)  # neither tets nor triangles
    with pytest.raises(ValueError):
        tactus.write_mesh(path, CUBE, tets=TETS, regions=[1, 2])
    assert not path.exists()
