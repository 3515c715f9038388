// The ULS as the rangekit binary sees it (cli/cli_family.hpp).
#include "rangekit/uls/formulas.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::uls {
namespace {

std::vector<std::uint32_t> bauds() {
  const auto choices = baud_choices();  // §8 BR
  return {choices.begin(), choices.end()};
}

}  // namespace

const cli::CliFamily& cli_family() noexcept {
  static const cli::CliFamily descriptor{
      .name = "uls",
      .label = "ULS",
      .add_command = cli::add_uls_command,
      .add_sim_command = cli::add_sim_uls,
      .add_decode_options = cli::add_uls_decode_options,
      .tables = cli::uls_tables,
      .default_max_speed = "25",
      .detect = {.bauds = bauds, .other_byte_formats = false, .add_options = cli::add_uls_detect_options},
      .add_capture_options = cli::add_uls_capture_options,
      .demo = cli::uls_demo,
      .demo_site = cli::uls_demo_site,
      .capture_scene = cli::uls_capture_scene,
  };
  return descriptor;
}

}  // namespace rangekit::uls
