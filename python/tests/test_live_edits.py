"""Parameters edited while a Simulation steps: Young's modulus, damping, a contact's stiffness."""
import numpy as np
import pytest

import tactus


def forces(model, edit=None, frames=3000):
    """The default scene's scripted press: the hand's force per frame, after edit(sim)."""
    sim = tactus.Simulation(model)
    if edit:
        edit(sim)
    out = np.empty((frames, 3))
    for k in range(frames):
        sim.step()
        out[k] = sim.forces[0]
    return out


@pytest.fixture(scope="module")
def model():
    return tactus.default_scene()


@pytest.fixture(scope="module")
def plain(model):
    return forces(model)


def test_a_stiffer_body_pushes_back_harder(model, plain):
    body = model.bodies[0]
    stiffer = forces(model, lambda s: s.set_material(body.name, 4 * model.material_of(body).young_modulus, from_time=0.0))
    peak, peak_stiffer = np.linalg.norm(plain, axis=1).max(), np.linalg.norm(stiffer, axis=1).max()
    assert peak > 1.0  # the press reaches the body
    assert peak_stiffer > 1.2 * peak


def test_an_edit_applies_from_its_time_and_is_reproducible(model, plain):
    body = model.bodies[0]
    at = 2.0  # [s]: frame 2000 at 1 kHz is the first one after it
    e = model.material_of(body).young_modulus
    edit = lambda s: s.set_material(body.name, 0.25 * e, damping=5.0, from_time=at)  # noqa: E731
    first, second = forces(model, edit), forces(model, edit)
    assert np.array_equal(first, second)  # lockstep: the same bits
    rate = model.rates["haptic"]
    before = int(at * rate) - 1
    assert np.array_equal(first[:before], plain[:before])
    assert not np.array_equal(first[before + 5:], plain[before + 5:])


def test_a_softer_coupling_renders_less_force(model, plain):
    soft = forces(model, lambda s: s.set_surface(0, 100.0))
    assert np.linalg.norm(soft, axis=1).max() < 0.5 * np.linalg.norm(plain, axis=1).max()


def test_bad_edits_raise(model, scenes):
    femoral = tactus.Simulation(tactus.load_scene(scenes / "femoral.toml"))
    with pytest.raises(tactus.InputError, match="no material that can be edited"):
        femoral.set_material("femur", 1e5)  # rigid
    sim = tactus.Simulation(model)
    with pytest.raises(IndexError):
        sim.set_material(len(model.bodies), 1e5)
    with pytest.raises(KeyError):
        sim.set_material("no such body", 1e5)
    with pytest.raises(tactus.InputError, match="positive"):
        sim.set_material(0, -1.0)
    with pytest.raises(tactus.InputError):
        sim.set_surface(0, 1e9)  # above the device's max_stiffness
    with pytest.raises(tactus.InputError):
        sim.set_surface(0, 100.0, static_friction=0.2, kinetic_friction=0.5)  # kinetic > static
