"""Each exception with its fields, from real bad input."""

import pytest

import sprung

ROPE = """[sim]
dt = 1e-3
steps = 10

[[body]]
name = "rope"
rope = { particles = 8, length = 1.0 }
stiffness = 100.0
"""


def test_a_misspelt_key_names_its_line_and_field(tmp_path):
    path = tmp_path / "rope.toml"
    path.write_text(ROPE.replace("stiffness", "stifness"))
    with pytest.raises(sprung.SceneError) as caught:
        sprung.load(path)
    error = caught.value
    assert isinstance(error, ValueError)
    assert error.path == str(path)
    assert error.line == 8
    assert error.field == "stifness"
    assert str(error).startswith(f"{path}:8: unknown field `stifness`")


def test_the_message_is_the_command_lines(tmp_path, cli):
    path = tmp_path / "rope.toml"
    path.write_text(ROPE.replace("particles = 8", "particles = 1"))
    with pytest.raises(sprung.SceneError) as caught:
        sprung.load(path)
    import subprocess
    from conftest import sprung_command
    done = subprocess.run([sprung_command(), "check", str(path)], capture_output=True, text=True)
    assert done.returncode == 1
    assert done.stderr.strip() == f"error: {caught.value}"


def test_a_blow_up_gives_its_step_and_stable_dt(tmp_path):
    # A stiff spring stepped by explicit Euler far beyond its stable step:
    # the state grows without bound within a few hundred steps.
    text = ROPE.replace("dt = 1e-3", 'dt = 0.05\nintegrator = "euler"').replace(
        "stiffness = 100.0", "stiffness = 1e4")
    world = sprung.loads(text)
    with pytest.raises(sprung.BlowUp) as caught:
        world.step(10_000)
    error = caught.value
    assert isinstance(error, RuntimeError)
    assert 1 <= error.step <= 10_000
    assert error.time == pytest.approx(error.step * 0.05, rel=1e-12)
    assert 0 < error.stable_dt < 0.05
    assert "blew up" in str(error)
    # From run(): the rows before it come with the exception, all finite.
    with pytest.raises(sprung.BlowUp) as caught:
        sprung.run(sprung.loads(text), steps=10_000, every=1)
    rows = caught.value.diagnostics
    assert len(rows["step"]) == caught.value.step  # rows 0 .. step-1
    assert all(map(lambda v: v == v and abs(v) != float("inf"), rows["total"]))


def test_a_mesh_error_names_the_mesh_file_and_line(tmp_path):
    mesh = tmp_path / "broken.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n")
    path = tmp_path / "scene.toml"
    path.write_text('[sim]\ndt = 1e-3\n\n[[body]]\nname = "cloth"\nmesh = "broken.obj"\n')
    with pytest.raises(sprung.MeshError) as caught:
        sprung.load(path)
    error = caught.value
    assert isinstance(error, sprung.SceneError)
    assert error.path == str(mesh)
    assert error.line == 4
    assert error.scene == str(path) and error.scene_line == 6
    assert "broken.obj:4" in str(error)


def test_a_damaged_state_file_is_refused(tmp_path):
    world = sprung.loads(ROPE)
    path = tmp_path / "x.state"
    world.save_state(path)
    data = bytearray(path.read_bytes())
    data[40] ^= 0xFF
    path.write_bytes(bytes(data))
    before = world.positions
    with pytest.raises(sprung.StateError) as caught:
        world.load_state(path)
    assert caught.value.path == str(path)
    assert (world.positions == before).all()
