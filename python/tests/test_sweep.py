"""Sweeps: on this machine without Dask, and on a real Dask cluster of a
scheduler and two workers on 127.0.0.1, with a worker killed mid-sweep."""

import csv
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

import sprung

# A 3 × 3 grid on the 2D gas ball; dt = 0.05 s is far above its stable
# step (about 9 ms), so that row of runs blows up.
GRID = {"sim.dt": [2.5e-4, 5e-4, 0.05], "body.ball.gas.nrt": [50, 100, 150]}


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def check_grid(out, rows, cli, scenes, tmp_path):
    table = read(out / "sweep.csv")
    assert len(table) == len(rows) == 9
    assert [r["status"] for r in table] == ["ok"] * 6 + ["blew_up"] * 3
    for row in table[6:]:
        assert "blew up" in row["message"] and int(row["steps"]) < 400
    assert list(table[0])[:8] == ["sim.dt", "body.ball.gas.nrt", "id", "status", "message",
                                  "steps", "time", "wall_s"]
    assert "final.total" in table[0] and "final.ball.volume" in table[0]
    # One row against sprung run --set, bit for bit.
    row = table[4]  # dt = 5e-4, nrt = 100
    cli("run", scenes / "ball2d.toml", "--out", tmp_path / "cli", "--steps", 400, "--quiet",
        "--set", "sim.dt=5e-4", "--set", "body.ball.gas.nrt=100")
    written = (tmp_path / "cli" / "diagnostics.csv").read_text()
    run_dir = out / "runs" / row["id"]
    assert (run_dir / "diagnostics.csv").read_text() == written
    header, last = written.splitlines()[0].split(","), written.splitlines()[-1].split(",")
    assert float(row["final.total"]) == float(last[header.index("total")])
    # The run's folder repeats it alone: its scene.toml holds the steps.
    cli("run", run_dir / "scene.toml", "--out", tmp_path / "again", "--quiet")
    assert (tmp_path / "again" / "diagnostics.csv").read_text() == written


def test_local_sweep_without_dask_from_the_command_line(tmp_path, cli, scenes):
    # `python -m sprung.sweep`, in a process where dask cannot be imported.
    out = tmp_path / "sweep"
    args = [str(scenes / "ball2d.toml"), "--grid", "sim.dt=2.5e-4,5e-4,0.05",
            "--grid", "body.ball.gas.nrt=50,100,150", "--steps", "400", "--out", str(out)]
    code = ("import runpy, sys\n"
            "sys.modules['dask'] = None\n"
            "sys.modules['distributed'] = None\n"
            f"sys.argv = ['sprung.sweep'] + {args!r}\n"
            "runpy.run_module('sprung.sweep', run_name='__main__')\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert "9 runs (3 blew_up, 6 ok)" in done.stdout
    check_grid(out, range(9), cli, scenes, tmp_path)


def test_sweep_stays_a_function_when_its_module_is_imported():
    # `sprung.sweep` is the function; its module (what `python -m
    # sprung.sweep` runs) is a plain module, its class never swapped, and
    # importing it by name does not rebind the package's attribute.
    code = ("import sys, types, sprung\n"
            "function = sprung.sweep\n"
            "import sprung.sweep\n"
            "module = sys.modules['sprung.sweep']\n"
            "assert sprung.sweep is function and callable(function), sprung.sweep\n"
            "assert type(module) is types.ModuleType and module.sweep is function\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    # Run as a program with warnings as errors: runpy warns when a plain
    # module it runs was imported first; a package's __main__ is not.
    done = subprocess.run([sys.executable, "-W", "error", "-m", "sprung.sweep", "--help"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and done.stderr == "", done.stderr
    assert done.stdout.startswith("usage: python -m sprung.sweep")


def test_command_line_values_are_read_as_set_reads_them():
    from sprung.sweep.__main__ import parse_value
    assert parse_value("1e-4") == 1e-4 and parse_value("100") == 100
    assert parse_value("true") is True and parse_value("rk4") == "rk4"
    assert parse_value('"rk4"') == "rk4" and parse_value("[0, 1]") == [0, 1]


def test_refused_values_are_rows_and_reruns_skip_what_ended(tmp_path, scenes):
    out = tmp_path / "sweep"
    grid = {"body.ball.stiffness": [-1.0, 2000.0], "body.nothing.mass": [1.0]}
    rows = sprung.sweep(scenes / "ball2d.toml", grid={"body.ball.stiffness": [-1.0, 2000.0]},
                        steps=50, out=out, progress=False)
    assert [r["status"] for r in rows] == ["error", "ok"]
    assert "must not be negative" in rows[0]["message"]
    assert f"runs/{rows[0]['id']}/scene.toml:" in rows[0]["message"]
    rows = sprung.sweep(scenes / "ball2d.toml", grid=grid, steps=50, out=tmp_path / "b",
                        progress=False)
    assert {r["status"] for r in rows} == {"error"}
    assert "nothing" in rows[0]["message"]
    stamps = {p: p.stat().st_mtime_ns for p in (out / "runs").glob("*/result.json")}
    again = sprung.sweep(scenes / "ball2d.toml", grid={"body.ball.stiffness": [-1.0, 2000.0]},
                         steps=50, out=out, progress=False)
    assert [r["status"] for r in again] == ["error", "ok"]
    assert {p: p.stat().st_mtime_ns for p in (out / "runs").glob("*/result.json")} == stamps


def test_what_a_dead_attempt_left_half_written_is_cleared(tmp_path, scenes):
    # A worker killed mid-run leaves its temporary folder (with a
    # result.json, if it died just before the rename): the sweep clears it
    # once every run has ended, and leaves folders of no run of its own.
    grid = {"body.ball.gas.nrt": [50]}
    first = sprung.sweep(scenes / "ball2d.toml", grid=grid, steps=20, out=tmp_path,
                         progress=False)
    runs = tmp_path / "runs"
    dead = runs / f"{first[0]['id']}.partial-k1ll3d"
    dead.mkdir()
    (dead / "result.json").write_text("{}")
    stranger = runs / "not-a-run.partial-x"
    stranger.mkdir()
    again = sprung.sweep(scenes / "ball2d.toml", grid=grid, steps=20, out=tmp_path,
                         progress=False)
    assert again == first
    assert not dead.exists()
    assert stranger.exists()
    assert sorted(p.parent.name for p in runs.glob("*/result.json")) == [first[0]["id"]]


def test_latin_hypercube_is_stratified_and_reproducible():
    from sprung.sweep._sampling import latin_hypercube
    points = latin_hypercube({"a": (0.0, 1.0), "b": (10.0, 20.0)}, 8, seed=3)
    assert points == latin_hypercube({"a": (0.0, 1.0), "b": (10.0, 20.0)}, 8, seed=3)
    assert points != latin_hypercube({"a": (0.0, 1.0), "b": (10.0, 20.0)}, 8, seed=4)
    # Each of the 8 strata of each range holds exactly one point.
    assert sorted(int(p["a"] * 8) for p in points) == list(range(8))
    assert sorted(int((p["b"] - 10.0) / 10.0 * 8) for p in points) == list(range(8))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def cluster(tmp_path):
    """A Dask scheduler and two single-thread workers on 127.0.0.1, always
    stopped; yields (address, worker processes)."""
    pytest.importorskip("distributed")
    dask = str(Path(sys.executable).parent / "dask")
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    logs = open(tmp_path / "cluster.log", "w")
    common = dict(stdout=logs, stderr=subprocess.STDOUT, cwd=tmp_path)
    scheduler = subprocess.Popen([dask, "scheduler", "--host", "127.0.0.1", "--port", str(port),
                                  "--dashboard-address", ":0"], **common)
    workers = [subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--nworkers", "1",
                                 "--no-nanny", "--dashboard-address", ":0",
                                 "--local-directory", str(tmp_path / f"w{k}")], **common)
               for k in range(2)]
    try:
        from dask.distributed import Client
        with Client(address, timeout=60) as client:
            client.wait_for_workers(2, timeout=90)
        yield address, workers
    finally:
        for process in workers + [scheduler]:
            if process.poll() is None:
                process.send_signal(signal.SIGTERM)
        for process in workers + [scheduler]:
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
        logs.close()


@pytest.mark.timeout(300)
def test_sweep_on_a_dask_cluster(tmp_path, cli, scenes, cluster):
    address, workers = cluster
    out = tmp_path / "sweep"
    rows = sprung.sweep(scenes / "ball2d.toml", grid=GRID, steps=400, out=out,
                        scheduler=address, progress=False)
    check_grid(out, rows, cli, scenes, tmp_path)
    stamps = {p: p.stat().st_mtime_ns for p in (out / "runs").glob("*/result.json")}
    sprung.sweep(scenes / "ball2d.toml", grid=GRID, steps=400, out=out, scheduler=address,
                 progress=False)
    assert {p: p.stat().st_mtime_ns for p in (out / "runs").glob("*/result.json")} == stamps


@pytest.mark.timeout(300)
def test_a_worker_killed_mid_sweep_costs_only_time(tmp_path, scenes, cluster):
    address, workers = cluster
    out = tmp_path / "sweep"
    # Eight runs of about a second each; one worker is killed after the
    # first has ended, with runs on it half done.
    import threading

    def kill_when_started():
        deadline = time.time() + 120
        while time.time() < deadline:
            if list((out / "runs").glob("*/result.json")):
                workers[0].kill()
                return
            time.sleep(0.05)

    killer = threading.Thread(target=kill_when_started)
    killer.start()
    rows = sprung.sweep(scenes / "ball3d.toml", grid={"body.ball.gas.nrt": [400, 450, 500, 550, 600, 650, 700, 750]},
                        steps=3000, out=out, scheduler=address, progress=False)
    killer.join()
    assert workers[0].poll() is not None  # it was killed
    assert [r["status"] for r in rows] == ["ok"] * 8
    assert len(list((out / "runs").glob("*/result.json"))) == 8
    # What the killed worker was writing is gone with it: only whole runs.
    assert not list((out / "runs").glob("*.partial-*"))
    for row in rows:
        assert row["steps"] == 3000


def test_a_run_that_fails_unexpectedly_is_a_row(tmp_path, scenes, monkeypatch):
    from sprung.sweep import _runs as engine
    real = engine.run_task

    def flaky(task):
        if "gas.nrt = 100" in task["scene"] or "nrt = 100\n" in task["scene"]:
            raise OSError("disk full")
        return real(task)

    monkeypatch.setattr(engine, "run_task", flaky)
    rows = sprung.sweep(scenes / "ball2d.toml", grid={"body.ball.gas.nrt": [50, 100]},
                        steps=20, out=tmp_path, progress=False)
    assert [r["status"] for r in rows] == ["ok", "error"]
    assert rows[1]["message"] == "OSError: disk full"
    assert len(read(tmp_path / "sweep.csv")) == 2


def test_frames_only_when_asked(tmp_path, scenes):
    rows = sprung.sweep(scenes / "ball2d.toml", grid={"body.ball.gas.nrt": [50]}, steps=20,
                        every=10, out=tmp_path / "a", progress=False)
    assert not (tmp_path / "a" / "runs" / rows[0]["id"] / "frames").exists()
    rows = sprung.sweep(scenes / "ball2d.toml", grid={"body.ball.gas.nrt": [50]}, steps=20,
                        every=10, out=tmp_path / "b", frames="vtk", progress=False)
    frames = tmp_path / "b" / "runs" / rows[0]["id"] / "frames"
    assert len(list(frames.glob("frame_*.vtk"))) == 3
