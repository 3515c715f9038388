// One row a sink writes, whatever the historian: a sensor's one reading (core::reading_of),
// or the figures of a 1/max_rate_hz window of them. A sink kind turns it into its own text.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "rangekit/core/sample.hpp"

namespace rangekit::sinks {

struct SinkReading {
  std::string_view sensor;
  std::string_view family;
  std::string_view unit;  // "m", "mm"; empty when the reading's channel has none
  double value = 0;       // the reading; of a window, its last
  bool suspect = false;   // of a window: every reading in it was suspect
  std::uint64_t seq = 0;  // the sensor's own sequence, one per row
  std::int64_t time_ns = 0;
  // A window's figures (max_rate_hz > 0): how many readings, their least and greatest.
  // count 0: a single reading, written as it came.
  std::size_t count = 0;
  double min = 0;
  double max = 0;
  const Sample* sample = nullptr;  // the reading's sample (of a window, its last), for kinds that keep it whole
};

// How a sink kind writes a row into its spool: the exact text it later sends (a line of
// Influx line protocol, a row of COPY text).
using RowEncoder = std::string (*)(const SinkReading& reading);

}  // namespace rangekit::sinks
