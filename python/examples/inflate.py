"""A 3D gas ball inflated on a floor, its energies plotted.

    python python/examples/inflate.py [OUT_DIR]

Loads scenes/ball3d.toml, runs it for 1.5 s with sprung.run (the numbers
`sprung run` writes), and plots the energy terms with matplotlib when it
is installed (sprung does not need it), else with sprung's own plot.
"""

import os
import sys
from pathlib import Path

import sprung

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "ball3d.toml"
out = Path(sys.argv[1] if len(sys.argv) > 1 else "out/python/inflate")
out.mkdir(parents=True, exist_ok=True)

table = sprung.run(SCENE, time=1.5, out=out)
print(f"{len(table['step'])} rows; final pressure {table['ball.pressure'][-1]:.1f} Pa, "
      f"volume {table['ball.volume'][-1]:.4f} m³")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sprung.plot(table)["energy"].save(out / "energy.png")
else:
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for name in ("kinetic", "spring", "gravity", "gas", "total"):
        ax.plot(table["time"], table[name], label=name)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J)")
    ax.legend()
    fig.savefig(out / "energy.png", dpi=100)
print(f"plot: {os.path.join(out, 'energy.png')}")
