// Names back to enums for the capture columns written with the *_name()
// functions of core/sample.hpp (a sample's kind and states: its family's names).
#pragma once

#include <optional>
#include <string_view>

#include "rangekit/core/sample.hpp"

namespace rangekit::record {

std::optional<StreamEventKind> parse_stream_event_kind(std::string_view name);

}  // namespace rangekit::record
