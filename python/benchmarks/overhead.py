"""What Python adds to sprung's step, and what a Batch gains on threads.

    python python/benchmarks/overhead.py [REPEATS]

1. Per-call overhead of World.step(): N calls of step() against one call
   of step(N), which loops in Rust (the same steps, the same world), on a
   small world (scenes/rope.toml, 2D, 20 particles). Each figure is the
   median of REPEATS timings.
2. A Batch of 8 small worlds (scenes/ball2d.toml, 34 particles each)
   stepped 10,000 steps on 1 thread and on 2: the speed-up.
"""

import statistics
import sys
import time
from pathlib import Path

import sprung

SCENES = Path(__file__).resolve().parents[2] / "scenes"
REPEATS = int(sys.argv[1]) if len(sys.argv) > 1 else 7
N = 20_000


def median_time(job):
    times = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        job()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


world = sprung.load(SCENES / "rope.toml")
world.step(1000)  # warm


def calls():
    for _ in range(N):
        world.step()


in_rust = median_time(lambda: world.step(N)) / N
from_python = median_time(calls) / N
print(f"step() on {len(world.masses)} particles: {in_rust * 1e6:.3f} µs a step in Rust's loop, "
      f"{from_python * 1e6:.3f} µs a call from Python: overhead {(from_python - in_rust) * 1e6:.3f} µs a call")

ball = sprung.load(SCENES / "ball2d.toml")
times = {}
for threads in (1, 2):
    batch = sprung.Batch([ball.copy() for _ in range(8)], threads=threads)
    batch.step(10)
    times[threads] = median_time(lambda: batch.step(10_000))
print(f"Batch of 8 × {len(ball.masses)} particles, 10000 steps: {times[1]:.3f} s on 1 thread, "
      f"{times[2]:.3f} s on 2: {times[1] / times[2]:.2f}× faster")
