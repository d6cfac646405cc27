"""A Batch steps each world exactly as it would be stepped alone, on any
number of threads, with the GIL released."""

import threading
import time

import numpy as np
import pytest

import sprung


def worlds(scenes):
    """Worlds of different kinds, some at different states, one above the
    engine's parallel chunk (4,225 particles: its loops run on the
    Batch's pool)."""
    made = [sprung.load(scenes / name) for name in ("ball2d.toml", "ball3d.toml", "cloth.toml", "rope.toml")]
    made[1].step(7)
    made[3].integrator = "rk4"
    big = (scenes / "cloth.toml").read_text().replace("nx = 20, ny = 20", "nx = 65, ny = 65")
    made.append(sprung.loads(big, base_dir=scenes))
    return made


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_a_batch_equals_each_world_alone(scenes, threads):
    alone = worlds(scenes)
    batched = worlds(scenes)
    for world in alone:
        world.step(150)
    batch = sprung.Batch(batched, threads=threads)
    assert batch.threads == threads and len(batch) == 5
    batch.step(100)
    batch.step(50)
    for a, b in zip(alone, batch.worlds):
        assert b.steps == a.steps
        assert a.positions.tobytes() == b.positions.tobytes()
        assert a.velocities.tobytes() == b.velocities.tobytes()
        assert a.energies() == b.energies()


def test_one_world_twice_is_refused(scenes):
    world = sprung.load(scenes / "rope.toml")
    with pytest.raises(ValueError, match="same World"):
        sprung.Batch([world, world])


def large(scenes):
    # A cloth of 1,600 particles (below the engine's parallel chunk, so a
    # world alone runs on one thread) that takes about 0.2 s per 100 steps.
    text = (scenes / "cloth.toml").read_text().replace("nx = 20, ny = 20", "nx = 40, ny = 40")
    return sprung.loads(text, base_dir=scenes)


def test_the_gil_is_released_while_a_batch_steps(scenes):
    batch = sprung.Batch([large(scenes), large(scenes)], threads=2)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    start = time.perf_counter()
    batch.step(200)
    end = time.perf_counter()
    stop.set()
    counter.join()
    during = [t for t in ticks if start < t < end]
    # The counter thread needs the GIL for each tick. Held through the
    # step (about 0.4 s), it would tick at most once inside it; released,
    # it ticks every few milliseconds. Five ticks tell the two apart on
    # a loaded machine too. What the second thread gains is a speed
    # figure: python/benchmarks/overhead.py, never a timed test.
    assert len(during) >= 5, (len(during), end - start)
