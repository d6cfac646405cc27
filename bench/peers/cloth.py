"""The bench's cloth, as sprung's builder makes it (`sprung bench`, case
"cloth N²"): an N x N grid, 1 m square, 1 kg in all, springs of 1000 N/m
with 0.01 N s/m of damping along each, structural (to the right and
down), shear (both diagonals of every square) and bending (two along),
pinned at the two corners of its last row, under gravity of 9.81 m/s².
For 256² that is 65,536 particles and 390,658 springs."""

import numpy as np

SIDE = 1.0  # m
MASS = 1.0  # kg, the whole cloth
STIFFNESS = 1000.0  # N/m
DAMPING = 0.01  # N s/m
GRAVITY = 9.81  # m/s²


def springs(n):
    """The spring list: an (S, 2) array of particle indices, numbered
    row-major like sprung's builder."""
    idx = np.arange(n * n).reshape(n, n)
    pairs = [
        (idx[:, :-1], idx[:, 1:]),  # structural, along rows
        (idx[:-1, :], idx[1:, :]),  # structural, along columns
        (idx[:-1, :-1], idx[1:, 1:]),  # shear
        (idx[:-1, 1:], idx[1:, :-1]),  # shear
        (idx[:, :-2], idx[:, 2:]),  # bending
        (idx[:-2, :], idx[2:, :]),  # bending
    ]
    return np.concatenate(
        [np.stack([a.ravel(), b.ravel()], axis=1) for a, b in pairs]
    ).astype(np.int32)


def positions(n):
    """Particle positions (m), (N², 3): the cloth flat in the x-z plane."""
    h = SIDE / (n - 1)
    j, i = np.meshgrid(np.arange(n), np.arange(n))
    return np.stack([j.ravel() * h, np.zeros(n * n), i.ravel() * h], axis=1)


def pinned(n):
    """The two pinned corners."""
    return [(n - 1) * n, n * n - 1]


def stable_step(n):
    """Half the explicit stability limit of the stiffest particle, as
    sprung's bench takes (s): 2 / omega with omega² = 4 k_sum / m."""
    m = MASS / (n * n)
    k_sum = 12 * STIFFNESS  # the most springs meeting at a particle
    return 0.5 * 2.0 / np.sqrt(4.0 * k_sum / m)
