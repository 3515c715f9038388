// The three text forms of a sample or event, shared by the stream sinks, replay
// and the benches. Every function appends one complete line (with '\n') so a
// sink can batch many lines into one write. Numbers use their channel's decimals
// (core/channel.hpp) so the same sample always gives the same bytes, live or
// replayed. docs/capture.md lists every field.
#pragma once

#include <chrono>
#include <string>

#include "rangekit/core/sample.hpp"

namespace rangekit::record {

// 2026-11-26T01:02:03.456Z (UTC, milliseconds truncated).
void append_iso_time(std::string& out, std::chrono::system_clock::time_point time);

// {"time":...,"device":...,"address":...,"source":...,"kind":..., family fields}
void append_jsonl(std::string& out, const Sample& sample);
// {"time":...,"event":...,"message":...,"count":...}
void append_jsonl(std::string& out, const StreamEvent& event);

// The CSV header row: time, device, address, source and kind, then every registered family's
// channels (their JSON keys, in registration order), error_text, suspect and suspect_reason.
// Targets are written "d1:s1;d2:s2".
std::string csv_header();
void append_csv(std::string& out, const Sample& sample);

// 01:02:03.456 uls #3  12.345 m  pw 18000   (UTC time of day)
void append_text(std::string& out, const Sample& sample);
// 01:02:03.456 disconnected: /dev/ttyUSB0 went away
void append_text(std::string& out, const StreamEvent& event);

}  // namespace rangekit::record
