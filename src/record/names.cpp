#include "names.hpp"

#include <array>

namespace rangekit::record {
namespace {

template <class Enum, std::size_t N, class NameOf>
std::optional<Enum> find_by_name(std::string_view name, const std::array<Enum, N>& values, NameOf name_of) {
  for (const auto value : values) {
    if (name == name_of(value)) return value;
  }
  return std::nullopt;
}

}  // namespace

std::optional<SampleKind> parse_sample_kind(std::string_view name) {
  constexpr std::array values{SampleKind::uls_averaging, SampleKind::uls_binning, SampleKind::uls_look_down,
                              SampleKind::uls_error,     SampleKind::ls5_result,  SampleKind::ls5_derivative};
  return find_by_name(name, values, sample_kind_name);
}

std::optional<SignalState> parse_signal_state(std::string_view name) {
  constexpr std::array values{SignalState::ok, SignalState::none_yet, SignalState::lost};
  return find_by_name(name, values, signal_state_name);
}

std::optional<StreamEventKind> parse_stream_event_kind(std::string_view name) {
  constexpr std::array values{StreamEventKind::connected, StreamEventKind::disconnected, StreamEventKind::reconnected,
                              StreamEventKind::bad_frame, StreamEventKind::lost_records, StreamEventKind::device_error,
                              StreamEventKind::polling};
  return find_by_name(name, values, stream_event_kind_name);
}

}  // namespace rangekit::record
