"""``python -m sprung.sweep SCENE --grid KEY=V1,V2 ... --out DIR``: a
parameter sweep from the command line (``sprung.sweep`` from Python)."""

import sys
import types

from . import _sweep
from ._sweep import main


class _CallableModule(types.ModuleType):
    """Importing ``sprung.sweep`` binds this module where the function
    ``sprung.sweep`` was: calling it still runs a sweep."""

    def __call__(self, *args, **kwargs):
        return _sweep.sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule

if __name__ == "__main__":
    sys.exit(main())
