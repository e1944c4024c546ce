"""A force algorithm written in Python, run as an overlay of a device's haptic loop."""
import numpy as np
import pytest

import tactus


def run(model, algorithms=None, frames=3000):
    sim = tactus.Simulation(model, force_algorithms=algorithms or {})
    out, touching = np.empty((frames, 3)), np.empty(frames, dtype=bool)
    for k in range(frames):
        sim.step()
        out[k], touching[k] = sim.forces[0], sim.contacts[0]
    return out, touching


@pytest.fixture(scope="module")
def model():
    return tactus.default_scene()


def test_its_force_is_sent_every_frame_with_the_contact_force(model):
    calls = []

    def push(t, position, velocity, contact_force, touching):
        calls.append((t, position, touching))
        return (0.0, 0.0, 0.5)

    plain, plain_touching = run(model)
    pushed, pushed_touching = run(model, {"hand": push})
    # Before the press touches, the hand feels the overlay alone: 0.5 N up, every frame. Once
    # it touches, the safety layer's onset ramp and the passivity control act on the sum, as for
    # any overlay (the pulse's), so the two runs no longer differ by exactly the overlay.
    first_touch = int(np.argmax(plain_touching))
    assert first_touch > 100
    np.testing.assert_allclose(pushed[:first_touch] - plain[:first_touch],
                               np.tile([0.0, 0.0, 0.5], (first_touch, 1)), rtol=0, atol=1e-12)
    assert np.array_equal(plain_touching, pushed_touching)
    times = np.array([c[0] for c in calls])
    assert len(calls) == 3000
    np.testing.assert_allclose(np.diff(times), 1.0 / model.rates["haptic"], rtol=1e-9)
    seen_touching = np.array([c[2] for c in calls])
    assert seen_touching.any() and not seen_touching.all()  # it sees the press touch and let go


def test_a_virtual_wall_written_in_python(model):
    wall_z, k = None, 300.0

    def wall(t, position, velocity, contact_force, touching):
        nonlocal wall_z
        if wall_z is None:
            wall_z = position[2] - 0.002  # 2 mm below where the tool starts
        depth = wall_z - position[2]
        return (0.0, 0.0, k * depth if depth > 0 else 0.0)

    plain, _ = run(model)
    walled, _ = run(model, {"hand": wall})
    extra = walled[:, 2] - plain[:, 2]
    assert extra.min() >= -1e-12 and extra.max() > 0.1  # the wall pushes back, never pulls


def test_its_exception_is_raised_by_step(model):
    def fails(t, *_):
        if t > 0.5:
            raise ValueError("prototype broke")
        return (0.0, 0.0, 0.0)

    sim = tactus.Simulation(model, force_algorithms={"hand": fails})
    with pytest.raises(ValueError, match="prototype broke"):
        sim.step(2000)
    assert 500 <= sim.frame <= 502  # it stopped at the frame that raised
    bad = tactus.Simulation(model, force_algorithms={"hand": lambda *_: "up"})
    with pytest.raises(TypeError, match="3 numbers"):
        bad.step()
    with pytest.raises(KeyError):
        tactus.Simulation(model, force_algorithms={"no such device": lambda *_: (0, 0, 0)})


def test_a_nan_never_reaches_the_device(model):
    out, _ = run(model, {"hand": lambda *_: (float("nan"), 0.0, 0.0)}, frames=200)
    assert np.isfinite(out).all()
