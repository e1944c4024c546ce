"""Scenes changed from Python before they are compiled (Model.with_changes)."""
import subprocess

import numpy as np
import pytest

import tactus


@pytest.fixture
def default(scenes):
    return tactus.load_scene(scenes / "default.toml")


def test_no_change_runs_the_same_bits(scenes):
    # A scene with a base (S2 on the femoral patient) too: its base is merged into the text.
    for name in ("default.toml", "femoral_s2_palpation.toml"):
        model = tactus.load_scene(scenes / name)
        same = model.with_changes({})
        assert "base =" not in same.text
        a, b = tactus.run(model, 1.0), tactus.run(same, 1.0)
        for device in a.devices:
            assert np.array_equal(a.frames(device)["force"], b.frames(device)["force"]), name


def test_values_change_and_tables_merge(default):
    material = default.materials[0].name
    changed = default.with_changes({
        f"materials.{material}.young_modulus": 4 * default.materials[0].young_modulus,
        "bodies.block.mesh": {"cells": [5, 5, 2]},   # merged: the generator and size stay
        "scene.description": "a stiffer, coarser block",
        "rates.haptic": 2000,
    })
    assert changed.materials[0].young_modulus == 4 * default.materials[0].young_modulus
    assert changed.bodies[0].node_count == 6 * 6 * 3 < default.bodies[0].node_count
    assert changed.description == "a stiffer, coarser block"
    assert changed.rates["haptic"] == 2000.0
    assert default.materials[0].young_modulus == 30e3  # the original is untouched
    # The text is a whole scene: parsed again on its own it gives the same model.
    again = tactus.parse_scene(changed.text, "again.toml")
    assert again.bodies[0].node_count == changed.bodies[0].node_count
    peak = [np.abs(tactus.run(m, 3.0).frames(0)["force"]).max() for m in (default, changed)]
    assert peak[1] > peak[0]


def test_a_changed_scene_replays_from_its_recording(default, tactus_binary, tmp_path):
    record = tmp_path / "changed.tacrec"
    tactus.run(default.with_changes({"materials.soft_tissue.young_modulus": 60e3}), 1.0, record=record)
    done = subprocess.run([tactus_binary, "replay", record], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "forces identical bit for bit" in done.stdout


def test_bad_changes_say_what_is_wrong(default):
    with pytest.raises(KeyError, match="no table 'tissue' there .*soft_tissue"):
        default.with_changes({"materials.tissue.young_modulus": 1.0})
    with pytest.raises(tactus.InputError, match="did you mean 'young_modulus'"):
        default.with_changes({"materials.soft_tissue.young_modulu": 1.0})
    with pytest.raises(tactus.InputError, match="young_modulus"):
        default.with_changes({"materials.soft_tissue.young_modulus": -5.0})
    with pytest.raises(TypeError, match="bool, int, float, str, list or dict"):
        default.with_changes({"materials.soft_tissue.young_modulus": None})
    with pytest.raises(KeyError):
        default.with_changes({"materials..young_modulus": 1.0})
