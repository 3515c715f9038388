// The ULS as the sensor service sees it (hub/service_family.hpp).
#include "rangekit/uls/service_family.hpp"

#include <array>

#include "rangekit/uls/bus.hpp"
#include "rangekit/uls/formulas.hpp"
#include "uls/service/service.hpp"

namespace rangekit::uls::service {
namespace {

// A unit address as §8's UA table writes it ("A", "0x41" or 65).
Result<int> parse_address(const hub::AddressValue& value) {
  if (!value.number && !value.text) {
    return make_error(Errc::invalid_frame, "address must be a character (\"A\") or a number");
  }
  const std::string text = value.number ? std::to_string(*value.number) : *value.text;
  const auto parsed = parse_unit_address(text);
  if (!parsed) {
    return make_error(Errc::out_of_range,
                      "address '" + text + "' is not a ULS unit address (0x30-0xEF, e.g. \"A\" or \"0x41\")");
  }
  return static_cast<int>(*parsed);
}

Result<SerialSettings> byte_format(std::string_view format, SerialSettings settings) {
  if (format != "8N1") {
    return make_error(Errc::out_of_range, "format '" + std::string(format) + "': the ULS speaks 8N1 only");
  }
  return settings;
}

constexpr std::array<std::string_view, 2> on_off{"on", "off"};
constexpr std::array actions{
    hub::ActionDescriptor{"single", "one measurement now (BM)", {}},
    hub::ActionDescriptor{"pointer", "the visible pointer on or off (PT)", on_off},
    hub::ActionDescriptor{"save", "the settings into non-volatile memory (SU)", {}},
    hub::ActionDescriptor{"reset", "every setting to its factory value, then read back", {}},
};

const hub::ServiceFamily descriptor{
    .name = "uls",
    .manufacturer = "Laser Technology Inc.",
    .model = "ULS",
    .parse_address = parse_address,
    .byte_format = byte_format,
    .bauds = baud_choices,  // §8 BR
    .udp = false,
    .bus = true,
    .one_per_port = {},
    .port_backend = make_port_backend,
    .udp_backend = nullptr,
    .parse_address_text = parse_unit_address,
    .address_help = "0x30..0xEF, e.g. 'E'",
    .scan_addresses = typable_addresses,  // §8 UA: a-z, A-Z, 0-9
    .settings_schema = settings_schema,
    .actions = actions,
};

}  // namespace

const hub::ServiceFamily& service_family() noexcept { return descriptor; }

}  // namespace rangekit::uls::service
