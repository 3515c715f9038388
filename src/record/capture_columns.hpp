// The `samples` table's columns: seq, session, time_ns, device, source, address and kind, then
// each registered family's channel columns (core/channel.hpp, registration order, a name two
// families share once), then suspect and suspect_reason. Old captures' columns keep their names.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/family.hpp"
#include "targets_text.hpp"

namespace rangekit::record {

struct ChannelColumn {
  std::string_view name;
  ColumnType type = ColumnType::real;
  bool in_stream = true;  // some family's channel in it is shown in the stream (core/channel.hpp)
};

// Where a family's channels are kept: for each channel, its place among the channel columns.
struct FamilyColumns {
  const FamilyDescriptor* family = nullptr;
  std::vector<std::optional<std::size_t>> column_of_channel;
};

struct CaptureLayout {
  std::vector<ChannelColumn> channels;
  std::vector<FamilyColumns> families;
  // "samples(\n  seq INTEGER PRIMARY KEY, …)": what sqlite_schema keeps after "CREATE TABLE ".
  std::string table_definition;
  // The places of the columns after the channel columns.
  [[nodiscard]] std::size_t suspect_column() const { return first_channel_column + channels.size(); }
  [[nodiscard]] std::size_t suspect_reason_column() const { return suspect_column() + 1; }
  [[nodiscard]] std::size_t column_count() const { return suspect_column() + 2; }
  // The family's columns, none for a family not registered.
  [[nodiscard]] const FamilyColumns* columns_of(std::string_view family) const;

  static constexpr std::size_t first_channel_column = 7;  // after seq … kind
};

// Built from the registered families on first use.
const CaptureLayout& capture_layout();

const char* sql_type(ColumnType type) noexcept;

// Fills the sample's channels (values and targets) from a row. `Row` reads a column by its
// place: is_null(i), integer(i) -> optional<int64>, real(i) -> optional<double>, text(i).
// `first` is the place of the first channel column in the row. `skip` leaves out channels
// not shown in the stream (an array read).
template <class Row>
void read_channels(Row& row, std::size_t first, const FamilyColumns& columns, Sample& sample, bool skip_hidden) {
  sample.values.clear();
  sample.targets.clear();
  const FamilyDescriptor& family = *columns.family;
  const std::vector<ChannelColumn>& layout = capture_layout().channels;
  for (std::size_t index = 0; index < family.channels.size(); ++index) {
    const auto column = columns.column_of_channel[index];
    const ChannelDescriptor& channel = family.channels[index];
    if (!column || (skip_hidden && !channel.in_stream)) continue;
    const std::size_t at = first + *column;
    if (row.is_null(at)) continue;
    switch (channel.form) {
      case ChannelForm::targets:
        parse_targets_text(row.text(at), sample.targets);
        break;
      case ChannelForm::state: {
        const std::string_view name = row.text(at);
        for (std::size_t state = 0; state < channel.states.size(); ++state) {
          if (channel.states[state] == name) sample.values.set(index, static_cast<double>(state));
        }
        break;
      }
      case ChannelForm::flag:
        if (const auto value = row.integer(at)) sample.values.set(index, *value != 0 ? 1.0 : 0.0);
        break;
      case ChannelForm::number:
        if (layout[*column].type == ColumnType::integer) {
          if (const auto value = row.integer(at)) {
            sample.values.set(index, static_cast<double>(*value) / channel.capture.scale);
          }
        } else if (const auto value = row.real(at)) {
          sample.values.set(index, *value);
        }
        break;
    }
  }
  if (family.read_back != nullptr) family.read_back(sample);
}

}  // namespace rangekit::record
