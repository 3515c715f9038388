// Names back to enums for the capture columns written with the *_name()
// functions of core/sample.hpp.
#pragma once

#include <optional>
#include <string_view>

#include "rangekit/core/sample.hpp"

namespace rangekit::record {

std::optional<SampleKind> parse_sample_kind(std::string_view name);
std::optional<SignalState> parse_signal_state(std::string_view name);
std::optional<StreamEventKind> parse_stream_event_kind(std::string_view name);

}  // namespace rangekit::record
