// The Modbus face's register map: one table that the face fills, `serve --modbus-map` prints
// and docs/modbus.md lists, so what a PLC engineer imports is what the face answers.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rangekit::modbus {

// How a 32-bit value lies in two registers: A is its most significant byte. ABCD is the
// Modbus habit (big-endian words, high word first); the others are what some PLCs expect.
enum class WordOrder : std::uint8_t { abcd, cdab, badc, dcba };
std::optional<WordOrder> parse_word_order(std::string_view text);  // "ABCD", "cdab", ...
std::string_view word_order_name(WordOrder order) noexcept;        // "ABCD"

enum class RegisterType : std::uint8_t { float32, int32, uint32, uint16, bits16 };
std::string_view register_type_name(RegisterType type) noexcept;  // "float32"
constexpr std::size_t words_of(RegisterType type) noexcept {
  return type == RegisterType::uint16 || type == RegisterType::bits16 ? 1 : 2;
}

struct RegisterRow {
  std::uint16_t address = 0;  // zero-based, as on the wire (mbpoll -0, or 30001 + address in 1-based tags)
  RegisterType type = RegisterType::uint16;
  std::string_view name;  // snake_case tag name
  std::string_view unit;  // "mm", "um", "ms", or empty
  std::string_view description;
};

// The named input registers (function 04) of one unit. Targets repeat: target_count at 16,
// then target i's float32 at 17 + 2i.
namespace input {
inline constexpr std::uint16_t reading_mm = 0;
inline constexpr std::uint16_t reading_um = 2;
inline constexpr std::uint16_t status = 4;
inline constexpr std::uint16_t device_error = 5;
inline constexpr std::uint16_t sequence = 6;
inline constexpr std::uint16_t age_ms = 8;
inline constexpr std::uint16_t records = 9;
inline constexpr std::uint16_t errors = 11;
inline constexpr std::uint16_t lost = 13;
inline constexpr std::uint16_t target_count = 16;
inline constexpr std::uint16_t first_target_mm = 17;
inline constexpr std::size_t max_targets = 15;                           // the ULS's binning limit (§3, §9)
inline constexpr std::size_t count = first_target_mm + 2 * max_targets;  // 47 registers: 0-46
}  // namespace input

// Bits of input register 4.
namespace status_bit {
inline constexpr unsigned connected = 0;
inline constexpr unsigned streaming = 1;
inline constexpr unsigned valid = 2;  // the reading has a value and no device error
inline constexpr unsigned suspect = 3;
inline constexpr unsigned stale = 4;  // no new reading in time (docs/modbus.md)
inline constexpr unsigned no_target = 5;
}  // namespace status_bit

// The holding registers (03, 06, 16), when the site file allows writes.
namespace holding {
inline constexpr std::uint16_t command = 0;        // write a command code; reads back the last one written
inline constexpr std::uint16_t command_state = 1;  // CommandState
inline constexpr std::uint16_t command_done = 2;   // commands finished, rising by one each (wraps)
inline constexpr std::size_t count = 3;
}  // namespace holding

enum class CommandState : std::uint16_t { idle = 0, running = 1, done = 2, failed = 3 };

// A command code and the action it asks of the sensor, with its argument.
struct CommandCode {
  std::uint16_t code = 0;
  std::string_view action;
  std::string_view argument;
  std::string_view description;
};
std::span<const CommandCode> command_codes() noexcept;
const CommandCode* find_command_code(std::uint16_t code) noexcept;

// Every named register, input then holding, in address order.
std::span<const RegisterRow> input_rows() noexcept;
std::span<const RegisterRow> holding_rows() noexcept;

// The 32-bit value's two registers in `order`.
std::array<std::uint16_t, 2> words_of_u32(std::uint32_t value, WordOrder order) noexcept;
std::uint32_t u32_of_words(std::uint16_t first, std::uint16_t second, WordOrder order) noexcept;

// The map as CSV, one row per register of every unit (unit id, sensor): "unit,sensor,table,
// register,type,name,unit_of_measure,word_order,description". Holding rows only when writable.
std::string write_register_map(std::span<const std::pair<std::uint8_t, std::string>> units, WordOrder order,
                               bool writable);

}  // namespace rangekit::modbus
