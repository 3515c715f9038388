// The ULS's probe of `rangekit detect`: ID and US only, read requests (§8), at 8N1, its
// only byte format (§9).
#include <fmt/core.h>

#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/formulas.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {

DetectProbe add_uls_detect_options(CLI::App& /*detect*/) {
  return [](Transport& port, const std::string& path, std::uint32_t baud, std::chrono::milliseconds timeout) {
    std::vector<DetectFinding> findings;
    auto found = uls::probe(port, std::nullopt, timeout);
    if (!found) return findings;
    findings.push_back(DetectFinding{path, "uls", baud, found->address ? fmt::format("0x{:02X}", *found->address) : "-",
                                     found->version, found->status.measuring() ? "measuring" : "idle"});
    return findings;
  };
}

}  // namespace rangekit::cli
