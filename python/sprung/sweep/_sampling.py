"""Where a sweep's runs lie in its parameters: every combination of a
grid, or a Latin hypercube over ranges, with the values checked before
any run."""

import itertools
import math
from typing import Dict, Iterable, List, Mapping, Sequence, Tuple

import numpy as np

from .. import _native


def latin_hypercube(ranges: Mapping[str, Tuple[float, float]], samples: int,
                    seed: int) -> List[Dict[str, float]]:
    """``samples`` points over ``ranges`` (KEY: (low, high)), a Latin
    hypercube: each range cut in ``samples`` equal strata, each stratum
    used once per key, a uniform point within it; the same points for the
    same seed."""
    if samples < 1:
        raise ValueError(f"samples = {samples}: at least 1")
    rng = np.random.default_rng(seed)
    points: List[Dict[str, float]] = [dict() for _ in range(samples)]
    for key, (low, high) in ranges.items():
        low, high = float(low), float(high)
        if not (math.isfinite(low) and math.isfinite(high) and low <= high):
            raise ValueError(f"range {key}: {low}:{high} must be finite, low <= high")
        strata = rng.permutation(samples)
        offsets = rng.random(samples)
        for point, stratum, offset in zip(points, strata, offsets):
            point[key] = low + (high - low) * (stratum + offset) / samples
    return points


def check_nesting(where: str, value: object) -> None:
    """Refuse ``value`` where its lists, tuples and dicts nest deeper than a
    scene's value may (``MAX_VALUE_DEPTH``, 32 levels), counted without
    recursion: a sweep's values are hashed into run ids and written into
    ``sweep.csv``, and neither may recurse without bound."""
    limit = _native.MAX_VALUE_DEPTH
    stack = [(value, 0)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, np.ndarray):
            # Its Python form, at the same level (as ``set=`` reads it).
            stack.append((item.tolist(), depth))
            continue
        children: Iterable[object]
        if isinstance(item, dict):
            children = item.values()
        elif isinstance(item, (list, tuple)):
            children = item
        else:
            continue
        if depth >= limit:
            raise ValueError(f"{where}: the value nests lists or dicts more than {limit} deep, "
                             "the most a value may")
        stack.extend((child, depth + 1) for child in children)


def grid_points(grid: Mapping[str, Sequence[object]]) -> List[Dict[str, object]]:
    """Every combination of the grid's values, the first key slowest; a
    value nested deeper than a scene's value may be is refused."""
    keys = list(grid)
    for key in keys:
        if len(grid[key]) == 0:
            raise ValueError(f"grid {key}: no values")
        for n, value in enumerate(grid[key]):
            check_nesting(f"grid {key}: value {n}", value)
    return [dict(zip(keys, values)) for values in itertools.product(*(grid[k] for k in keys))]
