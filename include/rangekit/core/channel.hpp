// What a number in a sample means: its quantity, its unit and the key every face shows it by.
// A family describes its channels once (its family descriptor); faces read the description
// and never ask which family a sample came from.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace rangekit {

enum class Quantity : std::uint8_t {
  distance,         // along the beam, to a target
  distance_change,  // the difference of two distances (an LS5 derivative)
  pulse_width,      // of the returned laser pulse
  strength,         // hits of a target's bin, a signal level
  presence,         // 1 when a target is there, 0 when not
  pulse_count,      // laser pulses between two events
  result_code,      // the raw number the sensor sent
  error_number,     // the sensor's own error number
  signal,           // whether the sensor sees a target: 0 it does, its last state it sees none,
                    // the states between why there is no value yet
  overflow,         // 1 when a count went beyond what the sensor can send
  resolution,       // one step of the sensor's values where this sample was read
};

enum class Unit : std::uint8_t { none, metre, millimetre, nanosecond };

// "distance", "distance_change", …: the words of docs and JSON.
const char* quantity_name(Quantity quantity) noexcept;
// "m", "mm", "ns"; "" for a count or a state.
const char* unit_symbol(Unit unit) noexcept;
// The factor from `unit` to the metre, for the length units only.
std::optional<double> metres_per(Unit unit) noexcept;

// How a channel's value is written: a number, true/false, the name of a state, or the
// sample's targets (a list of distance and strength).
enum class ChannelForm : std::uint8_t { number, flag, state, targets };

// How a channel is kept in a capture's samples table (record/capture.hpp).
enum class ColumnType : std::uint8_t { real, integer, text };
struct CaptureColumn {
  std::string_view name;  // "distance_m"; channels of two families with one name share it
  ColumnType type = ColumnType::real;
  // An integer column holds value × scale (a pulse width in ns kept as the wire's ps).
  double scale = 1;
};

struct ChannelDescriptor {
  std::string_view key;  // the JSON and CSV key: "distance_m"
  Quantity quantity = Quantity::distance;
  Unit unit = Unit::none;
  std::string_view description;  // one line for help and the API's descriptors
  ChannelForm form = ChannelForm::number;
  // Decimals a number is written with; 0 for a count.
  int decimals = 0;
  // A channel of the same family holding this one's step (LS5's discreteness): when a sample
  // has it, its decimals replace `decimals`. -1 for none.
  int step_channel = -1;
  // The names of a state's values, 0 first ("ok", "none_yet", "lost").
  std::span<const std::string_view> states = {};
  CaptureColumn capture;
  // False: kept in captures and used by the family, but not a column of CSV or JSON lines.
  bool in_stream = true;
  // The value an absent channel has in a line of a kind that lists it (a flag false unless set);
  // none: written as null.
  std::optional<double> otherwise = std::nullopt;
};

// The one number a sample reports, with the channel that gives it its meaning: what the
// dashboard plots, MQTT publishes, an SSE aggregate and Python's NumPy arrays count.
struct Reading {
  const ChannelDescriptor* channel = nullptr;
  double value = 0;
  // The decimals the value deserves (the sensor's discreteness, as the stream prints it);
  // -1 when not known. A mean of such values is rounded to them.
  int decimals = -1;
};

// The decimals a step needs: 0.0001 -> 4, 0.1 -> 1, 5 -> 0; -1 for no step (0, NaN).
int decimals_of_step(double step) noexcept;
// `value` rounded to `decimals` (unchanged for -1), so that it prints as 15.7188, not
// 15.718792959999998.
double rounded_to(double value, int decimals) noexcept;

}  // namespace rangekit
