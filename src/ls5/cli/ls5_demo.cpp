// The LS5 in `rangekit demo`: its emulator with a part passing under the head, streamed
// at address 01, and its session of `demo --walkthrough` with an Ethernet packet.
#include <fmt/core.h>

#include <array>

#include "cli/commands.hpp"
#include "cli/demo.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/udp_packet.hpp"

namespace rangekit::cli {
namespace {

// 12 mm to 44 mm from the sensor (the 8.1234/40.001 model measures 8.1234 ... 48.1244 mm),
// with one shading gap.
constexpr const char* scene = R"([target]
path = [[0.0, 12.0], [10.0, 44.0], [20.0, 12.0]]
repeat = true
reflectivity = 0.8

[[dropout]]
start_s = 6.0
end_s = 6.5
kind = "shading"
)";

std::vector<std::string> sim_arguments(const DemoFiles& files) {
  return {"ls5", "--port", files.port, "--scene", files.scene, "--control", files.control};
}

// T = n × t (§8.4), 20 × 10 ms (factory period): 5 readings a second.
Result<SampleSourcePtr> start_source(const DemoFiles& files) {
  auto source = start_ls5_source(Ls5SourceOptions{files.port, 115200, 0x01, std::uint8_t{20}});
  if (!source) return make_error(source.error().code, source.error().describe());
  fmt::print("  LS5  address 01  streaming every 20th measurement\n");
  return source;
}

constexpr std::array session{
    WalkthroughLine{Direction::to_device, "#01ON", "§9.4"},
    WalkthroughLine{Direction::from_device, "!01ON", "§9.4"},
    WalkthroughLine{Direction::to_device, "#02W0B01", "§9.4"},
    WalkthroughLine{Direction::from_device, "!02W0B01", "§9.4"},
    WalkthroughLine{Direction::to_device, "#01ID", "§9.2"},
    WalkthroughLine{Direction::from_device, "%01LS5.6.0   b8,1234d40,0010s/n0000157", "§9.2 example"},
    WalkthroughLine{Direction::to_device, "#01W1620", "table 9.3"},
    WalkthroughLine{Direction::to_device, "#01ST", "table 9.1"},
    WalkthroughLine{Direction::from_device, "!25000", "§8.9"},
    WalkthroughLine{Direction::from_device, "!65535", "§8.9 no signal"},
    WalkthroughLine{Direction::to_device, "#00FX", "table 9.1 broadcast"},
    WalkthroughLine{Direction::from_device, "!01LR25000", "table 9.1"},
};

// An Ethernet packet of §10.1, built and read back through the codec.
int walk_through_udp_packet() {
  ls5::UdpPacket packet;
  for (std::size_t i = 0; i < packet.records.size(); ++i) {
    packet.records[i] = ls5::UdpRecord{static_cast<std::uint16_t>(0x2000 + i), 0x07};
  }
  packet.serial_number = 157;
  packet.lower_boundary_mm = 8;
  packet.range_mm = 40;
  packet.counter = 1;
  std::array<std::uint8_t, ls5::udp_packet_size> datagram{};
  if (auto encoded = ls5::encode_udp_packet(packet, datagram); !encoded) {
    fmt::print(stderr, "demo: {}\n", encoded.error().describe());
    return exit_bad_input;
  }
  auto decoded = ls5::decode_udp_packet(datagram);
  if (!decoded) {
    fmt::print(stderr, "demo: {}\n", decoded.error().describe());
    return exit_bad_input;
  }
  const auto first = ls5::udp_distance_mm(decoded->records[0], decoded->range_mm);
  fmt::print("\nLS5 Ethernet: 512-byte packet, checksum {:02X} verified, counter {}, serial {}, {} records;\n",
             datagram[511], decoded->counter, decoded->serial_number, decoded->records.size());
  fmt::print("  first record code 0x{:04X} = {:.4f} mm (formula 10.1, range {} mm)\n", decoded->records[0].code,
             first ? *first : 0.0, decoded->range_mm);
  return exit_ok;
}

int walkthrough() {
  print_walkthrough_session(
      "LS5 triangulation sensor, serial (ls5-manual.txt); range 40.001 mm from the ID reply", session,
      [](Bytes frame, Direction direction) { return describe_ls5_frame(frame, direction, 40.001); });
  return walk_through_udp_packet();
}

}  // namespace

const CliDemo ls5_demo{
    .scene = scene,
    .sim_arguments = sim_arguments,
    .start_source = start_source,
    .busy_output = "streaming",
    .idle_text = "not streaming",
    .walkthrough = walkthrough,
};

}  // namespace rangekit::cli
