#include "names.hpp"

#include <array>
#include <utility>

namespace rangekit::record {
namespace {

// Each value with its name as a string_view, built once: a capture's reader parses a
// name on every row, and should not measure the names (strlen) every time.
template <class Enum, std::size_t N>
using NameTable = std::array<std::pair<Enum, std::string_view>, N>;

template <class Enum, std::size_t N, class NameOf>
NameTable<Enum, N> name_table(const std::array<Enum, N>& values, NameOf name_of) {
  NameTable<Enum, N> table{};
  for (std::size_t i = 0; i < N; ++i) table[i] = {values[i], name_of(values[i])};
  return table;
}

template <class Enum, std::size_t N>
std::optional<Enum> find_by_name(std::string_view name, const NameTable<Enum, N>& table) {
  for (const auto& [value, value_name] : table) {
    if (name == value_name) return value;
  }
  return std::nullopt;
}

}  // namespace

std::optional<StreamEventKind> parse_stream_event_kind(std::string_view name) {
  static const auto table =
      name_table(std::array{StreamEventKind::connected, StreamEventKind::disconnected, StreamEventKind::reconnected,
                            StreamEventKind::bad_frame, StreamEventKind::lost_records, StreamEventKind::device_error,
                            StreamEventKind::polling},
                 stream_event_kind_name);
  return find_by_name(name, table);
}

}  // namespace rangekit::record
