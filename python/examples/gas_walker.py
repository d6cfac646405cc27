"""A soft creature that walks by pumping its gas: a 2D crawler whose gas
bladder (a loop of 12 particles) sits behind its two feet and carries a
heavy particle at its tail. A controller in Python pumps the bladder's
nRT up in a twentieth of a period and lets it down over the rest, 2.5
times a second. The quick pump throws the heavy tail back, and the push
forward on the feet is more than friction holds: the feet slip forward.
The slow let-down draws the tail in gently, and the feet hold. Each pump
moves the crawler about 4 mm, feet first; the same crawler left alone
stays where it is (an inertial, stick-slip drive).

    python python/examples/gas_walker.py [PUMPS]
"""

import math
import sys

import sprung

BLADDER = 12
PERIOD = 0.4  # s, one pump
BASE, PUMP = 1.0, 8.0  # nRT (J; N·m in 2D) at rest and added at the top


def crawler() -> sprung.World:
    """Two feet (0.2 kg each) on the floor, 0.25 m apart, and the bladder
    (0.02 kg per particle, 0.4 kg at its tail) braced to them."""
    points, masses = [[-0.25, 0.0], [0.0, 0.0]], [0.2, 0.2]
    for i in range(BLADDER):
        a = math.pi + 2 * math.pi * i / BLADDER  # from its back, anticlockwise
        points.append([round(0.14 + 0.1 * math.cos(a), 6), round(0.12 + 0.1 * math.sin(a), 6)])
        masses.append(0.02)
    masses[2 + BLADDER // 2] = 0.4
    loop = [[2 + i, 2 + (i + 1) % BLADDER] for i in range(BLADDER)]
    braces = [[2 + i, 2 + (i + 2) % BLADDER] for i in range(BLADDER)]
    legs = [[0, 1], [0, 2], [1, 2], [0, 3], [1, 3], [0, 13], [1, 13], [1, 12], [1, 4]]
    return sprung.loads(f"""
[sim]
dt = 1e-4
integrator = "symplectic_euler"

[[body]]
name = "crawler"
particles = {points}
masses = {masses}
segments = {loop}
springs = {loop + braces + legs}
stiffness = 4000.0
damping = 2.0
gas = {{ nrt = {BASE}, ramp_time = 0.2 }}

[[collider]]
plane = {{ point = [0.0, -0.001, 0.0], normal = [0.0, 1.0, 0.0] }}
friction = 0.3
""")


def walk(pumps: int, pump: bool) -> float:
    """How far (m) the back foot moves over `pumps` periods after the
    crawler has settled for 1 s; with `pump` false its gas is left alone."""
    world = crawler()
    bladder = world.body("crawler")
    world.step(round(1.0 / world.dt))
    start = world.positions[0][0]
    steps = round(PERIOD / world.dt)
    for _ in range(pumps):
        for k in range(steps):
            phase = k / steps
            level = phase / 0.05 if phase < 0.05 else 1.0 - (phase - 0.05) / 0.95
            if pump:
                bladder.nrt = BASE + PUMP * level
            world.step()
    return world.positions[0][0] - start


pumps = int(sys.argv[1]) if len(sys.argv) > 1 else 20
walked, stayed = walk(pumps, pump=True), walk(pumps, pump=False)
print(f"{pumps} pumps in {pumps * PERIOD:.1f} s: the crawler walked {-walked * 1000:.0f} mm "
      f"(feet first); left alone it moved {abs(stayed) * 1000:.0f} mm")
