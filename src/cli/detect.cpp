// `rangekit detect`: which sensors answer on the given ports, at which baud, byte
// format and with which protocol. Only read requests are sent (ULS ID/US, LS5 ID),
// so a device is left as it was found.
#include <fcntl.h>
#include <fmt/core.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/ls5_cli.hpp"
#include "rangekit/core/fd_transport.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/settings.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/formulas.hpp"

namespace rangekit::cli {
namespace {

struct DetectOptions {
  std::vector<std::string> ports;
  std::vector<std::uint32_t> bauds;  // empty: every rate of both documents
  std::vector<std::uint8_t> ls5_addresses{0x01};
  std::vector<std::string> byte_formats;  // empty: 8N1, then the LS5's other five where 8N1 found nothing
  int timeout_ms = 300;
  bool jsonl = false;
  bool all_bauds = false;  // keep scanning a port after the first answer
};

struct Finding {
  std::string port;
  std::string family;
  std::uint32_t baud = 0;
  std::string address;
  std::string version;
  std::string detail;
  std::string byte_format = "8N1";
};

// Every rate either document lists, the factory rate (115200) first.
std::vector<std::uint32_t> candidate_bauds() {
  std::vector<std::uint32_t> bauds{115200};
  for (const auto baud : uls::baud_choices()) bauds.push_back(baud);
  for (const auto& row : ls5::baud_rate_table()) bauds.push_back(row.baud);
  std::vector<std::uint32_t> unique;
  for (const auto baud : bauds) {
    if (std::find(unique.begin(), unique.end(), baud) == unique.end()) unique.push_back(baud);
  }
  return unique;
}

std::optional<Finding> probe_uls(Transport& port, const std::string& path, std::uint32_t baud,
                                 std::chrono::milliseconds timeout) {
  auto found = uls::probe(port, std::nullopt, timeout);
  if (!found) return std::nullopt;
  Finding finding{path,           "uls",
                  baud,           found->address ? fmt::format("0x{:02X}", *found->address) : "-",
                  found->version, found->status.measuring() ? "measuring" : "idle"};
  return finding;
}

std::optional<Finding> probe_ls5(Transport& port, const std::string& path, std::uint32_t baud, std::uint8_t address,
                                 std::chrono::milliseconds timeout) {
  auto found = ls5::probe(port, address, timeout);
  if (!found) return std::nullopt;
  // Decimal, as --ls5-address takes it and `ls5 info` prints it (§9 "from 1 to 255", L70).
  Finding finding{path, "ls5", baud, fmt::format("{}", found->address), "", ""};
  if (found->identification) {
    const auto& id = *found->identification;
    finding.version = std::string(id.version_text.view());
    finding.detail = fmt::format("lower boundary {} mm, range {} mm, serial {}", id.lower_boundary_mm, id.range_mm,
                                 id.serial_number);
  } else if (found->streaming) {
    finding.detail = "streaming (records arriving; address and ID not asked)";
  }
  return finding;
}

void print_finding(const Finding& finding, bool jsonl) {
  if (jsonl) {
    nlohmann::json line{{"port", finding.port},       {"family", finding.family},
                        {"baud", finding.baud},       {"byte_format", finding.byte_format},
                        {"address", finding.address}, {"version", finding.version},
                        {"detail", finding.detail}};
    fmt::print("{}\n", line.dump());
  } else {
    fmt::print("{}  {}  {} baud {}  address {}  {}  {}\n", finding.port, finding.family == "uls" ? "ULS" : "LS5",
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

// The byte formats to try: 8N1 (the ULS's only one, the LS5's default) and the LS5's
// other five of table 9.2 (04), parity-free first; or those given with --byte-format.
std::vector<std::string> candidate_formats(const DetectOptions& options) {
  if (!options.byte_formats.empty()) return options.byte_formats;
  return {"8N1", "8N2", "8E1", "8O1", "8E2", "8O2"};
}

bool is_ls5_baud(std::uint32_t baud) {
  const auto table = ls5::baud_rate_table();
  return std::any_of(table.begin(), table.end(), [baud](const auto& row) { return row.baud == baud; });
}

struct PortScan {
  int found = 0;
  bool failed = false;  // the port could not be opened: reported, scan ended
};

// One port. First pass: 8N1 at every rate, ULS and LS5. Second pass, only when the first
// found nothing: the LS5's other byte formats (§8.3) at the LS5's rates, factory rate
// first, so that a sensor moved to 8N2 at 115200 is found at the first try (L66).
PortScan scan_port(const DetectOptions& options, const std::string& path, const std::vector<std::uint32_t>& bauds,
                   std::chrono::milliseconds timeout) {
  PortScan scan;
  const auto formats = candidate_formats(options);
  const bool try_8n1 = std::find(formats.begin(), formats.end(), "8N1") != formats.end();
  auto report = [&](const Finding& finding) {
    clear_progress();
    print_finding(finding, options.jsonl);
    ++scan.found;
  };
  // Opens the port at a rate and format; nothing when the rate cannot be set here, or when
  // the port failed (scan.failed).
  auto open_at = [&](std::uint32_t baud, const std::string& format) -> std::optional<TransportPtr> {
    auto settings = ls5_serial_settings(baud, format);
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
  auto probe_ls5_addresses = [&](Transport& port, std::uint32_t baud, const std::string& format) {
    for (const auto address : options.ls5_addresses) {
      if (auto finding = probe_ls5(port, path, baud, address, timeout)) {
        finding->byte_format = format;
        report(*finding);
      }
    }
  };

  if (try_8n1) {
    for (const auto baud : bauds) {
      if (scan.found > 0 && !options.all_bauds) break;
      auto port = open_at(baud, "8N1");
      if (scan.failed) return scan;
      if (!port) continue;
      if (auto finding = probe_uls(**port, path, baud, timeout)) {
        report(*finding);
        continue;
      }
      probe_ls5_addresses(**port, baud, "8N1");
    }
  }
  if (scan.found > 0) return scan;
  for (const auto baud : bauds) {
    if (!is_ls5_baud(baud)) continue;
    for (const auto& format : formats) {
      if (format == "8N1") continue;
      auto port = open_at(baud, format);
      if (scan.failed) return scan;
      if (!port) continue;
      const int before = scan.found;
      probe_ls5_addresses(**port, baud, format);
      if (scan.found > before) break;  // one format per rate: over a pty parity is not seen (H2)
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
    const PortScan scan = scan_port(options, path, bauds, timeout);
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
  auto* command = app.add_subcommand(
      "detect",
      "Find ULS and LS5 sensors on serial ports: tries every baud rate of both documents and both protocols, and the "
      "LS5's byte formats");
  command->add_option("--port", options.ports, "serial port or pty to scan (repeat for several)")->required();
  command->add_option("--baud", options.bauds, "only these rates (default: all of both documents, 115200 first)");
  command->add_option("--ls5-address", options.ls5_addresses, "LS5 network addresses to ask (default 1)")
      ->check(CLI::Range(1, 255));
  command
      ->add_option("--byte-format", options.byte_formats,
                   "only these byte formats (8N1 8E1 8O1 8N2 8E2 8O2; default: 8N1, then the LS5's other five where "
                   "nothing answered at 8N1)")
      ->check(CLI::IsMember({"8N1", "8E1", "8O1", "8N2", "8E2", "8O2"}));
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
