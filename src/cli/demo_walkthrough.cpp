// `rangekit demo --walkthrough`: a sample session typed from the two documents,
// both directions, decoded through the same codecs the drivers use.
#include <fmt/core.h>

#include <array>

#include "cli/commands.hpp"
#include "cli/demo.hpp"
#include "cli/describe.hpp"
#include "rangekit/ls5/udp_packet.hpp"

namespace rangekit::cli {
namespace {

struct Line {
  Direction direction;
  std::string_view wire;  // without the CR
  std::string_view source;
};

constexpr std::array uls_session{
    Line{Direction::to_device, "$ID", "§8 Get Software Version"},
    Line{Direction::from_device, "$ID,ULS 0.97 03/2005", "§8"},
    Line{Direction::to_device, "$MM", "§8 example"},
    Line{Direction::from_device, "$MM,1", "§8 example"},
    Line{Direction::to_device, "#ZMM,1", "§8 example: unit 0x5A"},
    Line{Direction::from_device, "#ZOK", "§8"},
    Line{Direction::to_device, "$PF,3000", "§9 example: 3000 PRF"},
    Line{Direction::to_device, "$PO,300", "§9 example: 300 PPM, 10 Hz"},
    Line{Direction::to_device, "$PF,6000", "§2: PRF 10-5000"},
    Line{Direction::from_device, "$ER,32", "§10"},
    Line{Direction::to_device, "$DM,2", "§8 range and intensity"},
    Line{Direction::to_device, "$GO", "§8"},
    Line{Direction::from_device, "$BM,12.345,8600", "§8/§9 averaging, range and pulse width (ps)"},
    Line{Direction::from_device, "$ER,4", "§10 streamed"},
    Line{Direction::to_device, "$TT,107AC0", "§3: 1,080,000 pulses = 6 min at 3000 PRF"},
    Line{Direction::from_device, "$0BB8", "§3: 3000 pulses = 1 s at 3 kHz"},
    Line{Direction::from_device, "$0", "§8: no presence"},
};

constexpr std::array ls5_session{
    Line{Direction::to_device, "#01ON", "§9.4"},
    Line{Direction::from_device, "!01ON", "§9.4"},
    Line{Direction::to_device, "#02W0B01", "§9.4"},
    Line{Direction::from_device, "!02W0B01", "§9.4"},
    Line{Direction::to_device, "#01ID", "§9.2"},
    Line{Direction::from_device, "%01LS5.6.0   b8,1234d40,0010s/n0000157", "§9.2 example"},
    Line{Direction::to_device, "#01W1620", "table 9.3"},
    Line{Direction::to_device, "#01ST", "table 9.1"},
    Line{Direction::from_device, "!25000", "§8.9"},
    Line{Direction::from_device, "!65535", "§8.9 no signal"},
    Line{Direction::to_device, "#00FX", "table 9.1 broadcast"},
    Line{Direction::from_device, "!01LR25000", "table 9.1"},
};

void print_session(std::string_view title, std::span<const Line> lines, bool uls) {
  fmt::print("\n{}\n", title);
  const uls::MeasurementContext context{uls::Mode::averaging, uls::DisplayMode::range_and_intensity, uls::Units::metres,
                                        false};
  for (const auto& line : lines) {
    const Bytes frame = as_bytes(line.wire);
    const std::string description =
        uls ? describe_uls_frame(frame, line.direction, context) : describe_ls5_frame(frame, line.direction, 40.001);
    fmt::print("  {} {:<40} {}\n", line.direction == Direction::to_device ? "host ->" : "     <-", line.wire,
               description);
    fmt::print("          {:<40} ({})\n", "", line.source);
  }
}

}  // namespace

int run_walkthrough() {
  fmt::print("rangekit demo --walkthrough: a sample session typed from the two documents, decoded by the codecs.\n");
  print_session("ULS, Universal Laser Sensor (uls-interface-spec.txt)", uls_session, true);
  print_session("LS5 triangulation sensor, serial (ls5-manual.txt); range 40.001 mm from the ID reply", ls5_session,
                false);

  // An Ethernet packet of §10.1, built and read back through the codec.
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
  fmt::print("\nLS5 Ethernet (§10.1): 512-byte packet, checksum {:02X} verified, counter {}, serial {}, {} records;\n",
             datagram[511], decoded->counter, decoded->serial_number, decoded->records.size());
  fmt::print("  first record code 0x{:04X} = {:.4f} mm (formula 10.1, range {} mm)\n", decoded->records[0].code,
             first ? *first : 0.0, decoded->range_mm);
  return exit_ok;
}

}  // namespace rangekit::cli
