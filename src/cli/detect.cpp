// `rangekit detect`: which sensors answer on the given ports, at which baud and
// with which protocol. Only read requests are sent (ULS ID/US, LS5 ID), so a
// device is left as it was found.
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
#include "cli/host_sources.hpp"
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
  Finding finding{path, "ls5", baud, fmt::format("{:02X}", found->address), "", ""};
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
    nlohmann::json line{{"port", finding.port},       {"family", finding.family},   {"baud", finding.baud},
                        {"address", finding.address}, {"version", finding.version}, {"detail", finding.detail}};
    fmt::print("{}\n", line.dump());
  } else {
    fmt::print("{}  {}  {} baud  address {}  {}  {}\n", finding.port, finding.family == "uls" ? "ULS" : "LS5",
               finding.baud, finding.address, finding.version, finding.detail);
  }
  std::fflush(stdout);
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

int run_detect(const DetectOptions& options) {
  const auto bauds = options.bauds.empty() ? candidate_bauds() : options.bauds;
  const auto timeout = std::chrono::milliseconds(options.timeout_ms);
  int found = 0;
  bool any_port_failed = false;
  for (const auto& path : options.ports) {
    bool answered = false;
    bool port_failed = false;
    if (auto usable = check_is_terminal(path); !usable) {
      fmt::print(stderr, "rangekit detect: {}\n", usable.error().message);
      any_port_failed = true;
      continue;
    }
    for (const auto baud : bauds) {
      if (answered && !options.all_bauds) break;
      auto port = open_serial(path, baud);
      if (!port) {
        // A rate this system cannot set (14400, H1) is skipped; anything else ends the scan of the port.
        if (port.error().code == Errc::unsupported) continue;
        fmt::print(stderr, "rangekit detect: {}\n", port.error().describe());
        port_failed = true;
        break;
      }
      if (auto finding = probe_uls(**port, path, baud, timeout)) {
        print_finding(*finding, options.jsonl);
        answered = true;
        ++found;
        continue;
      }
      for (const auto address : options.ls5_addresses) {
        if (auto finding = probe_ls5(**port, path, baud, address, timeout)) {
          print_finding(*finding, options.jsonl);
          answered = true;
          ++found;
        }
      }
    }
    any_port_failed = any_port_failed || port_failed;
    if (!answered && !port_failed) {
      fmt::print(stderr, "rangekit detect: nothing answered on {} at any of {} baud rates\n", path, bauds.size());
    }
  }
  if (found > 0) return exit_ok;
  return any_port_failed ? exit_io : exit_no_reply;
}

}  // namespace

void add_detect_command(CLI::App& app, int& exit_code) {
  static DetectOptions options;
  auto* command = app.add_subcommand(
      "detect", "Find ULS and LS5 sensors on serial ports: tries every baud rate of both documents and both protocols");
  command->add_option("--port", options.ports, "serial port or pty to scan (repeat for several)")->required();
  command->add_option("--baud", options.bauds, "only these rates (default: all of both documents, 115200 first)");
  command->add_option("--ls5-address", options.ls5_addresses, "LS5 network addresses to ask (default 1)")
      ->check(CLI::Range(1, 255));
  command->add_option("--timeout-ms", options.timeout_ms, "wait per request")->capture_default_str();
  command->add_flag("--all-bauds", options.all_bauds, "keep trying other rates after a port answered");
  command->add_flag("--jsonl", options.jsonl, "one JSON object per finding");
  command->callback([&exit_code] { exit_code = run_detect(options); });
}

}  // namespace rangekit::cli
