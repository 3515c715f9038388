"""rangekit.uls against the ULS emulator (rangekit.sim.uls): open, get, set, single
measurement, stream; refusals before anything is sent; errors with §10 numbers."""

import pytest

import rangekit
from conftest import first_event, samples


def test_open_info_and_get_all(uls_unit):
    with rangekit.uls.open(uls_unit.port) as drv:
        info = drv.info()
        assert info["version"]  # §8 ID: the unit's version text
        values = drv.get_all()
        # The names of `rangekit uls get`, the unit in the name; PF's three PRFs (§8 Set/Get PRF:
        # "$PF,n,n,n where n,n,n is Averaging,Binning,Look Down").
        assert isinstance(values["prf-hz"], list) and len(values["prf-hz"]) == 3
        assert values["mode"] in ("averaging", "binning", "look-down")
        assert list(drv.settings)[: len(rangekit.uls.readable_names())] == rangekit.uls.readable_names()


def test_set_then_get_through_the_settings_mapping(uls_unit):
    with rangekit.uls.open(uls_unit.port) as drv:
        drv.settings["prf-hz"] = 3000  # §2 PRF: "Values range from 10 to 5000"
        assert drv.settings["prf-hz"][0] == 3000
        drv.set(short_gate_m=1.5)
        assert drv.get("short-gate-m") == pytest.approx(1.5)
        drv.settings.update({"averaging-weight": 100, "ppm": 200})
        assert drv.get("averaging-weight") == 100


def test_out_of_range_value_raises_before_anything_is_sent(silent_line):
    # §2 PRF: "Values range from 10 to 5000." Nothing behind the line: no byte may be sent.
    with rangekit.uls.open(silent_line.path, timeout=0.2) as drv:
        with pytest.raises(rangekit.errors.SettingError) as raised:
            drv.settings["prf-hz"] = 6000
        assert raised.value.code == "out_of_range"
        assert isinstance(raised.value, ValueError)
        with pytest.raises(rangekit.errors.SettingError):
            drv.set_many({"mode": "binning", "no-such-setting": 1})
        assert not silent_line.written()


def test_device_error_carries_the_section_10_number_and_text(uls_unit):
    # §10 error 31 "Already Measuring": settings are refused while the unit measures (U24).
    with rangekit.uls.open(uls_unit.port) as drv:
        drv.start_measuring()
        with pytest.raises(rangekit.errors.DeviceError) as raised:
            drv.settings["mode"] = "binning"
        assert raised.value.number == 31
        assert "Already Measuring" in raised.value.text
        drv.stop_measuring()


def test_single_measurement(uls_unit):
    # The emulator's default scene: "one 90 % white target at 50 m" (docs/emulator-uls.md).
    with rangekit.uls.open(uls_unit.port) as drv:
        sample = drv.measure()
        assert sample.kind == "averaging"
        assert sample.device == "uls"
        assert sample.distance_m == pytest.approx(50.0, abs=0.05)


def test_stream_iterates_samples_and_reads_numpy(uls_unit):
    with rangekit.uls.open(uls_unit.port) as drv:
        # A measurement every 50 ms (§2 "The Pulses/Measurement divided by the PRF establishes the
        # measurement output"); the average weight below PPM (§10 error 49).
        drv.set_many({"prf-hz": 2000, "averaging-weight": 50, "ppm": 100})
        with drv.stream() as stream:
            assert first_event(stream).kind == "connected"
            for sample in samples(stream, 3):
                assert sample.distance_m == pytest.approx(50.0, abs=0.05)
            block = stream.read(5)
        assert block.dtype == rangekit.sample_dtype
        assert len(block) == 5
        assert (block["kind"] == rangekit.sample_kinds.index("averaging")).all()
        assert (abs(block["distance_m"] - 50.0) < 0.05).all()
        assert (block["flags"] & rangekit.FLAG_VALID).all()


def test_killed_emulator_yields_disconnected_then_reconnected(uls_unit):
    with rangekit.uls.open(uls_unit.port) as drv:
        drv.set_many({"prf-hz": 2000, "averaging-weight": 50, "ppm": 100})
        stream = drv.stream()
        assert first_event(stream).kind == "connected"
        samples(stream, 2)
        uls_unit.kill()  # the pty and its path vanish: a cable pulled out
        event = first_event(stream)
        while event.kind == "polling":
            event = first_event(stream)
        assert event.kind == "disconnected"
        uls_unit.restart()  # the same path again
        event = first_event(stream)
        assert event.kind == "reconnected"
        assert samples(stream, 1)[0].distance_m == pytest.approx(50.0, abs=0.05)
        stream.stop()
