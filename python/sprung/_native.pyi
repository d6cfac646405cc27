"""Type stubs of sprung's Rust extension (``sprung._native``).

Units are SI: m, s, kg, N, J, Pa (in 2D: areas in m², pressures in N/m).
Every array a World returns is a copy of its state at the call, never a
view: it cannot outlive its World or change under a program's feet.
"""

import os
from typing import Dict, List, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__all__ = ["__version__", "MAX_VALUE_DEPTH", "World", "Body", "Batch", "load", "loads",
           "read_scene", "write_output", "run", "animate", "plot", "columns", "integrators",
           "effective_scene", "parse_value"]

__version__: str
MAX_VALUE_DEPTH: int
"""The most levels of lists and dicts a ``set=`` value (or a scene's
value) may nest: 32."""


def integrators() -> List[str]:
    """The integrators' names, as ``World.integrator`` takes them."""


def load(path: str, set: Optional[List[Tuple[str, object]]] = None) -> "World":
    """Load a scene file (see ``sprung.load``)."""


def read_scene(path: str) -> str:
    """The text of the scene file at ``path`` through the command line's
    gate: a regular file (not a device, FIFO or folder, also behind a link),
    at most 16 MiB (``SPRUNG_MAX_INPUT_BYTES`` bytes when set), UTF-8.

    Raises:
        SceneError: with the words ``sprung run`` prints.
    """


def write_output(path: str, text: str) -> None:
    """Write ``text`` to the file at ``path`` whole or not at all (under
    ``PATH.partial``, renamed into place).

    Raises:
        OSError: it cannot be written, or ``path`` is not a regular file
            (a link, FIFO, device or folder, which is never replaced).
    """


def loads(text: str, base_dir: Optional[str] = None,
          set: Optional[List[Tuple[str, object]]] = None,
          name: Optional[str] = None) -> "World":
    """Build a World from scene text (see ``sprung.loads``); errors name it
    ``name`` (default ``<string>``) in ``base_dir``."""


def effective_scene(text: str, path: str,
                    set: Optional[List[Tuple[str, object]]] = None,
                    steps: Optional[int] = None, time: Optional[float] = None,
                    every: Optional[int] = None) -> str:
    """The scene ``text`` (named ``path``, whose folder anchors its meshes)
    with ``set`` applied, as TOML with absolute mesh paths; ``steps`` (or
    ``time``, s) and ``every`` written into its ``[sim]``."""


def parse_value(text: str) -> object:
    """A command line's VALUE as ``--set`` reads it (TOML, or a bare word)."""


def run(scene: Union[str, "World"], steps: Optional[int] = None,
        time: Optional[float] = None, every: Optional[int] = None,
        integrator: Optional[str] = None, out: Optional[str] = None,
        format: Optional[str] = None) -> Tuple[str, Optional[BaseException]]:
    """Run a scene; the diagnostics CSV text and the error that stopped it
    early, if any (see ``sprung.run``)."""


def animate(world: "World", time: Optional[float] = None, steps: Optional[int] = None,
            fps: float = 25.0, width: int = 480, height: int = 360) -> bytes:
    """Step ``world`` and return an animated GIF of it (see ``sprung.animate``)."""


def plot(text: str, name: str = "run", width: int = 1000,
         height: int = 600) -> List[Tuple[str, bytes]]:
    """PNG plots of a diagnostics CSV text: ``energy``, and ``gas`` where a
    body has gas."""


def columns(text: str) -> List[Tuple[str, Union[npt.NDArray, List[str]]]]:
    """The columns of a diagnostics CSV text (``step`` int64, the text
    column ``solver_preconditioner`` a list of strings, the rest float64
    with NaN for empty cells)."""


@final
class World:
    """A simulated world: particles joined by springs, bodies, colliders.

    Made by ``sprung.load`` or ``sprung.loads``.
    """

    dt: float
    """The time step (s); set it to step by another."""
    integrator: str
    """The integrator's name (``sprung.integrators()``); set it to switch."""
    positions: npt.NDArray[np.float64]
    """Positions (m): a copy, ``(n, 3)``, ``(n, 2)`` in a 2D scene. Assign an
    array of that shape to set them (the integrator starts afresh)."""
    velocities: npt.NDArray[np.float64]
    """Velocities (m/s): a copy, ``(n, 3)`` or ``(n, 2)``; assign to set
    (pinned particles must stay at 0)."""
    external_forces: Optional[npt.NDArray[np.float64]]
    """Force (N) applied from outside to each particle over the coming
    steps: a copy, zeros when none; assign an array, or None to remove."""

    @property
    def time(self) -> float:
        """Simulated time (s)."""
    @property
    def steps(self) -> int:
        """Steps taken since the start."""
    @property
    def scene_steps(self) -> int:
        """Steps the scene asks for (its ``duration`` or ``steps``)."""
    @property
    def dimension(self) -> int:
        """2 for a 2D scene (every particle and gravity in z = 0 at load), else 3."""
    @property
    def path(self) -> "os.PathLike[str]":
        """The scene file, a ``pathlib.Path`` (``<string>`` for text)."""
    @property
    def masses(self) -> npt.NDArray[np.float64]:
        """Masses (kg): a copy, ``(n,)``."""
    @property
    def pinned(self) -> npt.NDArray[np.bool_]:
        """Which particles are pinned: a copy, ``(n,)``."""
    @property
    def springs(self) -> npt.NDArray[np.int64]:
        """Each spring's two particle indices: a copy, ``(m, 2)``."""
    @property
    def rest_lengths(self) -> npt.NDArray[np.float64]:
        """Each spring's rest length (m): a copy, ``(m,)``."""
    @property
    def bodies(self) -> List[str]:
        """The bodies' names in the scene's order."""

    def step(self, n: int = 1) -> None:
        """Advance ``n`` steps of ``dt``, with the GIL released; Ctrl-C stops
        between steps (``KeyboardInterrupt``), the World usable.

        Raises:
            BlowUp: the state ran away (``.step``, ``.time``, ``.stable_dt``).
            StepError: a step could not be taken.
        """
    def body(self, name: str) -> "Body":
        """The body called ``name`` (``KeyError`` if none)."""
    def energies(self) -> Dict[str, float]:
        """Energies (J) by ``diagnostics.csv``'s column names: ``kinetic``,
        each potential term, ``total``."""
    def save_state(self, path: str) -> None:
        """Save the state to ``path`` (written completely or not at all)."""
    def load_state(self, path: str) -> None:
        """Put back a state ``save_state`` wrote from the same scene
        (``StateError`` otherwise; the World is then unchanged)."""
    def copy(self) -> "World":
        """A new World of the same scene in the same state (gas nRT set from
        Python and external forces included)."""
    def __copy__(self) -> "World":
        """``copy.copy(world)``: as ``copy``."""
    def __deepcopy__(self, memo: object) -> "World":
        """``copy.deepcopy(world)``: as ``copy``."""
    def picture(self, width: int = 640, height: int = 480) -> bytes:
        """A PNG of the world now, drawn by ``sprung render``'s renderer."""
    def _repr_png_(self) -> bytes:
        """The picture Jupyter shows inline (640 × 480)."""


@final
class Body:
    """One body of a World, read live; it keeps its World alive."""

    nrt: Optional[float]
    """The gas's nRT (J) now, None without gas. Setting it holds nRT at
    that value from the next step on (ramp, schedule and leak dropped)."""

    @property
    def name(self) -> str:
        """The body's name."""
    @property
    def indices(self) -> npt.NDArray[np.int64]:
        """Its particles' indices in the World's arrays, ``(k,)``."""
    @property
    def volume(self) -> Optional[float]:
        """Enclosed volume (m³; area, m², in 2D); None if not closed."""
    @property
    def pressure(self) -> Optional[float]:
        """Gas pressure (Pa; N/m in 2D); None without gas."""
    @property
    def centroid(self) -> npt.NDArray[np.float64]:
        """Centre of mass (m), ``(3,)`` or ``(2,)``."""


@final
class Batch:
    """Worlds stepped together on Rust threads with the GIL released, each
    bit for bit as if stepped alone, on any number of threads."""

    def __new__(cls, worlds: Sequence[World], threads: Optional[int] = None) -> "Batch":
        """``worlds`` (distinct Worlds) on ``threads`` threads (default:
        every core, or ``SPRUNG_THREADS``)."""
    @property
    def worlds(self) -> List[World]:
        """The worlds, in the order given."""
    @property
    def threads(self) -> int:
        """The threads it runs on."""
    def __len__(self) -> int: ...
    def step(self, n: int = 1) -> None:
        """Advance every world ``n`` steps in parallel. A world that blows
        up stops there, the others finish, and ``BlowUp`` names the first
        (``.world``, its index)."""
