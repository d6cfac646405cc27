"""Long calls stop on Ctrl-C leaving the World usable; 10,000 calls of
step() do not grow the memory."""

import os
import signal
import threading

import pytest

import sprung


def resident_bytes():
    """The process's resident memory (bytes), from /proc."""
    with open("/proc/self/statm") as f:
        pages = int(f.read().split()[1])
    return pages * os.sysconf("SC_PAGE_SIZE")


@pytest.mark.skipif(not os.path.exists("/proc/self/statm"), reason="needs /proc")
def test_no_memory_growth_over_10000_calls(scenes):
    world = sprung.load(scenes / "ball2d.toml")
    for _ in range(1000):  # warm up: buffers sized, caches filled
        world.step()
        world.positions
        world.body("ball").pressure
    before = resident_bytes()
    for _ in range(10_000):
        world.step()
        world.positions = world.positions
        world.energies()
        world.body("ball").centroid
    grown = resident_bytes() - before
    # A leak of one array of 34 × 2 floats per call would be 5 MB; the
    # allocator's own slack is well under 1 MB.
    assert grown < 1_000_000, grown


def test_ctrl_c_stops_a_long_step_between_steps(scenes):
    world = sprung.load(scenes / "ball3d.toml")
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        world.step(10**9)
    timer.join()
    reached = world.steps
    assert 0 < reached < 10**9
    world.step(3)
    assert world.steps == reached + 3
