// `rangekit detect`: which sensors answer on the given ports, at which baud, byte
// format and with which protocol. Each family probes with read requests only
// (cli_family.hpp), so a device is left as it was found.
#include <fcntl.h>
#include <fmt/core.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/cli_family.hpp"
#include "cli/commands.hpp"
#include "cli/host_sources.hpp"
#include "cli/usb_latency.hpp"
#include "rangekit/core/fd_transport.hpp"
#include "rangekit/core/serial_port.hpp"

namespace rangekit::cli {
namespace {

struct DetectOptions {
  std::vector<std::string> ports;
  std::vector<std::uint32_t> bauds;       // empty: every rate of every document
  std::vector<std::string> byte_formats;  // empty: 8N1, then the others where 8N1 found nothing
  int timeout_ms = 300;
  bool jsonl = false;
  bool all_bauds = false;                                        // keep scanning a port after the first answer
  std::vector<std::pair<const CliFamily*, DetectProbe>> probes;  // each family's, from its options
};

// Every byte format a family may speak, in table order; 8N1 is every family's factory one.
const std::vector<std::string> byte_format_names{"8N1", "8E1", "8O1", "8N2", "8E2", "8O2"};

// Every rate a document lists, the factory rate (115200) first.
std::vector<std::uint32_t> candidate_bauds() {
  std::vector<std::uint32_t> bauds{115200};
  for (const CliFamily* family : cli_families()) {
    for (const auto baud : family->detect.bauds()) bauds.push_back(baud);
  }
  std::vector<std::uint32_t> unique;
  for (const auto baud : bauds) {
    if (std::find(unique.begin(), unique.end(), baud) == unique.end()) unique.push_back(baud);
  }
  return unique;
}

// Whether the family may answer at this rate in this byte format: 8N1 is tried at every
// rate; another format only at a rate of the family's own document.
bool may_answer(const CliFamily& family, std::uint32_t baud, const std::string& format) {
  if (format == "8N1") return true;
  if (!family.detect.other_byte_formats) return false;
  const auto bauds = family.detect.bauds();
  return std::find(bauds.begin(), bauds.end(), baud) != bauds.end();
}

// The families that speak formats besides 8N1, for the help: "the A's".
std::string other_format_speakers() {
  std::string text;
  for (const CliFamily* family : cli_families()) {
    if (family->detect.other_byte_formats)
      text += (text.empty() ? "the " : ", the ") + std::string(family->label) + "'s";
  }
  return text;
}

void print_finding(const DetectFinding& finding, bool jsonl, const std::optional<UsbLatency>& latency) {
  if (jsonl) {
    nlohmann::json line{{"port", finding.port},       {"family", finding.family},
                        {"baud", finding.baud},       {"byte_format", finding.byte_format},
                        {"address", finding.address}, {"version", finding.version},
                        {"detail", finding.detail}};
    if (latency) line["latency_timer_ms"] = latency->milliseconds;
    fmt::print("{}\n", line.dump());
  } else {
    const CliFamily* family = find_cli_family(finding.family);
    fmt::print("{}  {}  {} baud {}  address {}  {}  {}\n", finding.port, family ? family->label : finding.family,
               finding.baud, finding.byte_format, finding.address, finding.version, finding.detail);
  }
  std::fflush(stdout);
}

// No silent waits (docs/cli.md): a port where nothing answers takes about 22 s,
// so on a terminal (stdout and stderr, as for the status line of docs/cli.md) one line
// on stderr, redrawn in place, says which rate and format is being tried.
bool progress_wanted() {
  static const bool wanted = ::isatty(STDOUT_FILENO) == 1 && ::isatty(STDERR_FILENO) == 1;
  return wanted;
}

void show_progress(const std::string& path, std::uint32_t baud, const std::string& format) {
  if (!progress_wanted()) return;
  fmt::print(stderr, "\r\x1b[Krangekit detect: trying {} at {} {} ...", path, baud, format);
  std::fflush(stderr);
}

void clear_progress() {
  if (!progress_wanted()) return;
  fmt::print(stderr, "\r\x1b[K");
  std::fflush(stderr);
}

// A path that is not there or is not a terminal is reported once, not per baud.
Status check_is_terminal(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return make_error(Errc::io, errno_text("cannot open " + path, errno));
  const bool terminal = ::isatty(fd) == 1;
  ::close(fd);
  if (!terminal) return make_error(Errc::unsupported, path + " is not a serial port or terminal");
  return ok_status();
}

// The byte formats to try: 8N1 and the others, parity-free first; or those given with --byte-format.
std::vector<std::string> candidate_formats(const DetectOptions& options) {
  if (!options.byte_formats.empty()) return options.byte_formats;
  return {"8N1", "8N2", "8E1", "8O1", "8E2", "8O2"};
}

struct PortScan {
  int found = 0;
  bool failed = false;  // the port could not be opened: reported, scan ended
};

// One port. First pass: 8N1 at every rate, every family. Second pass, only when the first
// found nothing: the other byte formats at the rates of the families that speak them,
// factory rate first, so that a sensor moved to 8N2 at 115200 is found at the first try.
PortScan scan_port(const DetectOptions& options, const std::string& path, const std::vector<std::uint32_t>& bauds,
                   std::chrono::milliseconds timeout, const std::optional<UsbLatency>& latency) {
  PortScan scan;
  const auto formats = candidate_formats(options);
  const bool try_8n1 = std::find(formats.begin(), formats.end(), "8N1") != formats.end();
  auto report = [&](const DetectFinding& finding) {
    clear_progress();
    print_finding(finding, options.jsonl, latency);
    ++scan.found;
  };
  // Opens the port at a rate and format; nothing when the rate cannot be set here, or when
  // the port failed (scan.failed).
  auto open_at = [&](std::uint32_t baud, const std::string& format) -> std::optional<TransportPtr> {
    auto settings = serial_settings(baud, format);
    if (!settings) {
      fmt::print(stderr, "rangekit detect: {}\n", settings.error().message);
      scan.failed = true;
      return std::nullopt;
    }
    show_progress(path, baud, format);
    auto port = SerialPort::open(path, *settings);
    if (!port) {
      // A rate this system cannot set (14400, H1) is skipped; anything else ends the scan of the port.
      if (port.error().code != Errc::unsupported) {
        fmt::print(stderr, "rangekit detect: {}\n", port.error().describe());
        scan.failed = true;
      }
      return std::nullopt;
    }
    return TransportPtr(std::move(*port));
  };
  // Each family that may answer here asks in turn; the first that hears a sensor ends the turn.
  auto probe_families = [&](Transport& port, std::uint32_t baud, const std::string& format) {
    for (const auto& [family, probe] : options.probes) {
      if (!may_answer(*family, baud, format)) continue;
      auto findings = probe(port, path, baud, timeout);
      for (auto& finding : findings) {
        finding.byte_format = format;
        report(finding);
      }
      if (!findings.empty()) return;
    }
  };
  auto anyone_may_answer = [&](std::uint32_t baud, const std::string& format) {
    return std::any_of(options.probes.begin(), options.probes.end(),
                       [&](const auto& entry) { return may_answer(*entry.first, baud, format); });
  };

  if (try_8n1) {
    for (const auto baud : bauds) {
      if (scan.found > 0 && !options.all_bauds) break;
      auto port = open_at(baud, "8N1");
      if (scan.failed) return scan;
      if (!port) continue;
      probe_families(**port, baud, "8N1");
    }
  }
  if (scan.found > 0) return scan;
  for (const auto baud : bauds) {
    for (const auto& format : formats) {
      if (format == "8N1" || !anyone_may_answer(baud, format)) continue;
      auto port = open_at(baud, format);
      if (scan.failed) return scan;
      if (!port) continue;
      const int before = scan.found;
      probe_families(**port, baud, format);
      if (scan.found > before) break;  // one format per rate: over a pty parity is not seen
    }
    if (scan.found > 0 && !options.all_bauds) return scan;
  }
  return scan;
}

int run_detect(const DetectOptions& options) {
  const auto bauds = options.bauds.empty() ? candidate_bauds() : options.bauds;
  const auto timeout = std::chrono::milliseconds(options.timeout_ms);
  int found = 0;
  bool any_port_failed = false;
  for (const auto& path : options.ports) {
    if (auto usable = check_is_terminal(path); !usable) {
      fmt::print(stderr, "rangekit detect: {}\n", usable.error().message);
      any_port_failed = true;
      continue;
    }
    // Said before the scan, which takes seconds: on stdout beside the findings, or on stderr
    // when stdout is JSON lines (there each finding carries latency_timer_ms).
    const auto latency = usb_latency(path);
    if (latency && !latency_advice(*latency).empty()) {
      fmt::print(options.jsonl ? stderr : stdout, "{}\n", latency_advice(*latency));
    } else if (latency && !options.jsonl) {
      fmt::print("{}: USB serial latency timer {} ms\n", latency->device, latency->milliseconds);
    }
    std::fflush(stdout);
    const PortScan scan = scan_port(options, path, bauds, timeout, latency);
    clear_progress();
    found += scan.found;
    any_port_failed = any_port_failed || scan.failed;
    if (scan.found == 0 && !scan.failed) {
      fmt::print(stderr, "rangekit detect: nothing answered on {} at any of {} baud rates and {} byte formats\n", path,
                 bauds.size(), candidate_formats(options).size());
    }
  }
  if (found > 0) return exit_ok;
  return any_port_failed ? exit_io : exit_no_reply;
}

}  // namespace

void add_detect_command(CLI::App& app, int& exit_code) {
  static DetectOptions options;
  const std::string both = std::string(both_or_all());
  auto* command = app.add_subcommand(
      "detect", "Find " + cli_family_labels(" and ") + " sensors on serial ports: tries every baud rate of " + both +
                    " documents and " + both + " protocols, and " + other_format_speakers() + " byte formats");
  command->add_option("--port", options.ports, "serial port or pty to scan (repeat for several)")->required();
  command->add_option("--baud", options.bauds,
                      "only these rates (default: all of " + both + " documents, 115200 first)");
  for (const CliFamily* family : cli_families()) {
    options.probes.emplace_back(family, family->detect.add_options(*command));
  }
  std::string formats_list;
  for (const auto& name : byte_format_names) formats_list += (formats_list.empty() ? "" : " ") + name;
  command
      ->add_option("--byte-format", options.byte_formats,
                   "only these byte formats (" + formats_list + "; default: 8N1, then " + other_format_speakers() +
                       " other " + count_in_words(byte_format_names.size() - 1) + " where nothing answered at 8N1)")
      ->check(CLI::IsMember(byte_format_names));
  command->add_option("--timeout-ms", options.timeout_ms)->check(timeout_milliseconds())->group("");  // old spelling
  command->add_option("--timeout", options.timeout_ms, "milliseconds to wait per request")
      ->check(timeout_milliseconds())
      ->capture_default_str();
  command->add_flag("--all-bauds", options.all_bauds, "keep trying other rates after a port answered");
  command->add_flag("--json", options.jsonl, "one JSON object per finding, one per line");
  command->add_flag("--jsonl", options.jsonl)->group("");  // the earlier spelling, kept for scripts
  command->callback([&exit_code] { exit_code = run_detect(options); });
}

}  // namespace rangekit::cli
