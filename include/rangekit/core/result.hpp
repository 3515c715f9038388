// Errors as values: every fallible call in rangekit returns Result<T>.
// A small type of our own (not std::expected) so that g++ 12 in C++20 mode and
// clang 14 (libFuzzer builds) compile the same code.
#pragma once

#include <string>
#include <type_traits>
#include <utility>
#include <variant>

namespace rangekit {

enum class Errc {
  invalid_frame,      // bytes that are not a frame of the protocol
  truncated,          // frame ended before a required field
  overlong,           // frame or field longer than the protocol allows
  bad_hex,            // a hex field holds a non-hex character
  bad_number,         // a decimal field does not parse
  bad_checksum,       // checksum of a packet does not match
  unknown_command,    // mnemonic not in the command table
  unknown_parameter,  // parameter address not in the parameter table
  out_of_range,       // value outside the range the document allows
  wrong_form,         // e.g. a set for a get-only command
  device_error,       // the device answered with an error number
  timeout,            // no answer in time
  io,                 // operating-system I/O failure
  closed,             // the other end went away
  unsupported,        // feature not available (firmware version, platform)
  limit,              // a bound of this program reached (running captures, free disk): end something first
};

const char* errc_name(Errc code) noexcept;

struct Error {
  Errc code;
  std::string message;
  int device_code = 0;  // protocol error number for Errc::device_error

  [[nodiscard]] std::string describe() const;
};

Error make_error(Errc code, std::string message);

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::in_place_index<0>, std::move(value)) {}      // NOLINT: implicit by design
  Result(Error error) : state_(std::in_place_index<1>, std::move(error)) {}  // NOLINT: implicit by design

  [[nodiscard]] bool ok() const noexcept { return state_.index() == 0; }
  explicit operator bool() const noexcept { return ok(); }

  T& value() & { return std::get<0>(state_); }
  const T& value() const& { return std::get<0>(state_); }
  T&& value() && { return std::get<0>(std::move(state_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

  const Error& error() const& { return std::get<1>(state_); }
  Error&& error() && { return std::get<1>(std::move(state_)); }

  template <class U>
  T value_or(U&& fallback) const& {
    return ok() ? value() : static_cast<T>(std::forward<U>(fallback));
  }

 private:
  std::variant<T, Error> state_;
};

// Result of an operation that yields nothing but may fail.
struct Ok {};
using Status = Result<Ok>;
inline Status ok_status() { return Ok{}; }

}  // namespace rangekit
