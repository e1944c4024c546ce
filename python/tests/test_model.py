"""Loading scenes and inspecting the Model; InputError with the file, line and reason."""
import gc

import numpy as np
import pytest

import tactus


def test_import_names_the_version():
    assert tactus.__version__.count(".") == 2


def test_liver_scene_parts(scenes):
    m = tactus.load_scene(scenes / "liver.toml")
    assert m.name == "liver"
    assert m.source.endswith("liver.toml")
    assert "[scene]" in m.text
    assert m.rates["haptic"] == 1000.0
    (body,) = m.bodies
    assert body.kind == "fem" and body.volumetric
    assert body.node_count == body.rest_positions.shape[0] > 100
    assert body.tets.shape == (body.tet_count, 4)
    assert body.triangles.shape == (body.triangle_count, 3)
    assert body.tets.max() < body.node_count
    material = m.material_of(body)
    assert material.name == m.materials[body.material_index].name
    assert material.model == "neo_hookean"
    assert material.young_modulus > 0 and 0 < material.poisson_ratio < 0.5
    # Elastic constants are all filled in: mu = E / (2 (1 + nu)).
    assert material.shear_modulus == pytest.approx(material.young_modulus / (2 * (1 + material.poisson_ratio)))
    assert [d.name for d in m.devices] == ["hand"]
    assert m.tools[0].kind == "sphere" and m.tools[0].radius > 0
    assert m.tools[0].device_indices == [0]
    assert m.body("liver").name == "liver"
    with pytest.raises(KeyError):
        m.body("spleen")
    assert "liver" in m.summary()


def test_femoral_scene_has_layers_and_two_devices(scenes):
    m = tactus.load_scene(scenes / "femoral_s3_needle.toml")
    assert {d.name for d in m.devices} == {"hand", "needle"}
    kinds = {b.kind for b in m.bodies}
    assert "embedded" in kinds and "fem" in kinds
    assert {t.kind for t in m.tools} >= {"needle"}


def test_arrays_are_read_only_views_that_keep_the_model_alive(scenes):
    m = tactus.load_scene(scenes / "liver.toml")
    rest = m.bodies[0].rest_positions
    again = m.bodies[0].rest_positions
    assert not rest.flags.writeable and not rest.flags.owndata
    assert np.shares_memory(rest, again)  # the same engine memory, not a copy each time
    first = rest.copy()
    del m, again
    gc.collect()
    np.testing.assert_array_equal(rest, first)  # still valid: the array holds the model
    with pytest.raises(ValueError):
        rest[0, 0] = 1.0


def test_parse_scene_and_default_scene():
    m = tactus.default_scene()
    assert m.bodies and m.devices
    again = tactus.parse_scene(m.text, "copy.toml")
    assert again.source == "copy.toml"
    assert [b.node_count for b in again.bodies] == [b.node_count for b in m.bodies]


def test_input_error_carries_file_line_and_reason():
    text = "[scene]\nname = 3\n"
    with pytest.raises(tactus.InputError) as info:
        tactus.parse_scene(text, "bad.toml")
    e = info.value
    assert isinstance(e, ValueError)
    assert e.file == "bad.toml" and e.line == 2 and e.column == 8
    assert "expected a string" in e.reason
    assert str(e) == f"bad.toml:2:8: {e.reason}"


def test_missing_file_raises_input_error(tmp_path):
    with pytest.raises(tactus.InputError) as info:
        tactus.load_scene(tmp_path / "absent.toml")
    assert info.value.file.endswith("absent.toml")


def test_file_access_can_be_refused(scenes):
    text = (scenes / "skin_patch.toml").read_text()
    with pytest.raises(tactus.InputError):
        tactus.parse_scene(text, str(scenes / "skin_patch.toml"), allow_file_access=False)
    assert tactus.parse_scene(text, str(scenes / "skin_patch.toml")).bodies
