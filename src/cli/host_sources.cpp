#include "cli/host_sources.hpp"

namespace rangekit::cli {

Error named(const std::string& what, Error error) {
  error.message = what + ": " + error.message;
  return error;
}

Result<TransportPtr> open_port(const std::string& path, const SerialSettings& settings) {
  return open_serial_link(path, settings);
}

Result<TransportPtr> open_serial(const std::string& path, std::uint32_t baud) {
  return open_port(path, SerialSettings{baud, Parity::none, 1});
}

std::function<Result<TransportPtr>()> reopen_port(const std::string& path, const SerialSettings& settings) {
  return [path, settings] { return open_port(path, settings); };
}

Result<SerialSettings> serial_settings(std::uint32_t baud, std::string_view byte_format) {
  const bool known = byte_format.size() == 3 && byte_format[0] == '8' &&
                     std::string_view("NEO").find(byte_format[1]) != std::string_view::npos &&
                     (byte_format[2] == '1' || byte_format[2] == '2');
  if (!known) {
    return make_error(Errc::out_of_range, "byte format " + std::string(byte_format) + " is not one of 8N1 ... 8O2");
  }
  const Parity parity = byte_format[1] == 'N' ? Parity::none : byte_format[1] == 'E' ? Parity::even : Parity::odd;
  return SerialSettings{baud, parity, byte_format[2] == '2' ? 2 : 1};
}

}  // namespace rangekit::cli
