"""A controller in Python that pushes a body every step: a PD controller
holds a soft ball's centre 1 m up, against gravity, by a force on each of
its particles.

    python python/examples/controller.py
"""

from pathlib import Path

import numpy as np

import sprung

world = sprung.load(Path(__file__).resolve().parents[2] / "scenes" / "ball2d.toml")
ball = world.body("ball")
mass = world.masses[ball.indices].sum()  # kg
target = np.array([-1.5, 1.0])  # m
gain, damping = 200.0, 30.0  # N/m and N·s/m, on the whole ball

previous = ball.centroid
for step in range(4000):
    centre = ball.centroid
    velocity = (centre - previous) / world.dt
    previous = centre
    # The whole push, shared by the ball's particles by their mass, plus
    # the ball's weight.
    push = gain * (target - centre) - damping * velocity + mass * np.array([0.0, 9.81])
    forces = np.zeros_like(world.positions)
    forces[ball.indices] = np.outer(world.masses[ball.indices] / mass, push)
    world.external_forces = forces
    world.step()

print(f"t = {world.time:.2f} s: the ball's centre is at {ball.centroid.round(3)} (target {target})")
