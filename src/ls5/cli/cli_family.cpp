// The LS5 as the rangekit binary sees it (cli/cli_family.hpp).
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::ls5 {
namespace {

std::vector<std::uint32_t> bauds() {
  std::vector<std::uint32_t> rates;
  for (const auto& row : baud_rate_table()) rates.push_back(row.baud);  // table 9.2 (03)
  return rates;
}

}  // namespace

const cli::CliFamily& cli_family() noexcept {
  static const cli::CliFamily descriptor{
      .name = "ls5",
      .label = "LS5",
      .add_command = cli::add_ls5_command,
      .add_sim_command = cli::add_sim_ls5,
      .add_decode_options = cli::add_ls5_decode_options,
      .tables = cli::ls5_tables,
      .default_max_speed = "its range a second",
      .detect = {.bauds = bauds, .other_byte_formats = true, .add_options = cli::add_ls5_detect_options},
      .add_capture_options = cli::add_ls5_capture_options,
      .demo = cli::ls5_demo,
      .demo_site = cli::ls5_demo_site,
      .capture_scene = cli::ls5_capture_scene,
  };
  return descriptor;
}

}  // namespace rangekit::ls5
