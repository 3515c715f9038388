// The ULS in `rangekit serve --demo`: one unit alone (`silo`) and an RS-485 bus of four
// (`bay-A` .. `bay-D`), each bus unit in a mode of its own.
#include <fmt/core.h>

#include <utility>

#include "cli/demo_scenes.hpp"
#include "cli/host_sources.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "rangekit/uls/driver.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {
namespace {

namespace fs = std::filesystem;

// The bus units share the emulator's scene file (bay-C's: a level rising and
// falling); bay-A, bay-B and bay-D get their own through the control socket.
constexpr const char* bus_scene = R"([[targets]]
name = "level"
path = [[0, 30], [30, 8], [60, 30]]
repeat = true
reflectivity = 0.5
)";

// bay-A in binning (§3): two targets inside the 512 bins of 1 inch (13 m), a crate
// moving slowly (0.1 m/s, so that one measurement's pulses stay within a few bins)
// between 4 m and 8 m in front of a wall at 11.5 m.
const nlohmann::json binning_scene = {
    {"targets",
     {{{"name", "crate"}, {"path", {{0, 4}, {40, 8}, {80, 4}}}, {"repeat", true}, {"reflectivity", 0.7}},
      {{"name", "wall"}, {"distance_m", 11.5}, {"reflectivity", 0.5}}}}};
// bay-B in look down (§3): a floor at 10 m and a box passing at 4 m for 1.5 s of every 4 s.
const nlohmann::json look_down_scene = {{"targets",
                                         {{{"name", "floor"}, {"distance_m", 10}, {"reflectivity", 0.5}},
                                          {{"name", "box"},
                                           {"path", {{0, 20}, {1, 20}, {1.01, 4}, {2.5, 4}, {2.51, 20}, {4, 20}}},
                                           {"repeat", true},
                                           {"reflectivity", 0.7}}}}};
// bay-D in averaging: a wall at 35 m.
const nlohmann::json wall_scene = {{"targets", {{{"name", "wall"}, {"distance_m", 35}, {"reflectivity", 0.9}}}}};

Status set_scene(const std::string& control, char unit, const nlohmann::json& scene) {
  auto client = ControlClient::connect(control);
  if (!client) return std::move(client).error();
  auto reply = client->request({{"cmd", "set_scene"}, {"device", std::string(1, unit)}, {"scene", scene}});
  if (!reply) return std::move(reply).error();
  if (reply->contains("error")) {
    return make_error(Errc::io, fmt::format("bus unit {} scene: {}", unit, (*reply)["error"].dump()));
  }
  return ok_status();
}

// §7: "The Continuous Output setting must be turned off since units only talk on the
// bus when addressed." Then each unit's mode (§8 Set Mode).
Status set_up_bus(const std::string& port) {
  auto link = open_serial(port, 115200);
  if (!link) return std::move(link).error();
  uls::Driver driver(std::move(link).value());
  const std::pair<char, uls::Mode> units[] = {
      {'A', uls::Mode::binning}, {'B', uls::Mode::look_down}, {'C', uls::Mode::averaging}, {'D', uls::Mode::averaging}};
  for (const auto& [unit, mode] : units) {
    const auto fail = [unit = unit](const Error& error) {
      return make_error(error.code, fmt::format("bus unit {}: {}", unit, error.describe()));
    };
    if (auto status = driver.set_address(static_cast<std::uint8_t>(unit)); !status) return fail(status.error());
    if (auto status = driver.set_continuous(false); !status) return fail(status.error());
    if (auto status = driver.set_mode(mode); !status) return fail(status.error());
  }
  return ok_status();
}

Status start(const fs::path& dir, std::vector<SimProcess>& emulators, hub::SiteConfig& site) {
  const auto path = [&](const char* name) { return (dir / name).string(); };
  if (auto status = demo_scenes::write_file(dir / "silo-scene.toml", uls_demo.scene); !status) return status;
  if (auto status = demo_scenes::write_file(dir / "bus-scene.toml", bus_scene); !status) return status;
  const std::vector<std::vector<std::string>> commands{
      {"uls", "--port", path("uls"), "--scene", path("silo-scene.toml"), "--control", path("uls.control")},
      {"uls", "--bus", path("bus"), "--address", "A", "--address", "B", "--address", "C", "--address", "D", "--scene",
       path("bus-scene.toml"), "--control", path("bus.control")}};
  for (const auto& arguments : commands) {
    if (auto status = start_site_emulator(dir, arguments, emulators); !status) return status;
  }
  for (const auto& [unit, scene] :
       {std::pair{'A', &binning_scene}, std::pair{'B', &look_down_scene}, std::pair{'D', &wall_scene}}) {
    if (auto status = set_scene(path("bus.control"), unit, *scene); !status) return status;
  }
  if (auto status = set_up_bus(path("bus")); !status) return status;
  fmt::print(
      "  bus: continuous output off (a bus is polled); bay-A binning, bay-B look down, bay-C and bay-D averaging\n");

  site.sensors.push_back(site_sensor("silo", "uls", path("uls")));
  for (const char unit : {'A', 'B', 'C', 'D'}) {
    hub::SensorConfig bay = site_sensor(fmt::format("bay-{}", unit), "uls", path("bus"));
    bay.address = unit;
    site.sensors.push_back(std::move(bay));
  }
  return ok_status();
}

}  // namespace

// Listed after the LS5, as docs/service.md describes the demo site.
const CliDemoSite uls_demo_site{.summary = "a ULS and a bus of four ULS", .position = 1, .start = start};

}  // namespace rangekit::cli
