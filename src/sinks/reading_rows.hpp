// Hub items to spool rows: a sample's one reading (reading_of) as a line, numbered by the
// spool's sequence of its sensor, at most max_rate_hz a second per sensor.
#pragma once

#include <chrono>
#include <map>
#include <optional>
#include <string>

#include "rangekit/hub/fanout.hpp"
#include "rangekit/record/spool.hpp"

namespace rangekit::sinks {

using record::Spool;
using record::SpoolRow;
using record::SpoolStats;

class ReadingRows {
 public:
  explicit ReadingRows(double max_rate_hz) : max_rate_hz_(max_rate_hz) {}
  // The row of an item, or none: an event, a sample without a reading (a gap), or one within
  // 1/max_rate_hz of the last row of its sensor. Takes a sequence from the spool only for a row.
  std::optional<SpoolRow> row_of(const hub::HubItem& item, Spool& spool);
  [[nodiscard]] std::uint64_t skipped() const noexcept { return skipped_; }

 private:
  double max_rate_hz_;
  std::map<std::string, std::chrono::system_clock::time_point, std::less<>> last_;  // per sensor
  std::uint64_t skipped_ = 0;
};

}  // namespace rangekit::sinks
