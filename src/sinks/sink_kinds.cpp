// The one table of sink kinds: [[sink]] kind names one of these rows.
#include <array>

#include "rangekit/sinks/line_protocol.hpp"
#include "sinks/copy_text.hpp"
#include "sinks/influx_writer.hpp"
#include "sinks/postgres_writer.hpp"
#include "sinks/writer.hpp"

namespace rangekit::sinks {
namespace {

const std::array kinds{
    SinkKind{"influx", encode_line, open_influx_writer},
    SinkKind{"postgres", encode_copy_row, open_postgres_writer},
};

}  // namespace

const SinkKind* find_sink_kind(std::string_view name) {
  for (const SinkKind& kind : kinds) {
    if (kind.name == name) return &kind;
  }
  return nullptr;
}

std::string sink_kind_names() {
  std::string names;
  for (const SinkKind& kind : kinds) names += (names.empty() ? "" : ", ") + std::string(kind.name);
  return names;
}

}  // namespace rangekit::sinks
