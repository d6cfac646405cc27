"""The exceptions sprung raises, each with the fields a program needs."""

from typing import Optional


class SceneError(ValueError):
    """A scene that cannot be read or built.

    The message is the one ``sprung run`` prints: ``FILE:LINE: what is wrong``.

    Attributes:
        path: the scene file (``<string>`` for text given to ``loads``).
        line: the 1-based line of the offending key or table, or None.
        field: the key (field) at fault where known, or None.
    """

    def __init__(self, message: str, path: Optional[str] = None,
                 line: Optional[int] = None, field: Optional[str] = None):
        super().__init__(message)
        self.path = path
        self.line = line
        self.field = field


class MeshError(SceneError):
    """A scene whose mesh file cannot be read or used.

    Attributes:
        path, line: the mesh file and the 1-based line in it (None if the
            problem is not tied to one line).
        field: ``"mesh"``.
        scene, scene_line: the scene file and the line of its ``mesh`` key.
    """

    def __init__(self, message: str, path: Optional[str] = None,
                 line: Optional[int] = None, field: Optional[str] = "mesh",
                 scene: Optional[str] = None, scene_line: Optional[int] = None):
        super().__init__(message, path, line, field)
        self.scene = scene
        self.scene_line = scene_line


class StateError(ValueError):
    """A state file that cannot be used (damaged, of another scene).

    Attributes:
        path: the state file.
    """

    def __init__(self, message: str, path: Optional[str] = None):
        super().__init__(message)
        self.path = path


class StepError(RuntimeError):
    """A step that could not be taken (a solver failure, rods that cannot
    be held, too many contacts).

    Attributes:
        step: the number of the step (1 = the first), or None.
        time: the simulated time (s), or None.
        world: in a Batch, the index of the world; else None.
        diagnostics: from ``sprung.run``, the rows recorded before it.
    """

    def __init__(self, message: str, step: Optional[int] = None,
                 time: Optional[float] = None):
        super().__init__(message)
        self.step = step
        self.time = time
        self.world = None
        self.diagnostics = None


class BlowUp(StepError):
    """The state ran away (grew without bound or stopped being finite).

    Attributes:
        step: the step that produced the bad state (1 = the first).
        time: the simulated time at its end (s).
        stable_dt: the stable time-step estimate (s): run with a dt below it.
        dt: the time step used (s).
        particle: a particle whose state is bad (index in the World).
        body: which body it belongs to, in words.
    """

    def __init__(self, message: str, step: Optional[int] = None,
                 time: Optional[float] = None,
                 stable_dt: Optional[float] = None, dt: Optional[float] = None,
                 particle: Optional[int] = None, body: Optional[str] = None):
        super().__init__(message, step, time)
        self.stable_dt = stable_dt
        self.dt = dt
        self.particle = particle
        self.body = body
