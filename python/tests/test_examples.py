"""The examples of examples/python run against the emulators, as a user would run them."""

import os
import subprocess
import sys

import rangekit
from conftest import LS5_ARGUMENTS, LS5_SCENE

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python")


def run_example(name, *arguments):
    return subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *arguments], capture_output=True, text=True,
                          timeout=120, env=dict(os.environ))


def test_stream_to_csv(tmp_path):
    out = tmp_path / "out.csv"
    with rangekit.sim.ls5(scene=LS5_SCENE, arguments=LS5_ARGUMENTS) as unit:
        done = run_example("stream_to_csv.py", "ls5", unit.port, str(out), "--count", "20")
    assert done.returncode == 0, done.stderr
    rows = out.read_text().splitlines()
    assert rows[0] == "time,distance_m,intensity,code,error,kind,flags"
    assert len(rows) == 21
    assert all(",12500,0,result," in row for row in rows[1:])


def test_rig_script(tmp_path):
    log = tmp_path / "rig.csv"
    with rangekit.sim.ls5(scene=LS5_SCENE, arguments=LS5_ARGUMENTS) as unit:
        done = run_example("rig.py", unit.port, "--serial", "157", "--range-mm", "100", "--seconds", "0.5",
                           "--log", str(log))
        assert done.returncode == 0, done.stdout + done.stderr
        assert "s/n 157" in done.stdout
        wrong = run_example("rig.py", unit.port, "--serial", "158", "--seconds", "0.1", "--log", str(log))
        assert wrong.returncode == 1
        assert "wrong sensor" in wrong.stderr
    assert log.read_text().startswith("time,code,distance_mm\n")


def test_plot_without_matplotlib_or_with_it(tmp_path):
    png = tmp_path / "plot.png"
    with rangekit.sim.ls5(scene=LS5_SCENE, arguments=LS5_ARGUMENTS) as unit:
        done = run_example("plot.py", "ls5", unit.port, "--seconds", "0.3", "--png", str(png))
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        assert done.returncode == 2 and "needs matplotlib" in done.stderr
    else:
        assert done.returncode == 0, done.stderr
        assert png.stat().st_size > 0
