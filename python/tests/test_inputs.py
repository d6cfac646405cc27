"""One input gate for every door: the scene files Python reads (``load``,
``run``, ``sweep``, ``python -m sprung.sweep``) pass the command line's
limits (a regular file, at most 16 MiB or ``SPRUNG_MAX_INPUT_BYTES``,
UTF-8) and are refused with its very words as ``sprung.SceneError``; scene
text in memory (``loads``) has the same size limit; ``set=`` values and
keys are bounded; a state is never written through a link, FIFO or device.
"""

import json
import os
import subprocess
import sys

import pytest

import sprung
from sprung import _native

# The words of the gate (crates/sprung-io/src/input.rs), after "PATH: ".
NOT_REGULAR = "cannot read the scene file: not a regular file (a device, pipe or folder is not read)"
LIMIT = 16 << 20  # bytes: DEFAULT_MAX_SCENE_BYTES


def too_large(size, limit=LIMIT):
    """The gate's words for a scene file of `size` bytes over `limit`."""
    return (f"cannot read the scene file: {size} bytes is more than the {limit} bytes an "
            "input file may have (set SPRUNG_MAX_INPUT_BYTES to raise the limit)")


SCENE = '[sim]\ndt = 1e-3\nsteps = 2\n\n[[body]]\nname = "a"\nparticles = [[0.0, 0.0]]\n'


def big_scene():
    """A scene that loads, padded by a comment to 17 MiB (over the 16 MiB
    limit): only the limit refuses it."""
    return SCENE + "#" * (17 << 20) + "\n"


# Every door of the package that reads a scene file, each given the file
# and a folder to write into.
DOORS = {
    "load": lambda path, out: sprung.load(path),
    "load(set=)": lambda path, out: sprung.load(path, set={"sim.dt": 1e-3}),
    "run": lambda path, out: sprung.run(path, steps=2),
    "run(out=)": lambda path, out: sprung.run(path, steps=2, out=out),
    "run(set=)": lambda path, out: sprung.run(path, steps=2, set={"sim.dt": 1e-3}),
    "sweep": lambda path, out: sprung.sweep(path, grid={"sim.dt": [1e-3, 2e-3]}, steps=2,
                                            out=out, progress=False),
    "read_scene": lambda path, out: _native.read_scene(path),
}


def refused_everywhere(path, message, tmp_path):
    """Assert that every door refuses the scene file `path` with
    `PATH: message`, as SceneError naming it, and writes nothing."""
    for name, door in DOORS.items():
        out = tmp_path / f"out-{name}"
        with pytest.raises(sprung.SceneError) as caught:
            door(str(path), out)
        assert str(caught.value) == f"{path}: {message}", name
        assert caught.value.path == str(path), name
        # Refused before any run: no folder, no sweep.csv, no runs.
        assert not out.exists(), name


def test_a_device_is_refused_by_every_door(tmp_path):
    # /dev/zero never ends: read, it would fill the memory. Every door
    # refuses it by its type, before a byte is read.
    refused_everywhere("/dev/zero", NOT_REGULAR, tmp_path)
    # Behind a link, and a folder, the same.
    link = tmp_path / "zero.toml"
    link.symlink_to("/dev/zero")
    refused_everywhere(link, NOT_REGULAR, tmp_path)
    refused_everywhere(tmp_path, NOT_REGULAR, tmp_path / "nothing")


def test_a_scene_over_the_size_limit_is_refused_by_every_door(tmp_path):
    # 17 MiB, over the 16 MiB a scene may have: refused by its size, with
    # the figures, before it is parsed.
    path = tmp_path / "big.toml"
    text = big_scene()
    path.write_text(text)
    refused_everywhere(path, too_large(len(text)), tmp_path)
    # Text in memory over the limit: refused as loads gets it, with set= too.
    message = (f"<string>: cannot read the scene: more than the {LIMIT} bytes a scene may have "
               "(set SPRUNG_MAX_INPUT_BYTES to raise the limit)")
    for set in (None, {"sim.dt": 1e-3}):
        with pytest.raises(sprung.SceneError) as caught:
            sprung.loads(text, set=set)
        assert str(caught.value) == message


def test_the_limit_is_the_environment_variables(tmp_path, monkeypatch):
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    # Raised: the 17 MiB scene loads; lowered below the small scene's size:
    # that is refused, from a file and as text.
    monkeypatch.setenv("SPRUNG_MAX_INPUT_BYTES", str(32 << 20))
    big = tmp_path / "big.toml"
    big.write_text(big_scene())
    assert sprung.load(big).steps == 0
    limit = len(SCENE) - 1
    monkeypatch.setenv("SPRUNG_MAX_INPUT_BYTES", str(limit))
    refused_everywhere(path, too_large(len(SCENE), limit), tmp_path)
    with pytest.raises(sprung.SceneError, match=f"more than the {limit} bytes a scene may have"):
        sprung.loads(SCENE)


def test_bytes_that_are_not_utf8_are_refused_by_every_door(tmp_path):
    # A Latin-1 é on the last line: refused with its line and byte.
    path = tmp_path / "latin1.toml"
    path.write_bytes(SCENE.encode() + b"# caf\xe9\n")
    line = SCENE.count("\n") + 1
    refused_everywhere(path, f"line {line}, byte 6: the scene file is not UTF-8 text (byte 0xe9)",
                       tmp_path)


# Run in a child with a time limit: a read of a FIFO without a writer
# blocks in the kernel, where no signal of the test can stop it.
FIFO_CHILD = r"""
import json, os, sys
sys.path.insert(0, sys.argv[3])
import sprung
from test_inputs import DOORS
results = {}
for name, door in DOORS.items():
    out = os.path.join(sys.argv[2], "out-" + name.replace("(", "-").replace(")", ""))
    try:
        door(sys.argv[1], out)
        results[name] = "accepted"
    except sprung.SceneError as e:
        results[name] = [str(e), e.path, os.path.exists(out)]
print(json.dumps(results))
"""


def test_a_fifo_is_refused_at_once_by_every_door(tmp_path):
    # A FIFO with no writer: every door refuses it by its type, without
    # opening it (an open would wait for a writer for ever).
    fifo = tmp_path / "scene.toml"
    os.mkfifo(fifo)
    tests = os.path.dirname(os.path.abspath(__file__))
    try:
        done = subprocess.run([sys.executable, "-c", FIFO_CHILD, str(fifo), str(tmp_path), tests],
                              capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail("a door blocked on a FIFO without a writer for 60 s")
    assert done.returncode == 0, done.stderr
    results = json.loads(done.stdout)
    assert results == {name: [f"{fifo}: {NOT_REGULAR}", str(fifo), False] for name in DOORS}


def test_the_words_are_the_command_lines(tmp_path):
    # `sprung run FILE` prints "error: " and the very message Python raises.
    from conftest import sprung_command
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)
    big = tmp_path / "big.toml"
    big.write_text(big_scene())
    for path in ("/dev/zero", fifo, big, tmp_path):
        done = subprocess.run([sprung_command(), "run", str(path), "--quiet"],
                              capture_output=True, text=True, timeout=60)
        assert done.returncode == 1, done.stderr
        with pytest.raises(sprung.SceneError) as caught:
            sprung.load(path)
        assert done.stderr.strip() == f"error: {caught.value}"


def test_the_sweep_command_refuses_an_unreadable_scene_before_any_run(tmp_path):
    # `python -m sprung.sweep /dev/zero`: exit status 1 and the command
    # line's words at once, no sweep folder.
    out = tmp_path / "sweep"
    done = subprocess.run([sys.executable, "-m", "sprung.sweep", "/dev/zero", "--grid",
                           "sim.dt=1e-3,2e-3", "--steps", "2", "--out", str(out)],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 1
    assert done.stderr == f"error: /dev/zero: {NOT_REGULAR}\n"
    assert not out.exists()


def test_a_sweeps_run_whose_scene_is_too_large_is_a_row(tmp_path):
    # The scene file passes the gate; an override makes its effective
    # scene longer than a scene may be: that run is a row, the others run.
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    long = "x" * (LIMIT + 1)
    rows = sprung.sweep(path, grid={"body.a.name": ["b", long]}, steps=2, out=tmp_path / "out",
                        progress=False)
    assert [row["status"] for row in rows] == ["ok", "error"]
    assert rows[1]["message"] == (
        f"{tmp_path / 'out' / 'runs' / rows[1]['id'] / 'scene.toml'}: cannot read the scene: "
        f"more than the {LIMIT} bytes a scene may have (set SPRUNG_MAX_INPUT_BYTES to raise "
        "the limit)")


# In a child: a crash (the stack overflowed) shows as its exit status.
BOUNDED_CHILD = r"""
import json, sys
import sprung
deep = 0.0
for _ in range(100_000):
    deep = [deep]
holder = []
holder.append(holder)
cases = {
    "key": {".".join(["sim"] * 40_000): 1.0},
    "parts": {".".join(["sim"] * 33): 1.0},
    "deep": {"sim.gravity": deep},
    "itself": {"sim.gravity": holder},
}
scene = sys.argv[1]
doors = {
    "load": lambda set: sprung.load(scene, set=set),
    "loads": lambda set: sprung.loads(open(scene).read(), set=set),
    "run": lambda set: sprung.run(scene, steps=1, set=set),
}
results = {}
for case, set in cases.items():
    for name, door in doors.items():
        try:
            door(set)
            results[case + " " + name] = "accepted"
        except sprung.SceneError as e:
            results[case + " " + name] = [str(e), e.field == next(iter(set))]
print(json.dumps(results))
"""


def test_set_keys_and_values_are_bounded(tmp_path):
    # A key of 40,000 dotted parts (159,999 bytes), one of 33 parts, a list
    # nested 100,000 deep and a list that holds itself: each refused as
    # SceneError naming its key and the limit it passed, by load, loads and
    # run, and the interpreter lives on.
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    done = subprocess.run([sys.executable, "-c", BOUNDED_CHILD, str(path)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
    assert _native.MAX_VALUE_DEPTH == 32
    key = ".".join(["sim"] * 40_000)
    too_long = f"`--set {key}`: the key is 159999 bytes long, more than the 4096 a key may have"
    parts = ".".join(["sim"] * 33)
    too_many = f"`--set {parts}`: the key has more than the 32 dotted parts a key may have"
    too_deep = ("set: `sim.gravity`: the value nests lists or dicts more than 32 deep, the most "
                "a value may (a list or dict that holds itself nests without end)")
    expected = {}
    for case, message in (("key", too_long), ("parts", too_many), ("deep", too_deep),
                          ("itself", too_deep)):
        for door, name in (("load", path), ("loads", "<string>"), ("run", path)):
            expected[f"{case} {door}"] = [f"{name}: {message}", True]
    assert json.loads(done.stdout) == expected


def nested(levels):
    """1.0 inside `levels` lists."""
    value = 1.0
    for _ in range(levels):
        value = [value]
    return value


def test_a_value_as_deep_as_the_limit_is_taken():
    # 32 levels are converted (a scene's own deepest value has 2) and
    # reach the scene, which refuses a gravity that is not a vector; 33
    # are refused by the limit.
    with pytest.raises(sprung.SceneError) as caught:
        sprung.loads(SCENE, set={"sim.gravity": nested(32)})
    assert caught.value.field == "sim.gravity"
    assert "deep" not in str(caught.value), str(caught.value)
    with pytest.raises(sprung.SceneError) as caught:
        sprung.loads(SCENE, set={"sim.gravity": nested(33)})
    assert str(caught.value) == (
        "<string>: set: `sim.gravity`: the value nests lists or dicts more than 32 deep, the "
        "most a value may (a list or dict that holds itself nests without end)")


def test_a_sweeps_grid_value_nested_too_deep_is_refused_before_any_run(tmp_path):
    # A grid value 100,000 lists deep could be neither hashed into a run id
    # nor written into sweep.csv (both recurse): refused, naming the limit.
    path = tmp_path / "scene.toml"
    path.write_text(SCENE)
    deep = 0.0
    for _ in range(100_000):
        deep = [deep]
    out = tmp_path / "out"
    with pytest.raises(ValueError) as caught:
        sprung.sweep(path, grid={"sim.dt": [1e-3], "sim.gravity": [[0.0, -9.8], deep]},
                     steps=2, out=out, progress=False)
    assert str(caught.value) == ("grid sim.gravity: value 1: the value nests lists or dicts "
                                 "more than 32 deep, the most a value may")
    assert not out.exists()


# In a child with a time limit: a FIFO opened for writing without a
# reader would block.
STATE_CHILD = r"""
import json, sys
import sprung
world = sprung.loads(sys.argv[1])
world.step(2)
results = []
for path in sys.argv[2:]:
    try:
        world.save_state(path)
        results.append("written")
    except sprung.StateError as e:
        results.append([str(e), e.path])
print(json.dumps(results))
"""


def test_a_state_is_never_written_through_a_link_fifo_or_device(tmp_path):
    # save_state replaces only a regular file: onto a link to a file
    # elsewhere, or a FIFO, StateError, and both nodes stand as they were.
    target = tmp_path / "elsewhere.state"
    target.write_bytes(b"not to be touched")
    link = tmp_path / "link.state"
    link.symlink_to(target)
    fifo = tmp_path / "fifo.state"
    os.mkfifo(fifo)
    try:
        done = subprocess.run([sys.executable, "-c", STATE_CHILD, SCENE, str(link), str(fifo)],
                              capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail("save_state blocked on a FIFO for 60 s")
    assert done.returncode == 0, done.stderr
    results = json.loads(done.stdout)
    assert [r if r == "written" else r[1] for r in results] == [str(link), str(fifo)], results
    for (message, _), path in zip(results, (link, fifo)):
        assert message.startswith(f"{path}: not a regular file"), message
    # The link and the FIFO stand, the link's target unchanged, nothing
    # left beside them.
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_bytes() == b"not to be touched"
    assert fifo.is_fifo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["elsewhere.state", "fifo.state",
                                                          "link.state"]


def test_a_run_folder_never_has_a_link_or_its_scene_replaced(tmp_path):
    # run(out=...) writes its scene.toml whole, never through a link, and
    # never over the scene it reads with other bytes (as `sprung run`).
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE + "# a comment\n")
    target = tmp_path / "elsewhere.txt"
    target.write_text("mine")
    out = tmp_path / "out"
    out.mkdir()
    (out / "scene.toml").symlink_to(target)
    with pytest.raises(OSError, match="not a regular file"):
        sprung.run(str(scene), out=str(out), steps=2)
    assert (out / "scene.toml").is_symlink() and target.read_text() == "mine"
    with pytest.raises(ValueError, match="would write its copy of the scene over"):
        sprung.run(str(scene), out=str(tmp_path), steps=2, set={"sim.dt": 5e-4})
    assert scene.read_text() == SCENE + "# a comment\n"
    # A run's own copy (the effective scene) run again into its folder:
    # the same bytes, so the run goes on and leaves the file as it was.
    plain = tmp_path / "plain"
    plain.mkdir()
    kept = plain / "scene.toml"
    kept.write_text(SCENE)
    own = _native.effective_scene(SCENE, str(kept), [])
    kept.write_text(own)
    sprung.run(str(kept), out=str(plain), steps=2)
    assert kept.read_text() == own
