// The LS5's probe of `rangekit detect`: ID only, a read request (§9.2), at each
// network address asked for.
#include <fmt/core.h>

#include <memory>

#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/driver.hpp"

namespace rangekit::cli {
namespace {

std::optional<DetectFinding> probe_address(Transport& port, const std::string& path, std::uint32_t baud,
                                           std::uint8_t address, std::chrono::milliseconds timeout) {
  auto found = ls5::probe(port, address, timeout);
  if (!found) return std::nullopt;
  // Decimal, as --ls5-address takes it and `ls5 info` prints it (§9 "from 1 to 255").
  DetectFinding finding{path, "ls5", baud, fmt::format("{}", found->address), "", ""};
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

}  // namespace

DetectProbe add_ls5_detect_options(CLI::App& detect) {
  auto addresses = std::make_shared<std::vector<std::uint8_t>>(std::vector<std::uint8_t>{0x01});
  detect.add_option("--ls5-address", *addresses, "LS5 network addresses to ask (default 1)")->check(CLI::Range(1, 255));
  return [addresses](Transport& port, const std::string& path, std::uint32_t baud, std::chrono::milliseconds timeout) {
    std::vector<DetectFinding> findings;
    for (const auto address : *addresses) {
      if (auto finding = probe_address(port, path, baud, address, timeout)) findings.push_back(std::move(*finding));
    }
    return findings;
  };
}

}  // namespace rangekit::cli
