// `rangekit uls ...`: configure, read and stream a ULS (docs/host-uls.md) through the
// host driver. Library errors become one message and a documented exit code.
#include <fmt/core.h>

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "cli/assignment_file.hpp"
#include "cli/commands.hpp"
#include "cli/config_diff.hpp"
#include "cli/host_sources.hpp"
#include "cli/key_values.hpp"
#include "cli/stream_runner.hpp"
#include "rangekit/uls/bus.hpp"
#include "rangekit/uls/describe.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/family.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/host_config.hpp"
#include "rangekit/uls/named_settings.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {

using namespace rangekit::uls;

namespace {

struct LinkOptions {
  std::string port;
  std::uint32_t baud = 115200;
  std::string address;
  int timeout_ms = 1000;
  bool json = false;  // info, get: one JSON object instead of NAME=VALUE lines
};

void add_link_options(CLI::App* command, LinkOptions& link) {
  command->add_option("--port", link.port, "serial port or pty (/dev/ttyUSB0, the emulator's symlink)")->required();
  command->add_option("--baud", link.baud, "baud rate of the port (115200 from the factory)")->capture_default_str();
  command->add_option("--address", link.address,
                      "RS-485 unit address: one character 0x30-0xEF ('A'), 0xNN or decimal; "
                      "without it the '$' protocol");
  command->add_option("--timeout", link.timeout_ms, "milliseconds to wait for each reply")
      ->check(timeout_milliseconds())
      ->capture_default_str();
}

int fail(std::string_view command, const Error& error) {
  fmt::print(stderr, "rangekit uls {}: {}\n", command, error.message);
  return exit_code_for(error);
}

Result<std::optional<std::uint8_t>> address_of(const LinkOptions& link) {
  if (link.address.empty()) return std::optional<std::uint8_t>{};
  auto address = parse_unit_address(link.address);
  if (!address)
    return make_error(Errc::out_of_range, "--address '" + link.address + "' is not a unit address 0x30..0xEF");
  return std::optional<std::uint8_t>{*address};
}

Result<std::unique_ptr<Driver>> open_driver(const LinkOptions& link, bool with_reopen = false) {
  auto address = address_of(link);
  if (!address) return address.error();
  const SerialSettings line{link.baud, Parity::none, 1};  // 8N1, §9
  auto port = open_port(link.port, line);
  if (!port) return port.error();
  DriverOptions options;
  options.address = *address;
  options.timeout = std::chrono::milliseconds(link.timeout_ms);
  options.source = link.port;
  return std::make_unique<Driver>(std::move(*port), options,
                                  with_reopen ? reopen_port(link.port, line) : ReopenFunction{});
}

std::string format_sample(const Sample& sample) {
  std::string text(kind_name_of(sample));
  // "error 4: Lock Not Found (display: Target Not Found)": §10's words, not a bare number (U90).
  if (const auto number = sample.get(channel::error)) text += fmt::format(" {}: {}", *number, error_text(*number));
  if (sample.address >= 0) text += " address=" + address_text(static_cast<std::uint8_t>(sample.address));
  if (const auto metres = sample.get(channel::distance_m)) text += fmt::format(" distance_m={:.3f}", *metres);
  // Picoseconds on the wire (U8), shown in ns with the unit in the name (U92).
  if (const auto picoseconds = sample.get(channel::pulse_width_ps))
    text += fmt::format(" pulse_width_ns={:.3f}", *picoseconds / 1000.0);
  for (std::size_t i = 0; i < sample.targets.size(); ++i)
    text += fmt::format(" target{}={:.3f}m/{}", i, sample.targets[i].distance_m, sample.targets[i].strength);
  if (const auto present = sample.get(channel::presence))
    text += fmt::format(" presence={}", *present ? "true" : "false");
  if (const auto pulses = sample.get(channel::pulses_between_events))
    text += fmt::format(" pulses_between_events={}", *pulses);
  if (sample.get(channel::pulses_overflow).value_or(false)) text += " pulses_between_events>65535";
  return text;
}

// --- get -------------------------------------------------------------------

// One get, printed as `name=value  # MN=wire` (uls::named::read_setting, shared with the service).
int print_setting(Driver& driver, const named::Target& target, Units units, KeyValues& out) {
  auto lines = named::read_setting(driver, target, units);
  if (!lines) return fail("get", lines.error());
  for (const named::Value& line : *lines) {
    if (line.reading.number) {
      out.add_number(line.key, line.reading.text, line.comment);
    } else {
      out.add(line.key, line.reading.text, line.comment);
    }
  }
  return exit_ok;
}

int run_get(const LinkOptions& link, const std::vector<std::string>& names) {
  std::vector<named::Target> targets;
  for (const auto& name : names) {
    auto target = named::find_setting(name);
    if (!target) return fail("get", target.error());
    if (!target->command->has_get())
      return fail("get", make_error(Errc::wrong_form, std::string(target->command->cli_name) + " (" +
                                                          std::string(target->command->mnemonic) +
                                                          ") cannot be read, only set"));
    targets.push_back(*target);
  }
  if (names.empty()) targets = named::readable_targets();
  auto driver = open_driver(link);
  if (!driver) return fail("get", driver.error());
  auto units = (*driver)->units();
  if (!units) return fail("get", units.error());
  int code = exit_ok;
  KeyValues out(link.json);
  for (const auto& target : targets) {
    const int one = print_setting(**driver, target, *units, out);
    if (one == exit_no_reply) return one;
    if (code == exit_ok) code = one;
  }
  if (code == exit_ok) out.finish();
  return code;
}

// --- set -------------------------------------------------------------------

// What `get` prints that there is nothing to write: read-only names, and an unassigned address
// (a unit's address can be changed, not taken away), which holds only when the unit has none.
struct Skipped {
  std::vector<std::string> read_only;
  bool unassigned = false;
};

bool skipped_from_file(const std::string& name, const std::string& value, Skipped& skipped) {
  auto target = named::find_setting(name, named::Purpose::get);
  if (!target) return false;
  if (!target->command->has_set()) {
    skipped.read_only.push_back(name);
    return true;
  }
  if (target->command->mnemonic == "UA" && value == "unassigned") {
    skipped.unassigned = true;
    return true;
  }
  return false;
}

Status check_still_unassigned(Driver& driver) {
  auto address = driver.get("UA");
  if (!address && address.error().device_code == error_number::unit_address_not_assigned) return ok_status();
  if (!address) return address.error();
  const auto reading = named::describe_reply(*find_command("UA"), *address, Units::metres);
  return make_error(Errc::wrong_form, "address=unassigned: the unit has address " + reading.text +
                                          "; an address can be changed (address=B), not taken away");
}

int run_set(const LinkOptions& link, const std::vector<std::string>& assignments, const std::string& from) {
  Skipped skipped;
  std::vector<std::pair<std::string, std::string>> pairs;
  if (!from.empty()) {
    auto lines = read_assignments(from);
    if (!lines) return fail("set", lines.error());
    for (const auto& line : *lines) {
      const auto equals = line.find('=');
      if (!skipped_from_file(line.substr(0, equals), line.substr(equals + 1), skipped))
        pairs.emplace_back(line.substr(0, equals), line.substr(equals + 1));
    }
  }
  if (assignments.empty() && pairs.empty() && !skipped.unassigned)
    return fail("set", make_error(Errc::wrong_form, "give NAME=VALUE (e.g. mode=binning prf-hz=2000) or --from FILE"));
  for (const auto& assignment : assignments) {
    const auto equals = assignment.find('=');
    if (equals == std::string::npos)
      return fail("set", make_error(Errc::wrong_form, "'" + assignment + "' is not NAME=VALUE"));
    pairs.emplace_back(assignment.substr(0, equals), assignment.substr(equals + 1));
  }
  if (!skipped.read_only.empty()) {
    std::string names;
    for (const auto& name : skipped.read_only) names += (names.empty() ? "" : ", ") + name;
    fmt::print(stderr, "note: skipped {} of the file: read-only\n", names);
  }
  auto work = named::plan(pairs);  // every value checked before the first is sent
  if (!work) return fail("set", work.error());
  auto driver = open_driver(link);
  if (!driver) return fail("set", driver.error());
  if (skipped.unassigned) {
    if (Status unassigned = check_still_unassigned(**driver); !unassigned) return fail("set", unassigned.error());
  }
  const auto echo = [&link](const named::Written& written) {
    std::string wire;
    for (const auto& field : written.fields) wire += (wire.empty() ? "" : ",") + field;
    const named::Target& target = written.assignment->target;
    fmt::print("{}={}  # {}={} OK\n", named::assignment_name(target), written.assignment->value,
               target.command->mnemonic, wire);
    if (target.command->mnemonic == "BR" && written.fields.size() == 2 &&
        written.fields[1] != std::to_string(link.baud))
      fmt::print(stderr, "note: port {} now runs at {} baud, from this answer on; use --baud {}\n", written.fields[0],
                 written.fields[1], written.fields[1]);
  };
  auto done = named::write(**driver, *work, echo);
  if (!done) return fail("set", done.error());
  if (*done) fmt::print(stderr, "note: the unit was measuring: stopped for the settings and started again\n");
  return exit_ok;
}

// --- info, actions, measure -------------------------------------------------

int run_info(const LinkOptions& link) {
  auto driver = open_driver(link);
  if (!driver) return fail("info", driver.error());
  auto info = (*driver)->info();
  if (!info) return fail("info", info.error());
  KeyValues out(link.json);
  out.add("port", link.port);
  if (info->address) out.add("address", address_text(*info->address));
  out.add("version", info->version);
  const StatusInfo& s = info->status;
  // The same words as `get` prints for US (the command table's names).
  const std::string_view status_name = command_info(CommandId::status).value_name(s.value);
  out.add("status",
          !status_name.empty() ? std::string(status_name)
          : s.value == 0       ? std::string("error")
          : s.measuring()      ? std::string("measuring")
                               : std::string("ready"),
          fmt::format("US={} (active={}, laser_firing={}, averaging_calc={}, binning_calc={})", s.value, s.active,
                      s.laser_firing, s.averaging_calc, s.binning_calc));
  auto units = (*driver)->units();
  if (!units) return fail("info", units.error());
  for (const char* mnemonic : {"MM", "MU", "PF", "PO", "CO", "MO"}) {
    if (const int code = print_setting(**driver, named::Target{find_command(mnemonic), false, ""}, *units, out);
        code != exit_ok)
      return code;
  }
  out.finish();
  return exit_ok;
}

// What an action leaves the unit as, in the words both families print (docs/cli.md).
struct ActionWords {
  std::string_view done;    // "stopped"
  int already = 0;          // the §10 number the unit answers when it is so already
  std::string_view as_was;  // "it was not measuring"
};

// start and stop succeed from any state: a unit already so answers 31 or 86 (§10), which
// here is no failure but says so.
int run_action(const LinkOptions& link, std::string_view name, std::string_view mnemonic, const ActionWords& words) {
  auto driver = open_driver(link);
  if (!driver) return fail(name, driver.error());
  if (auto done = (*driver)->action(mnemonic); !done) {
    if (words.already == 0 || done.error().code != Errc::device_error || done.error().device_code != words.already)
      return fail(name, done.error());
    fmt::print("{} ({})\n", words.done, words.as_was);
    return exit_ok;
  }
  fmt::print("{}\n", words.done);
  return exit_ok;
}

int run_measure(const LinkOptions& link, int count) {
  auto driver = open_driver(link);
  if (!driver) return fail("measure", driver.error());
  for (int i = 0; i < count; ++i) {
    auto sample = (*driver)->measure();
    if (!sample) return fail("measure", sample.error());
    fmt::print("{}\n", format_sample(*sample));
  }
  return exit_ok;
}

// --- stream ----------------------------------------------------------------

int run_uls_stream(const LinkOptions& link, const StreamOptions& options, const std::string& mode, bool reconnect) {
  auto driver = open_driver(link, reconnect);
  if (!driver) return fail("stream", driver.error());
  const StreamMode stream_mode = mode == "continuous" ? StreamMode::continuous
                                 : mode == "polled"   ? StreamMode::polled
                                                      : StreamMode::automatic;
  auto stream = (*driver)->start_stream(stream_mode);
  if (!stream) return fail("stream", stream.error());
  const int code = run_stream(**stream, options);
  (*stream)->stop(AfterStream::as_found);  // U86: ST only if this stream started the unit
  return code;
}

// --- config and reset -------------------------------------------------------

// Names and values as `get` prints them, the same lines as `rangekit ls5 config diff`.
std::vector<DiffLine> diff_lines(const std::vector<ConfigDifference>& differences) {
  std::vector<DiffLine> lines;
  for (const auto& difference : differences) {
    const CommandInfo& command = *difference.command;
    lines.push_back({named::setting_key(command), named::without_unit(command, difference.wanted),
                     named::without_unit(command, difference.actual)});
  }
  return lines;
}

void print_differences(const std::vector<ConfigDifference>& differences, std::string_view wanted_label) {
  print_diff_lines(diff_lines(differences), wanted_label);
}

Result<DeviceConfig> read_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return make_error(Errc::io, "cannot read " + path);
  std::stringstream text;
  text << in.rdbuf();
  return config_from_toml(text.str(), path);
}

int run_config(const LinkOptions& link, const std::string& what, const std::string& path) {
  const std::string name = "config " + what;
  std::optional<DeviceConfig> file;
  if (what != "save") {
    auto read = read_file(path);
    if (!read) return fail(name, read.error());
    file = std::move(*read);
  }
  auto driver = open_driver(link);
  if (!driver) return fail(name, driver.error());
  if (what == "save") {
    auto config = read_config(**driver);
    if (!config) return fail(name, config.error());
    std::ofstream out(path);
    out << config_to_toml(*config, "from " + link.port);
    out.close();
    if (!out) {
      fmt::print(stderr, "rangekit uls config save: cannot write {}\n", path);
      return exit_write_failed;
    }
    fmt::print("saved {} settings to {}\n", config->settings.size(), path);
    return exit_ok;
  }
  if (what == "diff") {
    auto device = read_config(**driver);
    if (!device) return fail(name, device.error());
    return print_config_diff(diff_lines(diff_config(*file, *device)), file->settings.size());
  }
  auto report = load_config(**driver, *file);
  if (!report) return fail(name, report.error());
  print_differences(report->mismatches, "file");
  fmt::print("loaded {} settings from {}; {} differ after reading back\n", file->settings.size(), path,
             report->mismatches.size());
  return report->mismatches.empty() ? exit_ok : exit_device_error;
}

int run_reset(const LinkOptions& link, bool save) {
  auto driver = open_driver(link);
  if (!driver) return fail("reset", driver.error());
  auto report = load_config(**driver, factory_config());
  if (!report) return fail("reset", report.error());
  print_differences(report->mismatches, "factory");
  if (save) {
    if (auto saved = (*driver)->save(); !saved) return fail("reset", saved.error());
  }
  fmt::print("factory settings written ({}){}\n", report->sent, save ? " and saved (SU)" : "; not saved (add --save)");
  return report->mismatches.empty() ? exit_ok : exit_device_error;
}

// --- bus -------------------------------------------------------------------

Result<std::unique_ptr<Bus>> open_bus(const LinkOptions& link) {
  const SerialSettings line{link.baud, Parity::none, 1};  // 8N1, §9
  auto port = open_port(link.port, line);
  if (!port) return port.error();
  BusOptions options;
  options.timeout = std::chrono::milliseconds(std::min(link.timeout_ms, 1000));
  return std::make_unique<Bus>(std::move(*port), options);
}

Result<std::vector<std::uint8_t>> address_list(const std::string& text, bool all) {
  if (text.empty()) return all ? all_unit_addresses() : typable_addresses();
  std::vector<std::uint8_t> list;
  for (const char c : text) {
    auto address = parse_unit_address(std::string(1, c));
    if (!address) return make_error(Errc::out_of_range, std::string("'") + c + "' is not a unit address");
    list.push_back(*address);
  }
  return list;
}

// How long a scan waits at each address: a unit answers ID within a few milliseconds at any
// baud of §9, so a silent address costs 150 ms (BusOptions) unless --timeout says otherwise.
constexpr int scan_wait_ms = 150;

struct ScanOptions {
  std::string units;
  bool all = false;
  std::optional<bool> progress;  // --progress / --no-progress; none: when stderr is a terminal
};

// Each unit is printed as it answers; the progress line ("asked 23 of 62, 2 answered") is
// redrawn on stderr, so a scan of every address never sits silent.
int run_scan(const LinkOptions& link, const ScanOptions& options, bool timeout_given) {
  auto bus = open_bus(link);
  if (!bus) return fail("bus scan", bus.error());
  auto addresses = address_list(options.units, options.all);
  if (!addresses) return fail("bus scan", addresses.error());
  const bool progress = options.progress.value_or(::isatty(STDERR_FILENO) == 1);
  const int wait_ms = timeout_given ? link.timeout_ms : scan_wait_ms;
  std::size_t answered = 0;
  int duplicates = 0;
  const auto units =
      (*bus)->scan(*addresses, std::chrono::milliseconds(wait_ms), [&](std::size_t asked, const BusUnit* unit) {
        if (unit != nullptr) {
          if (progress) fmt::print(stderr, "\r\033[K");
          fmt::print("{}  {}{}{}\n", address_text(unit->address), unit->version,
                     unit->status ? fmt::format("  status={}", unit->status->value) : "",
                     unit->duplicate ? "  DUPLICATE: " + unit->problem : "");
          std::fflush(stdout);
          ++answered;
          duplicates += unit->duplicate ? 1 : 0;
        }
        if (progress) fmt::print(stderr, "\rasked {} of {}, {} answered ", asked, addresses->size(), answered);
      });
  if (progress) fmt::print(stderr, "\r\033[K");
  fmt::print("{} address(es) answered of {} asked ({} ms at each silent one)\n", units.size(), addresses->size(),
             wait_ms);
  if (units.empty()) {
    fmt::print(stderr, "rangekit uls bus scan: no unit answered (check the port, the baud rate and the wiring)\n");
    return exit_no_reply;
  }
  return duplicates > 0 ? exit_device_error : exit_ok;
}

int run_bus(const LinkOptions& link, const std::string& what, const std::string& units_text, bool all,
            const std::string& from, const std::string& to, bool measure, int rounds) {
  const std::string name = "bus " + what;
  auto bus = open_bus(link);
  if (!bus) return fail(name, bus.error());
  if (what == "assign") {
    std::optional<std::uint8_t> old;
    if (!from.empty()) {
      old = parse_unit_address(from);
      if (!old) return fail(name, make_error(Errc::out_of_range, "--from '" + from + "' is not a unit address"));
    }
    auto fresh = parse_unit_address(to);
    if (!fresh) return fail(name, make_error(Errc::out_of_range, "--to '" + to + "' is not a unit address 0x30..0xEF"));
    if (auto done = (*bus)->assign(old, *fresh); !done) return fail(name, done.error());
    fmt::print("assigned {} -> {}\n", old ? address_text(*old) : std::string("(unaddressed)"), address_text(*fresh));
    return exit_ok;
  }
  auto addresses = address_list(units_text, all);
  if (!addresses) return fail(name, addresses.error());
  // poll: the Interface Program's network poll, round-robin.
  std::vector<std::uint8_t> list = *addresses;
  if (units_text.empty()) {
    list.clear();
    for (const auto& unit : (*bus)->scan(*addresses)) list.push_back(unit.address);
    if (list.empty()) return fail(name, make_error(Errc::timeout, "no unit answered on " + link.port));
  }
  // U93: a unit silent on US or on BM is "no reply" (5); a device error or a collision 6.
  int silent = 0;
  int failed = 0;
  for (int round = 0; round < rounds; ++round) {
    for (const auto& result : (*bus)->poll(list, measure)) {
      std::string line = address_text(result.address);
      if (result.status) line += fmt::format("  status={}", result.status->value);
      if (result.sample) line += "  " + format_sample(*result.sample);
      if (!result.problem.empty()) line += "  problem: " + result.problem;
      if (!result.answered || (result.error && result.error->code == Errc::timeout)) {
        ++silent;
      } else if (result.error) {
        ++failed;
      }
      fmt::print("{}\n", line);
    }
  }
  return silent > 0 ? exit_no_reply : failed > 0 ? exit_device_error : exit_ok;
}

}  // namespace

void add_uls_command(CLI::App& app, int& exit_code) {
  auto* uls = app.add_subcommand("uls", "configure, read and stream a ULS on a serial port or pty");
  uls->require_subcommand(1);
  // The document's sections stay here and in docs/conformance.md, out of the messages.
  uls->footer("Spec: §7 bus, §8 commands, §9 rates, §10 errors; docs/host-uls.md");
  auto link = std::make_shared<LinkOptions>();

  auto* info = uls->add_subcommand("info", "version (ID), status bits (US) and the main settings");
  add_link_options(info, *link);
  info->add_flag("--json", link->json, "one JSON object instead of NAME=VALUE lines");
  info->callback([&exit_code, link] { exit_code = run_info(*link); });

  auto names = std::make_shared<std::vector<std::string>>();
  auto* get = uls->add_subcommand(
      "get", "read settings by name (mode, prf, units, ...) or mnemonic (MM, PF); all without names");
  add_link_options(get, *link);
  get->add_option("names", *names, "settings to read");
  get->add_flag("--json", link->json, "one JSON object instead of NAME=VALUE lines");
  get->callback([&exit_code, link, names] { exit_code = run_get(*link, *names); });

  auto assignments = std::make_shared<std::vector<std::string>>();
  auto* set = uls->add_subcommand("set", "write settings: mode=binning prf-hz=2000 units=m short-gate-m=10 PF=2000");
  add_link_options(set, *link);
  auto from_file = std::make_shared<std::string>();
  set->add_option("assignments", *assignments, "NAME=VALUE ...");
  add_from_option(*set, *from_file);
  set->footer("Writable names (as `get` prints them): " + named::writable_names());
  set->callback([&exit_code, link, assignments, from_file] { exit_code = run_set(*link, *assignments, *from_file); });

  auto stream_options = std::make_shared<StreamOptions>();
  auto stream_mode = std::make_shared<std::string>("auto");
  auto no_reconnect = std::make_shared<bool>(false);
  auto* stream =
      uls->add_subcommand("stream", "start measuring and stream readings (reconnects when the port comes back)");
  add_link_options(stream, *link);
  add_stream_options(*stream, *stream_options);
  stream->add_option("--mode", *stream_mode, "auto (CO decides), continuous (GO) or polled (BM)")
      ->check(CLI::IsMember({"auto", "continuous", "polled"}))
      ->capture_default_str();
  stream->add_flag("--no-reconnect", *no_reconnect, "end the stream when the port goes away");
  stream->callback([&exit_code, link, stream_options, stream_mode, no_reconnect] {
    exit_code = run_uls_stream(*link, *stream_options, *stream_mode, !*no_reconnect);
  });

  auto count = std::make_shared<int>(1);
  auto* measure = uls->add_subcommand("measure", "one measurement with BM (starts the unit if idle)");
  add_link_options(measure, *link);
  measure->add_option("--count", *count, "measurements to read")->check(sample_count())->capture_default_str();
  measure->callback([&exit_code, link, count] { exit_code = run_measure(*link, *count); });

  auto* start = uls->add_subcommand("start", "start measuring (GO)");
  add_link_options(start, *link);
  start->callback([&exit_code, link] {
    exit_code = run_action(*link, "start", "GO", {"measuring", error_number::already_measuring, "it already was"});
  });
  auto* stop = uls->add_subcommand("stop", "stop measuring (ST)");
  add_link_options(stop, *link);
  stop->callback([&exit_code, link] {
    exit_code = run_action(*link, "stop", "ST", {"stopped", error_number::not_measuring, "it was not measuring"});
  });
  auto* save = uls->add_subcommand("save", "save the user settings into non-volatile memory (SU)");
  add_link_options(save, *link);
  save->callback([&exit_code, link] { exit_code = run_action(*link, "save", "SU", {"saved", 0, ""}); });

  auto save_after_reset = std::make_shared<bool>(false);
  auto* reset = uls->add_subcommand("reset", "write the factory settings (the unit has no reset command) and verify");
  add_link_options(reset, *link);
  reset->add_flag("--save", *save_after_reset, "also save them (SU)");
  reset->callback([&exit_code, link, save_after_reset] { exit_code = run_reset(*link, *save_after_reset); });

  auto* config = uls->add_subcommand("config", "settings as a TOML file (the Interface Program's .uls file)");
  config->require_subcommand(1);
  auto path = std::make_shared<std::string>();
  for (const auto& [what, help] : std::vector<std::pair<std::string, std::string>>{
           {"save", "read every setting and write FILE"},
           {"load", "upload FILE, read back and verify every value"},
           {"diff", "compare FILE with the device (exit 1 when they differ)"}}) {
    auto* sub = config->add_subcommand(what, help);
    add_link_options(sub, *link);
    sub->add_option("file", *path, "TOML file")->required();
    sub->callback([&exit_code, link, path, what = what] { exit_code = run_config(*link, what, *path); });
  }

  auto* bus = uls->add_subcommand("bus", "RS-485 bus of addressed units");
  bus->require_subcommand(1);
  auto units = std::make_shared<std::string>();
  auto all = std::make_shared<bool>(false);
  auto from = std::make_shared<std::string>();
  auto to = std::make_shared<std::string>();
  auto poll_measure = std::make_shared<bool>(false);
  auto rounds = std::make_shared<int>(1);
  auto* scan = bus->add_subcommand("scan", "which addresses answer (ID, US); reports collisions (duplicates)");
  add_link_options(scan, *link);
  auto scan_options = std::make_shared<ScanOptions>();
  scan->add_option("--units", scan_options->units, "addresses to ask, e.g. ABC (default 0-9 A-Z a-z)");
  scan->add_flag("--all", scan_options->all, "ask every address 0x30-0xEF");
  scan->add_flag("--progress,!--no-progress", scan_options->progress,
                 "show how far the scan is on stderr (default: when stderr is a terminal)");
  scan->footer(
      "A silent address costs 150 ms, or --timeout when given. The scan asks each address with "
      "addressed (#) frames: a $ request on a bus is answered by every unit at once, and on real "
      "RS-485 hardware those answers collide.");
  scan->callback([&exit_code, link, scan_options, scan] {
    exit_code = run_scan(*link, *scan_options, scan->get_option("--timeout")->count() > 0);
  });
  auto* assign = bus->add_subcommand("assign", "give a unit a new address (UA), refusing one already in use");
  add_link_options(assign, *link);
  assign->add_option("--from", *from, "the unit's address now (omit for a factory unit alone on the line)");
  assign->add_option("--to", *to, "the new address")->required();
  assign->callback(
      [&exit_code, link, from, to] { exit_code = run_bus(*link, "assign", "", false, *from, *to, false, 1); });
  auto* poll = bus->add_subcommand("poll", "round-robin status (and --measure) of each unit (the network poll)");
  add_link_options(poll, *link);
  poll->add_option("--units", *units, "addresses to poll, e.g. ABC (default: those a scan finds)");
  poll->add_flag("--measure", *poll_measure, "also read a measurement (BM) from each unit");
  poll->add_option("--rounds", *rounds, "poll rounds")->capture_default_str();
  poll->callback([&exit_code, link, units, poll_measure, rounds] {
    exit_code = run_bus(*link, "poll", *units, false, "", "", *poll_measure, *rounds);
  });
}

}  // namespace rangekit::cli
