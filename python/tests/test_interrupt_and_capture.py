"""Ctrl-C during a blocking read, and captures read into NumPy."""

import json
import os
import signal
import sqlite3
import subprocess
import threading
import time

import pytest

import rangekit
from conftest import LS5_ARGUMENTS, LS5_SCENE, samples


def interrupt_when_waiting(stream, sent_at):
    """Sends SIGINT to this process once the stream is inside its blocking wait (the
    stream says so: `waiting`), as Ctrl-C in a terminal would; no sleep stands in for it.
    The moment it is sent goes into `sent_at`."""

    def watch():
        while not stream.waiting:
            threading.Event().wait(0.001)
        sent_at.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    return watcher


@pytest.mark.parametrize("how", ["read", "iterate"])
def test_ctrl_c_during_a_blocking_read_returns_promptly(ls5_unit, how):
    with rangekit.ls5.open(ls5_unit.port) as drv:
        with drv.stream(thinning=1) as stream:
            samples(stream, 1)
            if how == "iterate":
                ls5_unit.kill()  # nothing arrives any more: the iterator blocks
            sent_at = []
            watcher = interrupt_when_waiting(stream, sent_at)
            with pytest.raises(KeyboardInterrupt):
                if how == "read":
                    stream.read(duration=3600)  # an hour's read, interrupted
                else:
                    for _ in stream:
                        pass
            raised_at = time.monotonic()
            watcher.join()
            # Promptly: the wait wakes in 50 ms slices to look for signals (0.005-0.05 s
            # measured); 5 s tells that from a read that waits for data or its hour.
            assert raised_at - sent_at[0] < 5.0
            assert not stream.waiting


def test_read_keeps_the_events_it_met_in_order(ls5_unit):
    with rangekit.ls5.open(ls5_unit.port) as drv:
        stream = drv.stream(thinning=1, reconnect_interval=0.1)
        block = stream.read(5)
        assert len(block) == 5
        assert [event.kind for event in stream.take_events()] == ["connected"]
        assert stream.take_events() == []
        stream.stop()


def test_capture_samples_as_numpy(tmp_path):
    # A capture written by the CLI (`rangekit capture`), read back by the package and
    # compared with the CLI's own replay of the same file.
    path = tmp_path / "run.sqlite"
    cli = rangekit.sim.cli_path()
    with rangekit.sim.ls5(scene=LS5_SCENE, arguments=LS5_ARGUMENTS) as unit:
        subprocess.run([cli, "capture", "--out", str(path), "--ls5", unit.port, "--ls5-thinning", "1",
                        "--count", "40", "--quiet"], check=True, timeout=120)
    replay = subprocess.run([cli, "replay", "--full-speed", "--format", "jsonl", str(path)], check=True,
                            capture_output=True, text=True, timeout=120)
    lines = [json.loads(line) for line in replay.stdout.splitlines() if line.strip()]
    codes = [line["code"] for line in lines if "code" in line]

    capture = rangekit.capture.open(path)
    assert capture.samples.dtype == rangekit.sample_dtype
    assert len(capture) == len(codes) == 40
    assert list(capture.samples["code"]) == codes
    assert (capture.samples["code"] == 12500).all()
    assert capture.samples["distance_m"] == pytest.approx(0.025)
    assert len(capture.of_kind("result")) == 40
    assert len(rangekit.capture.open(path, device="uls")) == 0
    with pytest.raises(rangekit.errors.LinkError):
        rangekit.capture.open(tmp_path / "missing.sqlite")


def test_capture_dataframe_when_pandas_is_there(tmp_path):
    pandas = pytest.importorskip("pandas")
    path = tmp_path / "run.sqlite"
    with rangekit.sim.ls5(scene=LS5_SCENE, arguments=LS5_ARGUMENTS) as unit:
        subprocess.run([rangekit.sim.cli_path(), "capture", "--out", str(path), "--ls5", unit.port, "--count", "5",
                        "--quiet"], check=True, timeout=120)
    frame = rangekit.capture.open(path).dataframe()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame["kind"].unique()) == ["result"]


def test_corrupt_capture_is_a_clear_error(tmp_path):
    # docs/capture.md: a corrupt file is refused with an error naming it. The integrity check
    # runs beside the bulk read: a damaged page must still raise, not crash or return
    # what happened to be readable.
    path = tmp_path / "corrupt.sqlite"
    with rangekit.sim.ls5(arguments=LS5_ARGUMENTS) as unit:
        subprocess.run([rangekit.sim.cli_path(), "capture", "--out", str(path), "--ls5", unit.port, "--count", "1",
                        "--quiet"], check=True, timeout=120)
    database = sqlite3.connect(path)
    database.execute("INSERT INTO samples(session, time_ns, device, source, address, kind, code, distance_mm, "
                     "signal) SELECT session, time_ns, device, source, address, kind, code, distance_mm, signal "
                     "FROM samples, (WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 2000) "
                     "SELECT i FROM n)")
    database.commit()
    page_size = database.execute("PRAGMA page_size").fetchone()[0]
    database.close()
    assert len(rangekit.capture.open(path)) == 2001
    content = bytearray(path.read_bytes())
    assert len(content) > 4 * page_size
    content[2 * page_size:3 * page_size] = b"\xa5" * page_size  # garbage over a b-tree page of the samples
    path.write_bytes(bytes(content))
    with pytest.raises(rangekit.errors.LinkError, match="corrupt") as raised:
        rangekit.capture.open(path)
    assert str(path) in str(raised.value)
