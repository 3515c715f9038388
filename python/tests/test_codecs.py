"""The codecs from Python: rangekit.uls.decode_line and rangekit.ls5.parse_udp; the
expectations are the documents' examples and formulas, typed by hand."""

import math

import numpy
import pytest

import rangekit


def test_uls_averaging_line_in_metres():
    # ULS §9: "$BM,xxxx.xxx<CR>" in averaging, range display; metres with 3 decimals.
    sample = rangekit.uls.decode_line(b"$BM,12.345\r")
    assert sample.kind == "averaging"
    assert sample.distance_m == pytest.approx(12.345)
    assert sample.pulse_width_ns is None


def test_uls_line_in_feet_is_converted_to_metres():
    # ULS §8 MU: units feet; 40.50 ft = 12.3444 m (1 ft = 0.3048 m).
    sample = rangekit.uls.decode_line(b"$BM,40.50\r", units="feet")
    assert sample.distance_m == pytest.approx(12.3444)


def test_uls_range_and_intensity_gives_the_pulse_width():
    # ULS §9: "$BM,xxxx.xxx,yyyyyyy<CR>" with DM range and intensity: the pulse width in ps (U8).
    sample = rangekit.uls.decode_line(b"$BM,50.000,33238\r", display="range-and-intensity")
    assert sample.distance_m == pytest.approx(50.0)
    assert sample.pulse_width_ns == pytest.approx(33.238)
    # U92: one name for the quantity, its unit last, as in jsonl, csv and the API.
    assert not hasattr(sample, "pulse_width")


def test_uls_error_line_carries_the_section_10_text():
    # ULS §10: error 4 "Lock Not Found" (display "Target Not Found"), streamed as $ER,4 (U13).
    sample = rangekit.uls.decode_line(b"$ER,4\r")
    assert sample.kind == "error"
    assert sample.device_error == 4
    assert "Lock Not Found" in sample.error_text
    assert "Lock Not Found" in rangekit.uls.error_text(4)


def test_uls_bad_line_raises_decode_error():
    with pytest.raises(rangekit.errors.DecodeError) as raised:
        rangekit.uls.decode_line(b"BM,12.345\r")
    assert raised.value.code == "invalid_frame"
    assert isinstance(raised.value, ValueError)


def udp_packet(records, serial, lower_mm, range_mm, counter):
    """LS5 §10.1 "The format of the data packet", byte by byte: 168 × (low, high, state),
    serial number, lower boundary and range (low byte first), counter, and the checksum
    "calculated as excluding OR all bytes ... excluding the byte of the packet number loop counter"."""
    data = bytearray(512)
    for index in range(168):
        code, state = records[index] if index < len(records) else (0, 0x02)
        data[3 * index] = code & 0xFF
        data[3 * index + 1] = code >> 8
        data[3 * index + 2] = state
    for offset, value in ((504, serial), (506, lower_mm), (508, range_mm)):
        data[offset] = value & 0xFF
        data[offset + 1] = value >> 8
    data[510] = counter
    checksum = 0
    for byte in data[:510]:
        checksum ^= byte
    data[511] = checksum
    return bytes(data)


def test_ls5_udp_packet_records_and_formula_10_1():
    # §10.1: state bit 0 measured, bit 1 always 1, bit 2 in range, bit 3 derivative;
    # formula 10.1: distance = range · code / 4000h.
    packet = udp_packet([(0x2000, 0x07), (0x4000, 0x07), (0x1000, 0x03), (0x1000, 0x0F)],
                        serial=157, lower_mm=8, range_mm=100, counter=9)
    decoded = rangekit.ls5.parse_udp(packet)
    assert decoded["serial_number"] == 157
    assert decoded["lower_boundary_mm"] == 8
    assert decoded["range_mm"] == 100
    assert decoded["counter"] == 9
    records = decoded["records"]
    assert len(records) == 168
    assert records.dtype["code"] == numpy.dtype("<u2")
    assert list(records["code"][:4]) == [0x2000, 0x4000, 0x1000, 0x1000]
    assert records["distance_mm"][0] == pytest.approx(50.0)
    assert records["distance_mm"][1] == pytest.approx(100.0)
    assert math.isnan(records["distance_mm"][2])  # bit 2 is 0: "OUT OF RANGE"
    assert math.isnan(records["distance_mm"][3])  # bit 3 is 1: a derivative, not a distance


def test_ls5_udp_packet_with_a_wrong_checksum_raises():
    packet = bytearray(udp_packet([], 1, 0, 100, 0))
    packet[511] ^= 0xFF
    with pytest.raises(rangekit.errors.DecodeError):
        rangekit.ls5.parse_udp(bytes(packet))
    with pytest.raises(rangekit.errors.DecodeError):
        rangekit.ls5.parse_udp(b"\x00" * 100)


def test_help_lists_every_setting_with_its_range():
    # help() shows the ranges (docs/python.md). Typed from the documents: ULS §2 PRF "Values
    # range from 10 to 5000", §9 1700 m the longest gate; LS5 table 9.2 median filter points
    # 1-49, odd (parameter 0D: 01h-31h, step 2).
    import pydoc

    uls_help = pydoc.render_doc(rangekit.uls, renderer=pydoc.plaintext)
    assert "prf-hz: 10..5000 Hz" in uls_help
    assert "short-gate-m: 0..1700 metres" in uls_help
    assert rangekit.uls.setting_ranges()["version"] == "read only"
    ls5_help = pydoc.render_doc(rangekit.ls5, renderer=pydoc.plaintext)
    assert "median-points: 1, 3, ..., 49 (odd)" in ls5_help
    assert set(rangekit.ls5.setting_ranges()) == set(rangekit.ls5.setting_units())
