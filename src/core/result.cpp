#include "rangekit/core/result.hpp"

namespace rangekit {

const char* errc_name(Errc code) noexcept {
  switch (code) {
    case Errc::invalid_frame:
      return "invalid frame";
    case Errc::truncated:
      return "truncated";
    case Errc::overlong:
      return "overlong";
    case Errc::bad_hex:
      return "bad hex";
    case Errc::bad_number:
      return "bad number";
    case Errc::bad_checksum:
      return "bad checksum";
    case Errc::unknown_command:
      return "unknown command";
    case Errc::unknown_parameter:
      return "unknown parameter";
    case Errc::out_of_range:
      return "out of range";
    case Errc::wrong_form:
      return "wrong form";
    case Errc::device_error:
      return "device error";
    case Errc::timeout:
      return "timeout";
    case Errc::io:
      return "I/O error";
    case Errc::closed:
      return "closed";
    case Errc::unsupported:
      return "unsupported";
    case Errc::limit:
      return "limit";
  }
  return "unknown error";
}

std::string Error::describe() const { return std::string(errc_name(code)) + ": " + message; }

Error make_error(Errc code, std::string message) { return Error{code, std::move(message), 0}; }

}  // namespace rangekit
