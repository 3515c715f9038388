// The ULS in `rangekit demo`: its emulator with a moving pallet, streamed from the
// configuration port, and its session of `demo --walkthrough`.
#include <fmt/core.h>

#include <array>

#include "cli/commands.hpp"
#include "cli/demo.hpp"
#include "cli/host_sources.hpp"
#include "rangekit/uls/driver.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {
namespace {

// A pallet moving between 5 m and 25 m and back every 20 s, with a weak far wall
// behind it (§3: binning would show both).
constexpr const char* scene = R"(dust = 0.002

[[targets]]
name = "pallet"
path = [[0, 5], [10, 25], [20, 5]]
repeat = true
reflectivity = 0.6

[[targets]]
name = "back wall"
distance_m = 60
reflectivity = 0.2
)";

// Its measurement output is the configuration port (§2 Output Setup).
std::string config_port(const DemoFiles& files) { return (files.dir / "uls-config").string(); }

std::vector<std::string> sim_arguments(const DemoFiles& files) {
  return {"uls",     "--port",    files.port,  "--config-port", config_port(files),
          "--scene", files.scene, "--control", files.control};
}

// 5000 pulses/s over 1024 pulses per reading is about 4.9 readings a second, each with
// its pulse width (§8 DM).
Result<SampleSourcePtr> start_source(const DemoFiles& files) {
  const std::string port = config_port(files);
  {
    auto link = open_serial(port, 115200);
    if (!link) return make_error(link.error().code, link.error().describe());
    uls::Driver setup(std::move(link).value());
    auto version = setup.version();
    if (!version) return make_error(version.error().code, "ULS: " + version.error().describe());
    if (auto status = setup.set_prf(5000); !status) {
      return make_error(status.error().code, "ULS PF: " + status.error().describe());
    }
    if (auto status = setup.set_display_mode(uls::DisplayMode::range_and_intensity); !status) {
      return make_error(status.error().code, "ULS DM: " + status.error().describe());
    }
    fmt::print("  ULS  {}  averaging, PRF 5000, 1024 pulses per reading, range and pulse width\n", *version);
  }
  auto source = start_uls_source(UlsSourceOptions{port, 115200, std::nullopt, "uls-config"});
  if (!source) return make_error(source.error().code, source.error().describe());
  return source;
}

constexpr std::array session{
    WalkthroughLine{Direction::to_device, "$ID", "§8 Get Software Version"},
    WalkthroughLine{Direction::from_device, "$ID,ULS 0.97 03/2005", "§8"},
    WalkthroughLine{Direction::to_device, "$MM", "§8 example"},
    WalkthroughLine{Direction::from_device, "$MM,1", "§8 example"},
    WalkthroughLine{Direction::to_device, "#ZMM,1", "§8 example: unit 0x5A"},
    WalkthroughLine{Direction::from_device, "#ZOK", "§8"},
    WalkthroughLine{Direction::to_device, "$PF,3000", "§9 example: 3000 PRF"},
    WalkthroughLine{Direction::to_device, "$PO,300", "§9 example: 300 PPM, 10 Hz"},
    WalkthroughLine{Direction::to_device, "$PF,6000", "§2: PRF 10-5000"},
    WalkthroughLine{Direction::from_device, "$ER,32", "§10"},
    WalkthroughLine{Direction::to_device, "$DM,2", "§8 range and intensity"},
    WalkthroughLine{Direction::to_device, "$GO", "§8"},
    WalkthroughLine{Direction::from_device, "$BM,12.345,8600", "§8/§9 averaging, range and pulse width (ps)"},
    WalkthroughLine{Direction::from_device, "$ER,4", "§10 streamed"},
    WalkthroughLine{Direction::to_device, "$TT,107AC0", "§3: 1,080,000 pulses = 6 min at 3000 PRF"},
    WalkthroughLine{Direction::from_device, "$0BB8", "§3: 3000 pulses = 1 s at 3 kHz"},
    WalkthroughLine{Direction::from_device, "$0", "§8: no presence"},
};

int walkthrough() {
  const uls::MeasurementContext context{uls::Mode::averaging, uls::DisplayMode::range_and_intensity, uls::Units::metres,
                                        false};
  print_walkthrough_session(
      "ULS, Universal Laser Sensor (uls-interface-spec.txt)", session,
      [&context](Bytes frame, Direction direction) { return describe_uls_frame(frame, direction, context); });
  return exit_ok;
}

}  // namespace

const CliDemo uls_demo{
    .scene = scene,
    .sim_arguments = sim_arguments,
    .start_source = start_source,
    .busy_output = "measuring",
    .idle_text = "not measuring",
    .walkthrough = walkthrough,
};

}  // namespace rangekit::cli
