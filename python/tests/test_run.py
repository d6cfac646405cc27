"""`sprung.run` gives the numbers the command line writes, bit for bit."""

import numpy as np
import pytest

import sprung


# A 2D gas ball, a 3D gas ball and a cloth, each run long enough for the
# gas and the contacts to act, recorded at the command line's own rate
# and at every 7th step.
CASES = [("ball2d", 400, None), ("ball3d", 300, 7), ("cloth", 300, None)]


@pytest.mark.parametrize("name,steps,every", CASES)
def test_run_is_the_command_line_bit_for_bit(tmp_path, cli, scenes, name, steps, every):
    scene = scenes / f"{name}.toml"
    args = ["run", scene, "--out", tmp_path / "cli", "--steps", steps, "--quiet"]
    if every:
        args += ["--every", every]
    cli(*args)
    written = (tmp_path / "cli" / "diagnostics.csv").read_text()
    table = sprung.run(scene, steps=steps, every=every, out=tmp_path / "py")
    # The same text, so the same numbers: every cell is written with the
    # shortest digits that read back to its float64.
    assert table.csv == written
    assert (tmp_path / "py" / "diagnostics.csv").read_text() == written
    lines = written.splitlines()
    names = lines[0].split(",")
    assert list(table) == names
    for k, column in enumerate(names):
        cells = [line.split(",")[k] for line in lines[1:]]
        if column == "solver_preconditioner":
            # A name, not a number: the cells as they are.
            assert list(table[column]) == cells
            continue
        expected = np.array([float(c) if c else np.nan for c in cells])
        got = table[column].astype(np.float64)
        assert np.array_equal(got, expected, equal_nan=True), column
    assert table["step"].dtype == np.int64
    assert table["step"][-1] == steps


def test_run_on_a_world_goes_on_from_its_state(scenes):
    world = sprung.load(scenes / "ball2d.toml")
    alone = sprung.load(scenes / "ball2d.toml")
    table = sprung.run(world, steps=50, every=10)
    alone.step(50)
    assert world.steps == 50
    assert np.array_equal(world.positions, alone.positions)
    assert list(table["step"]) == [0, 10, 20, 30, 40, 50]
    assert table["total"][-1] == alone.energies()["total"]


def test_energies_are_the_tables_energy_columns(scenes):
    world = sprung.load(scenes / "ball3d.toml")
    world.step(100)
    table = sprung.run(world, steps=1)
    energies = world.energies()
    assert list(energies)[:5] == ["kinetic", "spring", "gravity", "gas", "total"]
    for name, value in energies.items():
        assert table[name][-1] == value, name


def test_the_solvers_choice_is_a_column_of_names(scenes):
    # The stiff cloth under implicit Euler: auto's preconditioner by name,
    # from the first step's on (the first row has no step behind it), and
    # the factorisations of each step as numbers.
    table = sprung.run(scenes / "stiff_cloth.toml", steps=20, every=1)
    chosen = table["solver_preconditioner"]
    assert chosen.dtype.kind == "U"
    assert chosen[0] == ""
    assert set(chosen[1:]) <= {"jacobi", "stiffness"}
    assert "stiffness" in set(chosen)
    refactorings = table["solver_refactorings"]
    assert np.isnan(refactorings[0])
    assert refactorings[1:].sum() >= 1


def test_integrator_and_time_options(scenes):
    table = sprung.run(scenes / "rope.toml", time=0.01, integrator="rk4", every=1)
    world = sprung.load(scenes / "rope.toml")
    assert len(table["step"]) == round(0.01 / world.dt) + 1
    with pytest.raises(ValueError, match="unknown integrator|integrator"):
        sprung.run(scenes / "rope.toml", steps=1, integrator="leapfrog")
    with pytest.raises(ValueError, match="steps or time"):
        sprung.run(scenes / "rope.toml", steps=1, time=1.0)


def test_to_pandas(scenes):
    pd = pytest.importorskip("pandas")
    table = sprung.run(scenes / "rope.toml", steps=20, every=5)
    frame = table.to_pandas()
    assert isinstance(frame, pd.DataFrame)
    assert list(frame.columns) == list(table)


def test_set_is_the_command_lines_set_bit_for_bit(tmp_path, cli, scenes):
    scene = scenes / "ball2d.toml"
    cli("run", scene, "--out", tmp_path / "cli", "--steps", 300, "--quiet",
        "--set", "sim.dt=2.5e-4", "--set", "body.ball.gas.nrt=150.0",
        "--set", "collider.0.friction=0.5", "--set", "sim.integrator=rk4")
    written = (tmp_path / "cli" / "diagnostics.csv").read_text()
    overrides = {"sim.dt": 2.5e-4, "body.ball.gas.nrt": np.float64(150.0),
                 "collider.0.friction": 0.5, "sim.integrator": "rk4"}
    table = sprung.run(scene, steps=300, set=overrides)
    assert table.csv == written
    world = sprung.load(scene, set=overrides)
    assert (world.dt, world.integrator) == (2.5e-4, "rk4")
    world.step(round(1.0 / world.dt))  # past the gas's 0.5 s ramp
    assert world.body("ball").nrt == 150.0


def test_a_bad_override_names_its_key(scenes):
    with pytest.raises(sprung.SceneError) as caught:
        sprung.load(scenes / "ball2d.toml", set={"body.ball.stifness": 10.0})
    assert caught.value.field == "body.ball.stifness"
    assert "stifness" in str(caught.value)
    with pytest.raises(sprung.SceneError, match="no body named|bodies"):
        sprung.load(scenes / "ball2d.toml", set={"body.nothing.stiffness": 10.0})
    with pytest.raises(sprung.SceneError) as caught:
        sprung.load(scenes / "ball2d.toml", set={"sim.dt": "fast"})
    assert caught.value.field == "sim.dt"
    with pytest.raises(ValueError, match="no TOML form"):
        sprung.load(scenes / "ball2d.toml", set={"sim.dt": object()})


def test_frames_are_the_command_lines(tmp_path, cli, scenes):
    scene = scenes / "ball3d.toml"
    cli("run", scene, "--out", tmp_path / "cli", "--steps", 100, "--every", 25,
        "--format", "vtu", "--quiet")
    sprung.run(scene, steps=100, every=25, out=tmp_path / "py", format="vtu")
    names = sorted(p.name for p in (tmp_path / "cli" / "frames").iterdir())
    assert names == sorted(p.name for p in (tmp_path / "py" / "frames").iterdir())
    assert len([n for n in names if n.endswith(".vtu")]) == 5  # rows 0, 25, 50, 75, 100
    for name in names:
        assert (tmp_path / "cli" / "frames" / name).read_bytes() == \
            (tmp_path / "py" / "frames" / name).read_bytes(), name
    with pytest.raises(ValueError, match="out="):
        sprung.run(scene, steps=1, format="vtu")
