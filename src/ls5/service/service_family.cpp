// The LS5 as the sensor service sees it (hub/service_family.hpp).
#include "rangekit/ls5/service_family.hpp"

#include <array>

#include "ls5/service/service.hpp"
#include "rangekit/ls5/settings.hpp"

namespace rangekit::ls5::service {
namespace {

// The network address, table 9.2 parameter 01: 1-255.
Result<int> parse_address(const hub::AddressValue& value) {
  if (!value.number) return make_error(Errc::invalid_frame, "address must be an integer");
  if (*value.number < 1 || *value.number > 255) {
    return make_error(Errc::out_of_range, "address " + std::to_string(*value.number) +
                                              " is out of range 1-255 (LS5 network address, parameter 01)");
  }
  return static_cast<int>(*value.number);
}

Result<SerialSettings> byte_format(std::string_view format, SerialSettings settings) {
  std::string allowed;
  for (const ByteFormat& known : byte_format_table()) {
    if (known.name == format) {
      settings.parity = known.parity == Parity::none   ? rangekit::Parity::none
                        : known.parity == Parity::even ? rangekit::Parity::even
                                                       : rangekit::Parity::odd;
      settings.stop_bits = known.stop_bits;
      return settings;
    }
    allowed += (allowed.empty() ? "" : ", ") + std::string(known.name);
  }
  return make_error(Errc::out_of_range,
                    "format '" + std::string(format) + "' is not an LS5 byte format (" + allowed + ")");
}

// Table 9.2 parameter 04's speeds.
std::span<const std::uint32_t> bauds() noexcept {
  static const std::vector<std::uint32_t> speeds = [] {
    std::vector<std::uint32_t> all;
    for (const BaudRateInfo& rate : baud_rate_table()) all.push_back(rate.baud);
    return all;
  }();
  return speeds;
}

constexpr std::array<std::string_view, 1> read_only{"read"};
constexpr std::array actions{
    hub::ActionDescriptor{"single", "one measurement now (LR)", {}},
    hub::ActionDescriptor{"save", "the settings into flash memory (FL)", {}},
    hub::ActionDescriptor{"reset", "every parameter to its default (DF)", {}},
    hub::ActionDescriptor{"latch", "latch a result and read it (FX, FR); with read: the latched result alone (FR)",
                          read_only, true},
};

const hub::ServiceFamily descriptor{
    .name = "ls5",
    .manufacturer = "Prizma",
    .model = "LS5",
    .parse_address = parse_address,
    .byte_format = byte_format,
    .bauds = bauds,
    .udp = true,
    .bus = false,
    .one_per_port = "an LS5 stream holds its line, so one LS5 per port",
    .port_backend = make_port_backend,
    .udp_backend = make_udp_backend,
    .parse_address_text = nullptr,
    .address_help = {},
    .scan_addresses = nullptr,
    .settings_schema = settings_schema,
    .actions = actions,
};

}  // namespace

const hub::ServiceFamily& service_family() noexcept { return descriptor; }

}  // namespace rangekit::ls5::service
