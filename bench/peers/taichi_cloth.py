"""Time the bench's cloth (cloth.py) in Taichi's CPU back end, symplectic
Euler over the general spring list, on 1 thread and on all: the spring
updates per second that `sprung bench --only cloth` prints for sprung.

Two forms: "scatter" (one pass over springs, atomic adds into the
particles' forces) and "gather" (per particle, over its springs in a
compressed adjacency list: no atomics, each spring computed twice).
Usage: python taichi_cloth.py [N] [THREADS]"""

import sys
import time

import numpy as np
import taichi as ti

import cloth

n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
threads = int(sys.argv[2]) if len(sys.argv) > 2 else 1
ti.init(arch=ti.cpu, cpu_max_num_threads=threads, default_fp=ti.f64, random_seed=0)

pairs = cloth.springs(n)
count, springs_n = n * n, len(pairs)
x0 = cloth.positions(n)
rest = np.linalg.norm(x0[pairs[:, 0]] - x0[pairs[:, 1]], axis=1)
mass = cloth.MASS / count
dt = cloth.stable_step(n)
inverse_mass = np.full(count, 1.0 / mass)
inverse_mass[cloth.pinned(n)] = 0.0

# Adjacency for the gather form: for each particle, its springs and sign.
order = np.argsort(np.concatenate([pairs[:, 0], pairs[:, 1]]), kind="stable")
ends = np.concatenate([pairs[:, 0], pairs[:, 1]])[order]
offsets = np.searchsorted(ends, np.arange(count + 1)).astype(np.int32)
other = np.concatenate([pairs[:, 1], pairs[:, 0]])[order].astype(np.int32)
rest_adj = np.concatenate([rest, rest])[order]

x = ti.Vector.field(3, ti.f64, count)
v = ti.Vector.field(3, ti.f64, count)
f = ti.Vector.field(3, ti.f64, count)
w = ti.field(ti.f64, count)
a = ti.field(ti.i32, springs_n)
b = ti.field(ti.i32, springs_n)
L0 = ti.field(ti.f64, springs_n)
off = ti.field(ti.i32, count + 1)
oth = ti.field(ti.i32, 2 * springs_n)
L0a = ti.field(ti.f64, 2 * springs_n)
for field, data in [(x, x0), (w, inverse_mass), (a, pairs[:, 0]), (b, pairs[:, 1]),
                    (L0, rest), (off, offsets), (oth, other), (L0a, rest_adj)]:
    field.from_numpy(data)
k, c, g = cloth.STIFFNESS, cloth.DAMPING, cloth.GRAVITY


@ti.func
def spring_force(xi, xj, vi, vj, rest_length):
    d = xj - xi
    length = d.norm()
    u = d / length
    return (k * (length - rest_length) + c * (vj - vi).dot(u)) * u


@ti.kernel
def scatter():
    for p in f:
        f[p] = ti.Vector([0.0, -g * mass, 0.0])
    for s in a:
        i, j = a[s], b[s]
        force = spring_force(x[i], x[j], v[i], v[j], L0[s])
        f[i] += force  # atomic add
        f[j] -= force


@ti.kernel
def gather():
    for p in f:
        total = ti.Vector([0.0, -g * mass, 0.0])
        for e in range(off[p], off[p + 1]):
            q = oth[e]
            total += spring_force(x[p], x[q], v[p], v[q], L0a[e])
        f[p] = total


@ti.kernel
def advance():
    for p in x:
        v[p] += dt * w[p] * f[p]
        x[p] += dt * v[p]


def seconds_per_step(forces, steps=50, least=0.5):
    forces()
    advance()
    ti.sync()
    taken, start = 0, time.perf_counter()
    while taken < steps or time.perf_counter() - start < least:
        forces()
        advance()
        taken += 1
    ti.sync()
    return (time.perf_counter() - start) / taken


for name, forces in [("scatter", scatter), ("gather", gather)]:
    s = seconds_per_step(forces)
    print(f"taichi,{name},{n},{threads},{s * 1e3:.4f},{springs_n / s:.4e}")
