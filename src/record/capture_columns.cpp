#include "capture_columns.hpp"

#include <algorithm>

namespace rangekit::record {
namespace {

CaptureLayout make_layout() {
  CaptureLayout layout;
  for (const FamilyDescriptor* family : families()) {
    FamilyColumns columns{family, {}};
    for (const ChannelDescriptor& channel : family->channels) {
      if (channel.capture.name.empty()) {
        columns.column_of_channel.emplace_back();
        continue;
      }
      const auto found = std::find_if(layout.channels.begin(), layout.channels.end(),
                                      [&](const ChannelColumn& column) { return column.name == channel.capture.name; });
      const auto place = static_cast<std::size_t>(found - layout.channels.begin());
      columns.column_of_channel.emplace_back(place);
      if (found == layout.channels.end()) {
        layout.channels.push_back({channel.capture.name, channel.capture.type, channel.in_stream});
      } else if (channel.in_stream) {
        layout.channels[place].in_stream = true;
      }
    }
    layout.families.push_back(std::move(columns));
  }
  layout.table_definition =
      "samples(\n  seq INTEGER PRIMARY KEY,\n  session INTEGER NOT NULL,\n  time_ns INTEGER NOT NULL,\n"
      "  device TEXT NOT NULL,\n  source TEXT NOT NULL,\n  address INTEGER,\n  kind TEXT NOT NULL,\n";
  for (const ChannelColumn& column : layout.channels) {
    layout.table_definition += "  " + std::string(column.name) + " " + sql_type(column.type) + ",\n";
  }
  layout.table_definition += "  suspect INTEGER,\n  suspect_reason TEXT)";
  return layout;
}

}  // namespace

const FamilyColumns* CaptureLayout::columns_of(std::string_view family) const {
  for (const FamilyColumns& columns : families) {
    if (columns.family->name == family) return &columns;
  }
  return nullptr;
}

const CaptureLayout& capture_layout() {
  static const CaptureLayout layout = make_layout();
  return layout;
}

const char* sql_type(ColumnType type) noexcept {
  switch (type) {
    case ColumnType::real:
      return "REAL";
    case ColumnType::integer:
      return "INTEGER";
    case ColumnType::text:
      return "TEXT";
  }
  return "BLOB";
}

}  // namespace rangekit::record
