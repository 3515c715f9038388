// §5 ordering codes, §3 error limits, §7 current-loop load (conformance L25).
#include "rangekit/ls5/model.hpp"

#include <array>

#include "rangekit/core/text.hpp"

namespace rangekit::ls5 {
namespace {

Error code_error(std::string_view text, const std::string& what) {
  return make_error(Errc::invalid_frame, "LS5 ordering code '" + std::string(text) + "': " + what);
}

struct AnalogCode {
  std::string_view code;
  AnalogRange range;
};
constexpr std::array<AnalogCode, 3> analog_codes{{
    {"I4", current_4_20_mA},
    {"I0", current_0_20_mA},
    {"U10", voltage_0_10_V},
}};

// Splits at '-' outside the "485/E" interface group: LS5, L/R, interface, analog, outputs, volts, case.
constexpr std::size_t field_count = 7;

}  // namespace

Result<OrderingCode> parse_ordering_code(std::string_view text) {
  std::array<std::string_view, field_count> fields{};
  const std::size_t count = text::split(text, '-', fields);
  if (count != field_count) {
    return code_error(text, "needs 7 parts LS5-LOWER/RANGE-INTERFACE-ANALOG-OUTPUTS-VOLTS-CASE, found " +
                                std::to_string(count > field_count ? field_count + 1 : count));
  }
  if (fields[0] != "LS5") return code_error(text, "does not start with LS5");
  OrderingCode code;
  const auto slash = fields[1].find('/');
  const auto lower = text::parse_decimal(fields[1].substr(0, slash), '.');
  const auto range =
      slash == std::string_view::npos ? std::nullopt : text::parse_decimal(fields[1].substr(slash + 1), '.');
  if (!lower || !range || *lower < 0 || *range <= 0) {
    return code_error(text, "'" + std::string(fields[1]) + "' is not LOWER/RANGE in millimetres");
  }
  code.lower_boundary_mm = *lower;
  code.range_mm = *range;
  if (fields[2] == "232") {
    code.interface = DigitalInterface::rs232;
  } else if (fields[2] == "485") {
    code.interface = DigitalInterface::rs485;
  } else if (fields[2] == "485/E") {
    code.interface = DigitalInterface::rs485_ethernet;
  } else {
    return code_error(text, "interface '" + std::string(fields[2]) + "' is not 232, 485 or 485/E");
  }
  bool analog_known = false;
  for (const auto& analog : analog_codes) {
    if (fields[3] == analog.code) {
      code.analog = analog.range;
      code.analog_code = analog.code;
      analog_known = true;
    }
  }
  if (!analog_known) return code_error(text, "analog output '" + std::string(fields[3]) + "' is not I4, I0 or U10");
  const auto outputs = text::parse_unsigned(fields[4], 1, 2);
  if (!outputs) return code_error(text, "discrete outputs '" + std::string(fields[4]) + "' is not 0, 1 or 2");
  code.discrete_outputs = static_cast<std::uint8_t>(*outputs);
  const auto volts = text::parse_unsigned(fields[5], 2, 36);
  if (!volts || *volts < 5)
    return code_error(text, "supply '" + std::string(fields[5]) + "' is not 5-36 V (table 3.1)");
  code.supply_volts = static_cast<std::uint8_t>(*volts);
  if (fields[6].size() != 1 || fields[6].find_first_of("ABCDE") != 0) {
    if (fields[6] != "A2") return code_error(text, "case '" + std::string(fields[6]) + "' is not A, A2, B, C, D or E");
  }
  code.case_type = fields[6].front();
  return code;
}

bool has_ethernet(const OrderingCode& code) noexcept { return code.interface == DigitalInterface::rs485_ethernet; }

double minimum_load_ohms(double max_current_ma, double supply_volts) noexcept {
  const double amps = max_current_ma / 1000.0;
  return (amps * supply_volts - 0.125) / (amps * amps);
}

}  // namespace rangekit::ls5
