// Who the LS5 model is: the --model text, the ID command's 35 characters (table 9.1) and the
// label hosts print.
#include "rangekit/ls5/emulator/firmware.hpp"

#include <exception>
#include <string>

#include "ls5/emulator/command_handlers.hpp"

namespace rangekit::ls5::emulator {

Result<OrderingCode> parse_model(std::string_view text) {
  if (text.starts_with("LS5-")) return parse_ordering_code(text);
  const std::string message =
      "model '" + std::string(text) + "' is not LOWER_MM/RANGE_MM (e.g. 8.1234/40.001) or an ordering code (LS5-...)";
  const auto slash = text.find('/');
  if (slash == std::string_view::npos) return make_error(Errc::bad_number, message);
  try {
    std::size_t used1 = 0;
    std::size_t used2 = 0;
    const std::string lower(text.substr(0, slash));
    const std::string range(text.substr(slash + 1));
    OrderingCode code;
    code.lower_boundary_mm = std::stod(lower, &used1);
    code.range_mm = std::stod(range, &used2);
    if (used1 != lower.size() || used2 != range.size() || code.lower_boundary_mm < 0 || code.range_mm <= 0) {
      return make_error(Errc::bad_number, message);
    }
    code.interface = DigitalInterface::rs485_ethernet;  // the version decides (L6)
    return code;
  } catch (const std::exception&) {
    return make_error(Errc::bad_number, message);
  }
}

// The network address in decimal, as --address takes it and every host message prints it.
std::string Firmware::label() const { return "LS5 " + std::to_string(ram_[address::network_address]); }

void Firmware::handle_identification(const Exchange& exchange) {
  auto identification =
      make_identification(config_.version_text, config_.lower_boundary_mm, config_.range_mm, config_.serial_number);
  if (identification) reply(Reply::identification_of(exchange.own, *identification), exchange.now);
}

}  // namespace rangekit::ls5::emulator
