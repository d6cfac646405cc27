"""The programs in python/examples run (shortened where they take an
argument) and say what they should."""

import subprocess
import sys
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run(name, *args, cwd):
    done = subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)],
                          capture_output=True, text=True, cwd=cwd)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_inflate(tmp_path):
    out = run("inflate.py", tmp_path / "out", cwd=tmp_path)
    assert (tmp_path / "out" / "diagnostics.csv").is_file()
    assert (tmp_path / "out" / "energy.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "final pressure" in out


def test_controller_holds_the_ball(tmp_path):
    out = run("controller.py", cwd=tmp_path)
    # "... the ball's centre is at [-1.5  1. ] (target ...)": the PD
    # controller settles within a millimetre after 2 s.
    centre = out.split("is at [")[1].split("]")[0].split()
    assert abs(float(centre[0]) + 1.5) < 1e-3 and abs(float(centre[1]) - 1.0) < 1e-3, out


def test_the_crawler_walks_only_when_pumped(tmp_path):
    out = run("gas_walker.py", 10, cwd=tmp_path)
    walked = float(out.split("walked ")[1].split(" mm")[0])
    stayed = float(out.split("moved ")[1].split(" mm")[0])
    # About 4 mm a pump; left alone, the crawler settles in place.
    assert walked > 25 and stayed < 3, out
