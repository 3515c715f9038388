#include "cli/demo_site.hpp"
#include "cli/demo_scenes.hpp"

#include <arpa/inet.h>
#include <fmt/core.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <utility>

#include "cli/demo_scenes.hpp"
#include "cli/host_sources.hpp"
#include "rangekit/core/fd_transport.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "rangekit/uls/driver.hpp"

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

// A UDP port free on loopback now, for the LS5 emulator's packets and the service's listener.
Result<std::uint16_t> free_udp_port() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return make_error(Errc::io, errno_text("socket", errno));
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  const bool bound = ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
                     ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0;
  const int error = errno;
  ::close(fd);
  if (!bound) return make_error(Errc::io, errno_text("cannot find a free UDP port", error));
  return static_cast<std::uint16_t>(ntohs(address.sin_port));
}

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

hub::SensorConfig sensor(std::string name, std::string family, std::string port) {
  hub::SensorConfig config;
  config.name = std::move(name);
  config.family = std::move(family);
  config.port = std::move(port);
  return config;
}

}  // namespace

Result<DemoSite> DemoSite::start() {
  std::string pattern = (fs::temp_directory_path() / "rangekit-serve-demo-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    return make_error(Errc::io, "cannot create a directory in " + fs::temp_directory_path().string());
  }
  DemoSite demo;
  demo.dir_ = pattern;
  const fs::path& dir = demo.dir_;
  for (const auto& [file, text] :
       {std::pair{"silo-scene.toml", demo_scenes::uls}, std::pair{"belt-scene.toml", demo_scenes::ls5},
        std::pair{"bus-scene.toml", bus_scene}}) {
    if (auto status = demo_scenes::write_file(dir / file, text); !status) return std::move(status).error();
  }
  auto udp_port = free_udp_port();
  if (!udp_port) return std::move(udp_port).error();
  const std::string udp = fmt::format("127.0.0.1:{}", *udp_port);
  const auto path = [&](const char* name) { return (dir / name).string(); };

  fmt::print("rangekit serve --demo: starting the emulators on pseudo-terminals in {}\n", dir.string());
  const std::vector<std::vector<std::string>> commands{
      {"ls5", "--port", path("ls5"), "--scene", path("belt-scene.toml"), "--udp", udp, "--control",
       path("ls5.control")},
      {"uls", "--port", path("uls"), "--scene", path("silo-scene.toml"), "--control", path("uls.control")},
      {"uls", "--bus", path("bus"), "--address", "A", "--address", "B", "--address", "C", "--address", "D", "--scene",
       path("bus-scene.toml"), "--control", path("bus.control")}};
  for (const auto& arguments : commands) {
    const std::string log = (dir / (fmt::format("sim-{}.log", demo.emulators_.size()))).string();
    auto emulator = SimProcess::start(arguments, log, std::chrono::seconds(15));
    if (!emulator) return std::move(emulator).error();
    fmt::print("  {}\n", emulator->ready_line());
    demo.emulators_.push_back(std::move(emulator).value());
  }
  for (const auto& [unit, scene] :
       {std::pair{'A', &binning_scene}, std::pair{'B', &look_down_scene}, std::pair{'D', &wall_scene}}) {
    if (auto status = set_scene(path("bus.control"), unit, *scene); !status) return std::move(status).error();
  }
  if (auto status = set_up_bus(path("bus")); !status) return std::move(status).error();
  fmt::print("  bus: Continuous Output off (§7); bay-A binning, bay-B look down, bay-C and bay-D averaging\n");

  demo.site_.file = path("demo-site.toml");  // not written: the site is built here
  demo.site_.service.capture_dir = path("captures");
  demo.site_.sensors.push_back(sensor("belt", "ls5", path("ls5")));
  hub::SensorConfig belt_udp = sensor("belt-udp", "ls5", "");
  belt_udp.udp = udp;
  demo.site_.sensors.push_back(std::move(belt_udp));
  demo.site_.sensors.push_back(sensor("silo", "uls", path("uls")));
  for (const char unit : {'A', 'B', 'C', 'D'}) {
    hub::SensorConfig bay = sensor(fmt::format("bay-{}", unit), "uls", path("bus"));
    bay.address = unit;
    demo.site_.sensors.push_back(std::move(bay));
  }
  return demo;
}

DemoSite::DemoSite(DemoSite&& other) noexcept
    : dir_(std::exchange(other.dir_, {})),
      emulators_(std::exchange(other.emulators_, {})),
      site_(std::move(other.site_)) {}

DemoSite& DemoSite::operator=(DemoSite&& other) noexcept {
  if (this != &other) {
    stop();
    dir_ = std::exchange(other.dir_, {});
    emulators_ = std::exchange(other.emulators_, {});
    site_ = std::move(other.site_);
  }
  return *this;
}

DemoSite::~DemoSite() { stop(); }

void DemoSite::stop() noexcept {
  for (SimProcess& emulator : emulators_) emulator.stop();
  emulators_.clear();
  if (!dir_.empty()) {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
    dir_.clear();
  }
}

}  // namespace rangekit::cli
