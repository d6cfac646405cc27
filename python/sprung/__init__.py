"""sprung: mass-spring-damper simulation of elastic materials.

Soft bodies held up by gas, cloth, ropes and jelly, from scene files (TOML)
into worlds whose state is numpy arrays::

    import sprung
    world = sprung.load("scenes/ball2d.toml")
    world.step(1000)                       # with the GIL released
    print(world.time, world.body("ball").pressure)
    table = sprung.run("scenes/ball2d.toml", time=1.0)   # diagnostics.csv as arrays

Units are SI throughout: m, s, kg, N, J, Pa (in 2D, areas in m² and
pressures in N/m). The guide is docs/python.md in the repository.
"""

import base64
import os
from typing import Mapping, Optional, Union

import numpy as np

from . import _native
from ._errors import BlowUp, MeshError, SceneError, StateError, StepError
from ._native import Batch, Body, World, integrators
# The function, by the name of its module (which ``python -m sprung.sweep``
# runs): importing the module later leaves this name as it is.
from .sweep import sweep

__version__ = _native.__version__

__all__ = [
    "load", "loads", "run", "sweep", "animate", "plot", "integrators",
    "World", "Body", "Batch", "Diagnostics", "Gif", "Png", "Plots",
    "SceneError", "MeshError", "StateError", "StepError", "BlowUp",
]

PathLike = Union[str, "os.PathLike[str]"]


def _overrides(set: Optional[Mapping[str, object]]):
    """The overrides as (key, value) pairs, checked for their types."""
    if set is None:
        return None
    if not isinstance(set, Mapping):
        raise TypeError("set: give a dict of dotted keys, e.g. {'sim.dt': 1e-4}")
    return [(str(key), value) for key, value in set.items()]


def load(path: PathLike, set: Optional[Mapping[str, object]] = None,
         state: Optional[PathLike] = None) -> World:
    """Load the scene file at ``path`` into a World.

    Args:
        path: a scene file (TOML); its meshes are found relative to its folder.
        set: overrides of the scene's keys, by dotted key, as the command
            line's ``--set`` takes them: ``{"sim.dt": 1e-4,
            "body.ball.gas.nrt": 200.0}``.
        state: a state file ``World.save_state`` wrote from this scene, to
            go on from.

    Raises:
        SceneError: the scene cannot be read or built (``MeshError`` for a mesh).
        StateError: the state file cannot be used.
    """
    world = _native.load(os.fspath(path), _overrides(set))
    if state is not None:
        world.load_state(os.fspath(state))
    return world


def loads(text: str, base_dir: Optional[PathLike] = None,
          set: Optional[Mapping[str, object]] = None) -> World:
    """Build a World from a scene's TOML ``text``.

    Meshes are found relative to ``base_dir`` (default: the current folder);
    ``set`` as for ``load``.
    """
    base = None if base_dir is None else os.fspath(base_dir)
    return _native.loads(text, base, _overrides(set))


class Diagnostics(dict):
    """A run's diagnostics: each column of ``diagnostics.csv`` by its name,
    as a numpy array (``step`` int64, ``solver_preconditioner`` strings,
    the rest float64, NaN where the CSV cell is empty), the same numbers
    bit for bit.

    Attributes:
        csv: the table as ``sprung run`` writes it.
    """

    def __init__(self, csv: str):
        # Read by the reader of `sprung plot`: exact, NaN for empty cells.
        columns = {
            name: np.asarray(values, dtype=str) if isinstance(values, list) else values
            for name, values in (_native.columns(csv) if csv.strip() else [])
        }
        super().__init__(columns)
        self.csv = csv

    def to_pandas(self):
        """The table as a pandas DataFrame (pandas must be installed)."""
        import pandas as pd
        return pd.DataFrame(dict(self))

    def plot(self, width: int = 1000, height: int = 600) -> "Plots":
        """The plots ``sprung plot`` draws of this table (see ``sprung.plot``)."""
        return plot(self, width=width, height=height)

    def __repr__(self) -> str:
        rows = len(self["step"]) if "step" in self else 0
        return f"<sprung.Diagnostics: {rows} rows, columns {list(self)}>"


def run(scene: Union[PathLike, World], steps: Optional[int] = None,
        time: Optional[float] = None, every: Optional[int] = None,
        integrator: Optional[str] = None,
        set: Optional[Mapping[str, object]] = None,
        out: Optional[PathLike] = None, format: Optional[str] = None) -> Diagnostics:
    """Run a scene as ``sprung run`` does and return its diagnostics.

    Args:
        scene: a scene file, or a World (stepped in place, from its state
            now; ``integrator`` switches the World's integrator for good).
        steps: steps to run (default: the scene's duration); or
        time: simulated time to run (s).
        every: a row every ``every`` steps (default: the scene's
            ``every``, else 50 rows per simulated second).
        integrator: run with this integrator instead of the scene's.
        set: overrides of the scene's keys (with a scene file), as ``load``.
        out: a folder to write ``diagnostics.csv`` into, as ``sprung run
            --out`` does, with the effective ``scene.toml`` (mesh paths
            made absolute) for a scene file.
        format: also write a frame per row into ``out/frames/``: ``vtu``,
            ``vtk`` or ``obj``, as ``sprung run --format`` does.

    Returns:
        Diagnostics: the table, bit for bit the numbers of ``sprung run``'s
        ``diagnostics.csv`` for the same run.

    Raises:
        SceneError: the scene cannot be built.
        BlowUp: the run blew up; ``.diagnostics`` holds the rows before it
            (also written to ``out``).
        KeyboardInterrupt: Ctrl-C, between steps (rows so far written to ``out``).
    """
    target: Union[str, World]
    if isinstance(scene, World):
        if set:
            raise ValueError("set: overrides apply to a scene file; "
                             "a World is already built (use sprung.load(path, set=...))")
        target = scene
    elif set:
        target = load(scene, set=set)
    else:
        target = os.fspath(scene)
    out = None if out is None else os.fspath(out)
    if out is not None and not isinstance(scene, World):
        # The effective scene beside its diagnostics, as `sprung run` keeps it.
        path = os.fspath(scene)
        # Through the command line's gate, as load reads it.
        text = _native.read_scene(path)
        effective = _native.effective_scene(text, path, _overrides(set))
        os.makedirs(out, exist_ok=True)
        kept = os.path.join(out, "scene.toml")
        # Never over the scene it reads with other bytes (the overrides
        # applied, the comments dropped), as `sprung run` refuses.
        if os.path.exists(kept) and os.path.samefile(kept, path) and text != effective:
            raise ValueError(
                f"out={out!r}: the run would write its copy of the scene over {path}, "
                "which it reads, with other bytes (the effective scene: overrides applied, "
                "comments dropped): give another out (nothing was written)")
        if not (os.path.exists(kept) and os.path.samefile(kept, path)):
            # Whole or not at all, and never through a link, FIFO or device.
            _native.write_output(kept, effective)
    csv, error = _native.run(target, steps, time, every, integrator, out, format)
    table = Diagnostics(csv)
    if error is not None:
        # A StepError, a BlowUp or Ctrl-C's KeyboardInterrupt: each carries
        # the rows before it.
        error.diagnostics = table  # type: ignore[attr-defined]
        raise error
    return table


class Png:
    """A PNG picture: ``data`` holds its bytes; Jupyter shows it inline."""

    def __init__(self, data: bytes, name: str = "picture"):
        self.data = bytes(data)
        self.name = name

    def _repr_png_(self) -> bytes:
        return self.data

    def save(self, path: PathLike) -> None:
        """Write the picture to ``path``."""
        with open(path, "wb") as f:
            f.write(self.data)

    def __repr__(self) -> str:
        return f"<sprung.Png {self.name!r}: {len(self.data)} bytes>"


class Gif:
    """An animated GIF: ``data`` holds its bytes; Jupyter plays it inline."""

    def __init__(self, data: bytes):
        self.data = bytes(data)

    def _repr_html_(self) -> str:
        encoded = base64.b64encode(self.data).decode("ascii")
        return f'<img src="data:image/gif;base64,{encoded}"/>'

    def save(self, path: PathLike) -> None:
        """Write the GIF to ``path``."""
        with open(path, "wb") as f:
            f.write(self.data)

    def __repr__(self) -> str:
        return f"<sprung.Gif: {len(self.data)} bytes>"


class Plots(dict):
    """Plots by name (``energy``; ``gas`` where a body has gas), each a
    ``Png``; Jupyter shows them one under the other."""

    def _repr_html_(self) -> str:
        parts = []
        for png in self.values():
            encoded = base64.b64encode(png.data).decode("ascii")
            parts.append(f'<img src="data:image/png;base64,{encoded}"/>')
        return "<br/>".join(parts)


def animate(scene_or_world: Union[PathLike, World], time: Optional[float] = None,
            steps: Optional[int] = None, fps: float = 25.0, width: int = 480,
            height: int = 360) -> Gif:
    """An animated GIF of a scene run for ``time`` (s) or ``steps``
    (default: the scene's duration), ``fps`` pictures per simulated second
    played in real time, drawn by ``sprung render``'s renderer.

    A World is animated from its state now on a copy: the World itself
    does not move.
    """
    if isinstance(scene_or_world, World):
        world = scene_or_world.copy()
    else:
        world = load(scene_or_world)
    return Gif(_native.animate(world, time, steps, fps, width, height))


def plot(diagnostics: Union[Diagnostics, PathLike, str], width: int = 1000,
         height: int = 600, name: Optional[str] = None) -> Plots:
    """The plots ``sprung plot`` draws of a run's diagnostics, as PNG: the
    energy terms and total against time, and the gas bodies' volume and
    pressure where there are any.

    Args:
        diagnostics: a ``Diagnostics`` (from ``sprung.run``), a run folder or
            its ``diagnostics.csv``.
        width, height: each picture's size (pixels).
        name: the title (default: the run folder's name, or ``run``).
    """
    if isinstance(diagnostics, Diagnostics):
        text, title = diagnostics.csv, name or "run"
    else:
        path = os.fspath(diagnostics)
        if os.path.isdir(path):
            path = os.path.join(path, "diagnostics.csv")
        with open(path, encoding="utf-8") as f:
            text = f.read()
        title = name or os.path.basename(os.path.dirname(os.path.abspath(path)))
    pictures = _native.plot(text, title, width, height)
    return Plots((key, Png(data, key)) for key, data in pictures)
