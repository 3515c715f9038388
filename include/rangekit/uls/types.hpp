// Typed values of the ULS protocol (ULS §8). Numbers are the wire values.
#pragma once

#include <cstdint>
#include <optional>

namespace rangekit::uls {

// §8 Set/Get Measurement Mode; numbers lost in OCR, decided in U7.
enum class Mode : std::uint8_t { averaging = 1, binning = 2, look_down = 3 };

// §8 Set/Get Display Mode in Averaging.
enum class DisplayMode : std::uint8_t { range = 1, range_and_intensity = 2, intensity = 3 };

// §8 Set/Get Measurement Units.
enum class Units : std::uint8_t { feet = 0, metres = 1 };

// §8 Set/Get Power Level.
enum class PowerLevel : std::uint8_t { high = 0, medium = 1, low = 2 };

// §8 Set/Get Measurement Output Port.
enum class OutputPort : std::uint8_t { configuration = 0, universal_rs232 = 1, universal_rs485 = 2 };

// §8 Set/Get Baud Rate, argument p.
enum class BaudPort : std::uint8_t { configuration = 0, output = 1 };

// §8 Set/Get Bin Size: n selects 2^n inches.
enum class BinSize : std::uint8_t {
  inch_1 = 0,
  inches_2,
  inches_4,
  inches_8,
  inches_16,
  inches_32,
  inches_64,
  inches_128,
  inches_256
};

// §8 Get Unit Status: the reply is a sum of these bits (U6).
namespace status_bit {
inline constexpr std::uint8_t active = 0x01;
inline constexpr std::uint8_t laser_firing = 0x02;
inline constexpr std::uint8_t averaging_calc = 0x04;
inline constexpr std::uint8_t binning_calc = 0x08;
}  // namespace status_bit

// The five values §8 lists for US (U6).
enum class UnitStatus : std::uint8_t {
  error = 0,                                                                               // failed to initialise
  ready = status_bit::active,                                                              // 1: not measuring
  look_down = status_bit::active | status_bit::laser_firing,                               // 3
  averaging = status_bit::active | status_bit::laser_firing | status_bit::averaging_calc,  // 7
  binning = status_bit::active | status_bit::laser_firing | status_bit::binning_calc,      // 11
};

std::optional<Mode> to_mode(std::uint64_t number) noexcept;
std::optional<DisplayMode> to_display_mode(std::uint64_t number) noexcept;
std::optional<Units> to_units(std::uint64_t number) noexcept;
std::optional<PowerLevel> to_power_level(std::uint64_t number) noexcept;
std::optional<OutputPort> to_output_port(std::uint64_t number) noexcept;
std::optional<BaudPort> to_baud_port(std::uint64_t number) noexcept;
std::optional<BinSize> to_bin_size(std::uint64_t number) noexcept;
std::optional<UnitStatus> to_unit_status(std::uint64_t number) noexcept;

// The mode a status value reports while firing; none for error and ready.
std::optional<Mode> status_mode(UnitStatus status) noexcept;
constexpr bool status_firing(UnitStatus status) noexcept {
  return (static_cast<std::uint8_t>(status) & status_bit::laser_firing) != 0;
}
// The status a unit reports while measuring in `mode` (or ready when idle).
UnitStatus status_for(bool measuring, Mode mode) noexcept;

template <class Enum>
constexpr std::uint8_t wire_value(Enum value) noexcept {
  return static_cast<std::uint8_t>(value);
}

// §8 RS485 Protocol (U4): where a '#' frame's address byte falls.
inline constexpr std::uint8_t first_unit_address = 0x30;
inline constexpr std::uint8_t last_unit_address = 0xEF;
inline constexpr std::uint8_t first_broadcast_address = 0xF0;

// Who a frame is for (commands) or from (replies): '$' frames have no address.
struct Address {
  bool addressed = false;
  std::uint8_t byte = 0;

  static constexpr Address none() noexcept { return {}; }
  static constexpr Address unit(std::uint8_t address) noexcept { return {true, address}; }
  static constexpr Address broadcast(std::uint8_t address = first_broadcast_address) noexcept {
    return {true, address};
  }
  [[nodiscard]] constexpr bool is_broadcast() const noexcept { return addressed && byte >= first_broadcast_address; }
  [[nodiscard]] constexpr bool is_unit() const noexcept {
    return addressed && byte >= first_unit_address && byte <= last_unit_address;
  }
  friend constexpr bool operator==(Address, Address) noexcept = default;
};

// A time-between-events report (§3, §8, U12): `$0`, `$XXXX`, or `$0000` for overflow.
struct TimeBetweenEvents {
  enum class Kind { no_presence, pulses, overflow } kind = Kind::no_presence;
  std::uint16_t pulses = 0;  // kind == pulses: 1..65535
  friend constexpr bool operator==(const TimeBetweenEvents&, const TimeBetweenEvents&) noexcept = default;
};

}  // namespace rangekit::uls
