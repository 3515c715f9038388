// The LS5 in `rangekit serve --demo`: one emulated sensor heard twice, on its serial
// stream (`belt`) and as Ethernet packets on loopback (`belt-udp`).
#include <arpa/inet.h>
#include <fmt/core.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

#include "cli/demo_scenes.hpp"
#include "ls5/cli/ls5_cli.hpp"

namespace rangekit::cli {
namespace {

namespace fs = std::filesystem;

// A UDP port free on loopback now, for the emulator's packets and the service's listener.
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

Status start(const fs::path& dir, std::vector<SimProcess>& emulators, hub::SiteConfig& site) {
  const auto path = [&](const char* name) { return (dir / name).string(); };
  if (auto status = demo_scenes::write_file(dir / "belt-scene.toml", ls5_demo.scene); !status) return status;
  auto udp_port = free_udp_port();
  if (!udp_port) return std::move(udp_port).error();
  const std::string udp = fmt::format("127.0.0.1:{}", *udp_port);
  if (auto status = start_site_emulator(dir,
                                        {"ls5", "--port", path("ls5"), "--scene", path("belt-scene.toml"), "--udp", udp,
                                         "--control", path("ls5.control")},
                                        emulators);
      !status) {
    return status;
  }
  site.sensors.push_back(site_sensor("belt", "ls5", path("ls5")));
  hub::SensorConfig belt_udp = site_sensor("belt-udp", "ls5", "");
  belt_udp.udp = udp;
  site.sensors.push_back(std::move(belt_udp));
  return ok_status();
}

}  // namespace

const CliDemoSite ls5_demo_site{.summary = "an LS5 (serial and UDP)", .position = 0, .start = start};

}  // namespace rangekit::cli
