"""State written from numpy is the state the engine steps; the arrays are
copies with the shapes and dtypes the docs give."""

import gc

import numpy as np
import pytest

import sprung

# Two free particles under gravity; dt, g and the masses are powers of two
# so that a step of symplectic Euler is exact in binary:
# v1 = v0 + g dt, x1 = x0 + v1 dt, with no rounding at all.
PAIR = """
[sim]
dt = 0.125
integrator = "symplectic_euler"
gravity = [0, -8, 0]
[[body]]
name = "pair"
particles = [[0, 0, 0], [1, 0, 0]]
masses = [2, 4]
"""

# The same pair off the plane z = 0: a 3D scene.
PAIR_3D = PAIR.replace("[[0, 0, 0], [1, 0, 0]]", "[[0, 0, 1], [1, 0, 0]]")


def test_state_written_from_numpy_is_stepped():
    world = sprung.loads(PAIR)
    assert world.dimension == 2
    world.positions = np.array([[0.5, 2.0], [-1.0, 0.25]])
    world.velocities = [[1, 0], [0, 2]]
    world.step()
    dt, g = 0.125, -8.0
    v = np.array([[1.0, 0.0 + g * dt], [0.0, 2.0 + g * dt]])
    x = np.array([[0.5, 2.0], [-1.0, 0.25]]) + v * dt
    assert np.array_equal(world.velocities, v)
    assert np.array_equal(world.positions, x)
    assert (world.steps, world.time) == (1, 0.125)


def test_three_dimensional_arrays_and_external_force():
    world = sprung.loads(PAIR_3D)
    assert world.dimension == 3
    assert world.positions.shape == (2, 3) and world.positions.dtype == np.float64
    world.external_forces = [[4, 0, 8], [0, 0, 0]]
    world.step(2)
    # a = F/m + g on particle 0: (2, -8, 4) m/s², exact in binary, so two
    # steps give v = 2 a dt.
    assert np.array_equal(world.velocities[0], [0.5, -2.0, 1.0])
    assert np.array_equal(world.velocities[1], [0.0, -2.0, 0.0])
    assert np.array_equal(world.external_forces, [[4, 0, 8], [0, 0, 0]])
    world.external_forces = None
    assert not world.external_forces.any()
    world.step()
    assert world.velocities[0][0] == 0.5  # no push any more along x


def test_centroid_follows_the_positions(scenes):
    world = sprung.load(scenes / "ball3d.toml")
    ball = world.body("ball")
    before = ball.centroid
    shift = np.array([0.5, -0.25, 2.0])
    world.positions = world.positions + shift
    # The centroid is the mass-weighted mean: shifting every particle by
    # d shifts it by d, up to the rounding of 162 additions (1e-15 m).
    assert np.allclose(ball.centroid, before + shift, rtol=0, atol=1e-14)
    indices = ball.indices
    masses = world.masses[indices]
    mean = (world.positions[indices] * masses[:, None]).sum(0) / masses.sum()
    assert np.allclose(ball.centroid, mean, rtol=0, atol=1e-14)


def test_a_flat_surface_is_three_dimensional(scenes):
    # billow.toml's sheets start in z = 0 with no gravity, and its wind
    # blows along z: a surface is a 3D body.
    world = sprung.load(scenes / "billow.toml")
    assert world.dimension == 3
    world.step(200)
    assert np.abs(world.positions[:, 2]).max() > 0


def test_shapes_and_dtypes(scenes):
    world = sprung.load(scenes / "cloth.toml")
    n, m = len(world.masses), len(world.rest_lengths)
    assert world.positions.shape == (n, 3)
    assert world.velocities.shape == (n, 3)
    assert world.pinned.dtype == np.bool_ and world.pinned.shape == (n,)
    assert world.pinned.sum() == 2  # hung from two corners
    assert world.springs.shape == (m, 2) and world.springs.dtype == np.int64
    ends = world.positions[world.springs]
    lengths = np.linalg.norm(ends[:, 0] - ends[:, 1], axis=1)
    # At rest at the start: each spring's length is its rest length (to
    # the rounding of the grid's coordinates).
    assert np.allclose(lengths, world.rest_lengths, rtol=1e-12, atol=0)
    assert world.bodies == ["cloth"]


def test_bad_arrays_are_refused_and_change_nothing():
    world = sprung.loads(PAIR)
    before = world.positions
    with pytest.raises(ValueError, match=r"shape \[2, 3\]|\(2, 2\)"):
        world.positions = np.zeros((2, 3))
    with pytest.raises(ValueError, match="not finite"):
        world.positions = [[0, 0], [np.nan, 0]]
    assert np.array_equal(world.positions, before)
    pinned = sprung.loads(PAIR.replace('masses = [2, 4]', 'masses = [2, 4]\npinned = [1]'))
    with pytest.raises(ValueError, match="pinned"):
        pinned.velocities = [[0, 0], [1, 0]]
    with pytest.raises(ValueError, match="dt"):
        world.dt = -1.0


def test_arrays_are_copies_that_outlive_their_world(scenes):
    world = sprung.load(scenes / "rope.toml")
    positions = world.positions
    positions[0] = 99.0  # a copy: the world does not see it
    assert world.positions[0][0] != 99.0
    assert not np.shares_memory(world.positions, world.positions)
    body = world.body("rope")
    expected = world.positions.copy()
    centroid = body.centroid
    del world
    gc.collect()
    # The Body keeps its World alive.
    assert body.name == "rope" and np.array_equal(body.centroid, centroid)
    del body
    gc.collect()
    # With the World gone, the arrays are still whole: each is its own.
    assert positions.shape == expected.shape
    assert np.array_equal(positions[1:], expected[1:])


def test_gas_nrt_can_be_set_between_steps(scenes):
    world = sprung.load(scenes / "ball2d.toml")
    ball = world.body("ball")
    world.step(10)
    ball.nrt = 3.0
    assert ball.nrt == 3.0
    world.step(10)
    assert ball.nrt == 3.0
    # P = nRT / V, with the exact enclosed area.
    assert ball.pressure == pytest.approx(3.0 / ball.volume, rel=1e-15)
    with pytest.raises(ValueError, match="no gas"):
        world.body("no_gas").nrt = 1.0
    with pytest.raises(KeyError, match="no body named"):
        world.body("nothing")


def test_integrator_switch_and_save_load_state(tmp_path, scenes):
    world = sprung.load(scenes / "rope.toml")
    world.integrator = "rk4"
    world.step(20)
    path = tmp_path / "rope.state"
    world.save_state(path)
    resumed = sprung.load(scenes / "rope.toml", state=path)
    resumed.integrator = "rk4"
    world.step(30)
    resumed.load_state(path)
    resumed.step(30)
    assert resumed.steps == world.steps == 50
    assert np.array_equal(resumed.positions, world.positions)
    copy = world.copy()
    world.step(5)
    copy.step(5)
    assert np.array_equal(copy.velocities, world.velocities)
    gas = sprung.load(scenes / "ball2d.toml")
    gas.body("ball").nrt = 7.0
    assert gas.copy().body("ball").nrt == 7.0  # set from Python, kept
    with pytest.raises(sprung.StateError):
        sprung.load(scenes / "ball2d.toml", state=path)
    with pytest.raises(ValueError, match="integrator"):
        world.integrator = "leapfrog"
