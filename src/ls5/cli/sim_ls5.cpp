// `rangekit sim ls5`: the LS5 emulator on a pseudo-terminal, one or
// more sensors on the line (RS-485 bus), the Ethernet stream to a loopback
// UDP destination. Firmware: src/ls5/emulator; how to run it: docs/emulator-ls5.md.
#include <arpa/inet.h>
#include <fmt/core.h>
#include <netinet/in.h>

#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/sim.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/ls5/emulator/firmware.hpp"

namespace rangekit::cli {

namespace {

struct Ls5SimOptions {
  std::string port;
  std::vector<std::string> addresses;
  std::string model = "8.1234/40.001";
  std::uint32_t serial = 157;
  std::string version = "LS5.12.0";
  std::string udp;
  std::string analog;  // default: from the ordering code, else 4-20mA
};

std::optional<std::uint8_t> parse_address(const std::string& text) {
  try {
    std::size_t used = 0;
    const bool hex = text.starts_with("0x") || text.starts_with("0X");
    const unsigned long value = std::stoul(hex ? text.substr(2) : text, &used, hex ? 16 : 10);
    if (used != text.size() - (hex ? 2 : 0) || value < 1 || value > 255) return std::nullopt;
    return static_cast<std::uint8_t>(value);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// --udp HOST:PORT as parameters 5C-5F and 6C/6D hold a destination (L93).
Result<ls5::emulator::UdpDestination> destination_of(const Endpoint& endpoint) {
  in_addr address{};
  const std::string host = endpoint.host == "localhost" ? "127.0.0.1" : endpoint.host;
  if (::inet_pton(AF_INET, host.c_str(), &address) != 1) {
    return make_error(Errc::bad_number, "'" + endpoint.host + "' is not an IPv4 address");
  }
  if (endpoint.port == 0) return make_error(Errc::out_of_range, "port 0: the destination port is 1-65535");
  return ls5::emulator::UdpDestination{ntohl(address.s_addr), endpoint.port};
}

// Where a packet for `destination` goes. The emulated network is this host: the broadcast
// 255.255.255.255 (table 9.2's default) reaches it at 127.0.0.1, never a real network.
Endpoint endpoint_of(const ls5::emulator::UdpDestination& destination) {
  const bool broadcast = destination.ip == 0xFFFFFFFFU;
  return Endpoint{broadcast ? "127.0.0.1" : ls5::format_ipv4(destination.ip), destination.port};
}

// One sensor's Ethernet port: packets leave from the source port its parameters name (table 9.2
// 6E/6F), the socket bound again when they change, and go where 5C-5F and 6C/6D say.
// UdpSocket::bind sets SO_REUSEADDR, so the sensors of one bus share a port as sensors with IP
// addresses of their own do; a port another program holds cannot be bound, and the packet is not
// sent (an error event, never another port).
class UdpPort {
 public:
  Status send(const ls5::emulator::UdpDatagram& datagram) {
    if (!socket_ || bound_port_ != datagram.source_port) {
      socket_.reset();
      auto bound = UdpSocket::bind(Endpoint{"127.0.0.1", datagram.source_port});
      if (!bound) {
        return report(make_error(Errc::io, fmt::format("UDP source port {} (parameters 6E/6F) cannot be used: {}; "
                                                       "packets are not sent until it can be or 6E/6F name another",
                                                       datagram.source_port, bound.error().message)));
      }
      socket_.emplace(std::move(*bound));
      bound_port_ = datagram.source_port;
    }
    const Endpoint to = endpoint_of(ls5::emulator::UdpDestination{datagram.destination_ip, datagram.destination_port});
    return report(socket_->send_to(Bytes(datagram.bytes.data(), datagram.bytes.size()), to));
  }
  void attach(const ls5::emulator::Firmware* sensor) { sensor_ = sensor; }

 private:
  // A line on stderr when sending starts failing or works again, not one per packet.
  Status report(Status status) {
    const std::string error = status ? std::string() : status.error().message;
    if (error != last_error_) {
      const std::string label = sensor_ != nullptr ? sensor_->label() : "LS5";
      if (!error.empty()) {
        fmt::print(stderr, "rangekit sim ls5 [{}]: {}\n", label, error);
      } else {
        fmt::print(stderr, "rangekit sim ls5 [{}]: UDP packets leave from port {} again\n", label, bound_port_);
      }
      last_error_ = error;
    }
    return status;
  }

  std::optional<UdpSocket> socket_;
  std::uint16_t bound_port_ = 0;
  const ls5::emulator::Firmware* sensor_ = nullptr;  // for the label in messages
  std::string last_error_;
};

// Control requests for a sensor name it with "address" (decimal or "0x1A"); with one sensor it may be left out.
nlohmann::json route(const std::vector<std::unique_ptr<ls5::emulator::Firmware>>& sensors,
                     const nlohmann::json& request) {
  static const std::vector<std::string> device_commands = {"outputs", "sync", "power_cycle", "move_target",
                                                           "set_scene"};
  const std::string command = request.value("cmd", "");
  if (std::find(device_commands.begin(), device_commands.end(), command) == device_commands.end()) return nullptr;
  if (!request.contains("address")) {
    if (sensors.size() == 1) return sensors.front()->control(request, Nanos{0});
    return {{"error", command + ": several sensors share the line; name one with \"address\""}};
  }
  std::optional<std::uint8_t> address;
  if (request["address"].is_number_unsigned()) {
    const auto value = request["address"].get<std::uint64_t>();
    if (value >= 1 && value <= 255) address = static_cast<std::uint8_t>(value);
  } else if (request["address"].is_string()) {
    address = parse_address(request["address"].get<std::string>());
  }
  if (!address) return {{"error", command + ": address must be 1-255"}};
  for (const auto& sensor : sensors) {
    if (sensor->ram(ls5::address::network_address) == *address) return sensor->control(request, Nanos{0});
  }
  return {{"error", fmt::format("{}: no sensor at address {}", command, *address)}};
}

int run(const Ls5SimOptions& options, const SimCommonOptions& common) {
  auto model = ls5::emulator::parse_model(options.model);
  if (!model) {
    fmt::print(stderr, "rangekit sim ls5: --model: {}\n", model.error().message);
    return exit_usage;
  }
  ls5::AnalogRange analog = model->analog;  // the ordering code's, 4-20 mA for a bare LOWER/RANGE
  if (options.analog == "4-20mA") {
    analog = ls5::current_4_20_mA;
  } else if (options.analog == "0-20mA") {
    analog = ls5::current_0_20_mA;
  } else if (options.analog == "0-10V") {
    analog = ls5::voltage_0_10_V;
  } else if (!options.analog.empty()) {
    fmt::print(stderr, "rangekit sim ls5: --analog must be 4-20mA, 0-20mA or 0-10V\n");
    return exit_usage;
  }
  ls5::emulator::Scene scene;
  if (!common.scene.empty()) {
    auto loaded = ls5::emulator::load_scene(common.scene);
    if (!loaded) {
      fmt::print(stderr, "rangekit sim ls5: {}\n", loaded.error().message);
      return scene_exit_code(loaded.error());
    }
    scene = std::move(*loaded);
  }
  std::optional<ls5::emulator::UdpDestination> udp_destination;
  if (!options.udp.empty()) {
    auto endpoint = parse_endpoint(options.udp);
    auto destination = endpoint ? destination_of(*endpoint) : Result<ls5::emulator::UdpDestination>(endpoint.error());
    if (!destination) {
      fmt::print(stderr, "rangekit sim ls5: --udp: {}\n", destination.error().message);
      return exit_usage;
    }
    udp_destination = *destination;
  }
  std::vector<std::string> addresses = options.addresses;
  if (addresses.empty()) addresses.push_back("1");
  std::vector<std::unique_ptr<UdpPort>> udp_ports;  // one per sensor, each its own source port; outlives them
  std::vector<std::unique_ptr<ls5::emulator::Firmware>> sensors;
  for (std::size_t i = 0; i < addresses.size(); ++i) {
    const auto address = parse_address(addresses[i]);
    if (!address) {
      fmt::print(stderr, "rangekit sim ls5: --address '{}' must be 1-255 (decimal or 0x hex)\n", addresses[i]);
      return exit_usage;
    }
    ls5::emulator::FirmwareConfig config;
    config.lower_boundary_mm = model->lower_boundary_mm;
    config.range_mm = model->range_mm;
    config.ethernet = ls5::has_ethernet(*model);
    config.discrete_outputs = model->discrete_outputs;
    config.serial_number = options.serial + static_cast<std::uint32_t>(i);  // each sensor its own serial
    config.version_text = options.version;
    config.factory_address = *address;
    config.analog = analog;
    config.state_dir = common.state_dir;
    config.seed = common.seed + static_cast<std::uint32_t>(i);
    config.scene = scene;
    UdpPort* udp_port = nullptr;
    config.udp_destination = udp_destination;
    if (udp_destination) {
      udp_ports.push_back(std::make_unique<UdpPort>());
      udp_port = udp_ports.back().get();
      config.udp_sink = [udp_port](const ls5::emulator::UdpDatagram& datagram) { return udp_port->send(datagram); };
    }
    auto firmware = ls5::emulator::Firmware::create(std::move(config));
    if (!firmware) {
      fmt::print(stderr, "rangekit sim ls5: {}\n", firmware.error().message);
      return exit_usage;
    }
    if (udp_port != nullptr) udp_port->attach(firmware->get());
    sensors.push_back(std::move(*firmware));
  }
  LineConfig line{"port", std::nullopt, {}};
  if (!options.port.empty()) line.link_path = options.port;
  for (const auto& sensor : sensors) line.attachments.push_back(LineAttachment{sensor.get(), 0});
  std::string title = "rangekit sim ls5";
  for (const auto& sensor : sensors) title += " [" + sensor->label() + "]";
  return run_emulator({line}, common, title,
                      [&sensors](const nlohmann::json& request, Nanos /*now*/) { return route(sensors, request); });
}

}  // namespace

void add_sim_ls5(CLI::App& sim, int& exit_code) {
  auto* command = sim.add_subcommand("ls5", "LS5 emulator: firmware model on a pseudo-terminal (docs/emulator-ls5.md)");
  auto options = std::make_shared<Ls5SimOptions>();
  auto common = std::make_shared<SimCommonOptions>();
  command->add_option("--port", options->port, "symlink to create for the serial line's pty");
  command->add_option("--address", options->addresses,
                      "network address of a sensor on the line, 1-255 (repeat for an RS-485 bus); default 1");
  command
      ->add_option("--model", options->model,
                   "LOWER_MM/RANGE_MM (8.1234/40.001) or an ordering code (LS5-100/200-485/E-I4-2-12-A)")
      ->capture_default_str();
  command->add_option("--serial", options->serial, "serial number (the next sensors get +1, +2, ...)")
      ->capture_default_str();
  command->add_option("--version", options->version, "firmware version, LS5.x.y (LS5.12.x has Ethernet)")
      ->capture_default_str();
  command->add_option("--udp", options->udp,
                      "connect Ethernet: the destination parameters 5C-5F/6C-6D start at HOST:PORT (as delivered, "
                      "in ROM until FL stores others); no packets are sent without it");
  command->add_option("--analog", options->analog,
                      "analog output type: 4-20mA, 0-20mA, 0-10V (default: the ordering code's, else 4-20mA)");
  add_common_sim_options(*command, *common);
  command->callback([options, common, &exit_code] { exit_code = run(*options, *common); });
}

}  // namespace rangekit::cli
