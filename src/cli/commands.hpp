// Subcommands of the rangekit binary; each file registers one on the CLI11 app.
// Exceptions stop at this edge: the library returns Result values, and these
// functions turn failures into a message and a documented exit code.
#pragma once

#include <CLI/CLI.hpp>

#include "rangekit/core/result.hpp"

namespace rangekit::cli {

// Exit codes (documented in docs/cli.md).
inline constexpr int exit_ok = 0;
inline constexpr int exit_usage = 2;          // bad arguments, unknown subcommand or option
inline constexpr int exit_bad_input = 3;      // input that does not decode
inline constexpr int exit_io = 4;             // cannot open or read a file or port
inline constexpr int exit_no_reply = 5;       // the device did not answer (wrong port, baud or address; unplugged)
inline constexpr int exit_device_error = 6;   // the device answered with an error number
inline constexpr int exit_write_failed = 7;   // output or capture file could not be written (disk full)
inline constexpr int exit_link_lost = 8;      // the link went away and did not come back in time
inline constexpr int exit_interrupted = 130;  // Ctrl-C; files were closed cleanly

// The one map from a library error to an exit code, for every family and every
// subcommand (the table "Which error gives which code" in docs/cli.md). A port that
// cannot be opened, whatever the reason, is turned into Errc::io by open_port
// (host_sources.hpp) before it gets here.
int exit_code_for(const Error& error);

// Checks for numbers given on the command line, so that every subcommand refuses a
// negative or absurd duration, count or timeout the same way, naming the range
// ("--count -2 is out of range: give 1 to 1000000000 samples"), before the value is
// converted (an unsigned option would otherwise wrap -2 round to a 20-digit number).
inline constexpr double max_duration_s = 31'536'000;  // a year
inline constexpr double max_count = 1'000'000'000;
inline constexpr double max_timeout_ms = 60'000;
// above_lowest: the lowest value itself is refused too (a speed or a range of 0 means nothing).
CLI::Validator in_range(double lowest, double highest, const std::string& unit, bool above_lowest = false);
inline constexpr double max_pace_factor = 1000;
inline constexpr double max_target_speed_mps = 1'000'000;  // 1e5 switches the jump check off in tests
inline constexpr double max_range_mm = 1'000'000;
inline CLI::Validator duration_seconds() { return in_range(0, max_duration_s, "seconds"); }
inline CLI::Validator sample_count() { return in_range(1, max_count, "samples"); }
inline CLI::Validator timeout_milliseconds() { return in_range(1, max_timeout_ms, "milliseconds"); }
inline CLI::Validator pace_factor() { return in_range(0, max_pace_factor, "times as fast as recorded", true); }
inline CLI::Validator target_speed() { return in_range(0, max_target_speed_mps, "m/s", true); }
inline CLI::Validator range_millimetres() { return in_range(0, max_range_mm, "mm", true); }

void add_tables_command(CLI::App& app, int& exit_code);
void add_decode_command(CLI::App& app, int& exit_code);
// Between a host and a sensor: forward, decode and record (docs/tap.md).
void add_tap_command(CLI::App& app, int& exit_code);
CLI::App* add_tap_compare_command(CLI::App& tap, int& exit_code);  // `tap compare` (tap_compare_command.cpp)
void add_demo_command(CLI::App& app, int& exit_code);
// Host side: each family's own subcommand (cli_family.hpp), plus replay of captures.
void add_replay_command(CLI::App& app, int& exit_code);
void add_detect_command(CLI::App& app, int& exit_code);
void add_capture_command(CLI::App& app, int& exit_code);
// The sensor service (docs/service.md).
void add_serve_command(CLI::App& app, int& exit_code);

}  // namespace rangekit::cli
