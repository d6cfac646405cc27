"""Time the bench's cloth (cloth.py) as a pybullet deformable mass-spring
soft body: the grid written as an OBJ, loaded with structural and bending
springs at 1000 N/m, stepped headless at the same dt. Bullet makes its
own springs from the mesh (its links), so the spring updates per second
printed use sprung's count for the same cloth: a nominal figure.
Usage: python pybullet_cloth.py [N]"""

import os
import sys
import tempfile
import time

import pybullet as p

import cloth

n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
springs_n = len(cloth.springs(n))
x = cloth.positions(n)
with tempfile.TemporaryDirectory() as folder:
    path = os.path.join(folder, "cloth.obj")
    with open(path, "w") as obj:
        for px, py, pz in x:
            obj.write(f"v {px} {py} {pz}\n")
        for i in range(n - 1):
            for j in range(n - 1):
                q = i * n + j + 1
                obj.write(f"f {q} {q + 1} {q + n + 1}\nf {q} {q + n + 1} {q + n}\n")
    p.connect(p.DIRECT)
    p.resetSimulation(p.RESET_USE_DEFORMABLE_WORLD)
    p.setGravity(0, -cloth.GRAVITY, 0)
    dt = cloth.stable_step(n)
    p.setTimeStep(dt)
    body = p.loadSoftBody(path, mass=cloth.MASS, useMassSpring=1, useBendingSprings=1,
                          springElasticStiffness=cloth.STIFFNESS,
                          springDampingStiffness=cloth.DAMPING,
                          springBendingStiffness=cloth.STIFFNESS,
                          useSelfCollision=0, useFaceContact=0)
    for corner in cloth.pinned(n):
        p.createSoftBodyAnchor(body, corner, -1, -1)
    p.stepSimulation()
    taken, start = 0, time.perf_counter()
    while taken < 20 or time.perf_counter() - start < 0.5:
        p.stepSimulation()
        taken += 1
    s = (time.perf_counter() - start) / taken
    print(f"pybullet,soft body,{n},1,{s * 1e3:.4f},{springs_n / s:.4e}")
