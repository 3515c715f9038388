"""rangekit.ls5 against the LS5 emulator (rangekit.sim.ls5): open, get, set, single
result, stream; refusals before anything is written."""

import threading

import pytest

import rangekit
from conftest import first_event, samples

# LS5 §8 formula: "code = distance / range · 50000"; the scene's surface at 25 mm of a
# 100 mm range (lower boundary 0) is code 12500, and formula 8.1 gives 25 mm back.
EXPECTED_CODE = 12500
EXPECTED_MM = 25.0


def test_open_info_and_get_all(ls5_unit):
    with rangekit.ls5.open(ls5_unit.port, address=1) as drv:
        info = drv.info()
        assert info["version"] == "LS5.12.0"
        assert info["range_mm"] == pytest.approx(100.0)
        assert info["serial_number"] == 157
        assert info["ethernet"] is True  # LS5.12 answers R70
        values = drv.get_all()
        assert values["network-address"] == 1  # §8.1, factory address 1
        assert rangekit.ls5.setting_units()["period-ms"] == "ms"


def test_set_then_get(ls5_unit):
    with rangekit.ls5.open(ls5_unit.port) as drv:
        drv.settings["thinning"] = 4  # §8.4 n
        assert drv.settings["thinning"] == 4
        drv.set(median_points=7)
        assert drv.get("median-points") == 7


def test_out_of_range_value_raises_before_anything_is_written(ls5_unit):
    # Table 9.2, parameter 08 (thinning n): 01-FF. A refused value changes nothing.
    with rangekit.ls5.open(ls5_unit.port) as drv:
        drv.settings["thinning"] = 4
        with pytest.raises(rangekit.errors.SettingError) as raised:
            drv.settings["thinning"] = 999
        assert raised.value.code == "out_of_range"
        # Several at once: the bad second value stops the good first one too.
        with pytest.raises(rangekit.errors.SettingError):
            drv.set_many([("median-points", 9), ("thinning", 0)])
        assert drv.settings["thinning"] == 4
        assert drv.settings["median-points"] == 5  # the factory value, unchanged
        with pytest.raises(rangekit.errors.SettingError):
            drv.get("no-such-setting")


def test_out_of_range_value_raises_before_anything_is_sent(silent_line):
    # Table 9.2, parameter 08 (thinning n): 01-FF; median points 1-49 odd. Nothing behind the
    # line: no byte may be sent, not even the ID the sensor's own checks need.
    with rangekit.ls5.open(silent_line.path, timeout=0.2) as drv:
        with pytest.raises(rangekit.errors.SettingError) as raised:
            drv.settings["thinning"] = 999
        assert raised.value.code == "out_of_range"
        with pytest.raises(rangekit.errors.SettingError):
            drv.set_many([("thinning", 4), ("median-points", 8)])
        with pytest.raises(rangekit.errors.SettingError):
            drv.set_many([("thinning", 4), ("no-such-setting", 1)])
        assert not silent_line.written()


def test_a_reader_that_falls_behind_gets_a_lost_records_event_before_what_is_left(ls5_unit):
    # The emulator's 1 kHz records (§8.4, n = 1) overflow an 8-record queue nobody reads; the
    # wait is on the stream's own loss count, not on a clock.
    with rangekit.ls5.open(ls5_unit.port) as drv:
        with drv.stream(thinning=1, queue_capacity=8) as stream:
            while stream.lost == 0:
                threading.Event().wait(0.005)
            counted = stream.lost
            first = stream.next(timeout=5)
            # The oldest were dropped, so the gap comes before everything the queue still held.
            assert first.is_event and first.kind == "lost_records", first
            assert counted <= first.count <= stream.lost
            # Once caught up, every record lost is in some event's count, none twice.
            reported = first.count
            for item in [stream.next(timeout=5) for _ in range(200)]:
                if item.is_event and item.kind == "lost_records":
                    reported += item.count
            assert reported <= stream.lost
    with pytest.raises(ValueError):
        with rangekit.ls5.open(ls5_unit.port) as drv:
            drv.stream(queue_capacity=0)


def test_single_result(ls5_unit):
    with rangekit.ls5.open(ls5_unit.port) as drv:
        stream = drv.stream(thinning=1)
        samples(stream, 1)  # a measurement has been made (65534 before: "no measurement yet")
        stream.stop()
        sample = drv.measure()  # LR
        assert sample.kind == "result"
        assert sample.code == EXPECTED_CODE
        assert sample.distance_mm == pytest.approx(EXPECTED_MM)


def test_stream_iterator_and_numpy_values(ls5_unit):
    with rangekit.ls5.open(ls5_unit.port) as drv:
        with drv.stream(thinning=1) as stream:
            assert first_event(stream).kind == "connected"
            for sample in samples(stream, 3):
                assert sample.code == EXPECTED_CODE
                assert sample.distance_mm == pytest.approx(EXPECTED_MM)
                assert sample.signal == "ok"
            block = stream.read(50)
    assert block.dtype == rangekit.sample_dtype
    assert block.dtype["time"] == "<f8" and block.dtype["distance_m"] == "<f8"
    assert block.dtype["code"] == "<u2" and block.dtype["flags"] == "u1"
    assert len(block) == 50
    assert (block["code"] == EXPECTED_CODE).all()
    assert block["distance_m"] == pytest.approx(EXPECTED_MM / 1000.0)
    assert (block["kind"] == rangekit.sample_kinds.index("result")).all()
    assert (block["flags"] == rangekit.FLAG_VALID).all()
    assert (block["address"] == 1).all()
    assert (block["time"][1:] >= block["time"][:-1]).all()  # in receive order


def test_stream_read_by_duration(ls5_unit):
    with rangekit.ls5.open(ls5_unit.port) as drv:
        with drv.stream(thinning=1) as stream:
            block = stream.read(duration=0.3)
    assert block.dtype == rangekit.sample_dtype
    assert (block["code"] == EXPECTED_CODE).all()


def test_other_calls_are_refused_while_streaming(ls5_unit):
    with rangekit.ls5.open(ls5_unit.port) as drv:
        with drv.stream(thinning=1):
            with pytest.raises(rangekit.errors.UnsupportedError):
                drv.get("thinning")


def test_killed_emulator_yields_disconnected_then_reconnected(ls5_unit):
    with rangekit.ls5.open(ls5_unit.port) as drv:
        stream = drv.stream(thinning=1, reconnect_interval=0.1)
        assert first_event(stream).kind == "connected"
        samples(stream, 3)
        ls5_unit.kill()  # the pty and its path vanish: a cable pulled out
        assert first_event(stream).kind == "disconnected"
        ls5_unit.restart()
        assert first_event(stream).kind == "reconnected"
        assert samples(stream, 1)[0].code == EXPECTED_CODE
        stream.stop()


def test_batches_hand_out_every_item_once_in_order_across_read_and_iteration(ls5_unit):
    """The stream takes the driver's queue in batches (everything queued, with one lock):
    read(n) leaves the rest of a batch for the next read() or the iterator, and a link's
    events stay where they came among the samples."""
    with rangekit.ls5.open(ls5_unit.port) as drv:
        stream = drv.stream(thinning=1, reconnect_interval=0.1)
        assert first_event(stream).kind == "connected"
        block = stream.read(2)  # waits for a batch of several records and takes two
        following = next(stream)  # the next one: from the same batch, not a later one
        assert not following.is_event and following.code == EXPECTED_CODE
        assert block["time"][0] <= block["time"][1] <= following.time
        ls5_unit.kill()
        items = []
        for item in stream:  # the samples still queued, then the loss of the link
            items.append(item)
            if item.is_event and item.kind == "disconnected":
                break
        kinds = [item.kind if item.is_event else "sample" for item in items]
        # Samples first, at most a half frame's bad_frame, the disconnection last.
        assert kinds[-1] == "disconnected"
        assert kinds[:-1] == sorted(kinds[:-1], key=lambda kind: kind != "sample")
        assert set(kinds[:-1]) <= {"sample", "bad_frame"}
        times = [item.time for item in items]
        assert times == sorted(times)
        ls5_unit.restart()
        block = stream.read(3)  # the reconnection's event comes first, then the records
        assert len(block) == 3 and (block["code"] == EXPECTED_CODE).all()
        assert [event.kind for event in stream.take_events()] == ["reconnected"]
        stream.stop()


# L71: a record further from the running median than max_speed allows is
# marked suspect, as `rangekit ls5 stream` marks it; drop_suspect leaves it out. LS5 100/200
# (range 200 mm): the scene jumps 160 mm in 1 ms every second, beyond the default max_speed
# (the range a second, 0.2 m/s); the emulator's own noise is within table 3.1's ±0.15 %.
JUMPING_SCENE = {
    "target": {"path": [[0.0, 120.0], [1.0, 120.0], [1.001, 280.0], [2.0, 280.0], [2.001, 120.0]], "repeat": True}
}


def test_jumps_are_marked_suspect_and_drop_suspect_leaves_them_out():
    with rangekit.sim.ls5(scene=JUMPING_SCENE, arguments=["--model", "100/200"]) as unit:
        with rangekit.ls5.open(unit.port) as drv:
            with drv.stream() as stream:
                marked = [s for s in samples(stream, 350) if s.suspect]
                block = stream.read(350)
            assert marked, "350 records at 10 ms meet at least two jumps"
            assert all(s.suspect_reason.startswith("jump: ") for s in marked)
            flagged = (block["flags"] & rangekit.FLAG_SUSPECT) != 0
            assert 0 < flagged.sum() <= 3 * 8  # a jump is flagged until the median of five moves
            with drv.stream(drop_suspect=True) as stream:
                kept = stream.read(350)
            assert len(kept) == 350
            assert not ((kept["flags"] & rangekit.FLAG_SUSPECT) != 0).any()
            with drv.stream(check_quality=False) as stream:
                assert not any(s.suspect for s in samples(stream, 350))
            with pytest.raises(ValueError, match="max_speed"):
                drv.stream(max_speed=0)
