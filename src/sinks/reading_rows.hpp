// Hub items to spool rows: a sample's one reading (reading_of), numbered by the spool's
// sequence of its sensor; with max_rate_hz, one row per 1/max_rate_hz window of a sensor,
// with the window's count, min, max and last (as the SSE aggregates).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "rangekit/core/reading_stats.hpp"
#include "rangekit/hub/fanout.hpp"
#include "rangekit/record/spool.hpp"
#include "rangekit/sinks/sink_reading.hpp"

namespace rangekit::sinks {

using record::Spool;
using record::SpoolRow;
using record::SpoolStats;

class ReadingRows {
 public:
  ReadingRows(double max_rate_hz, RowEncoder encode) : max_rate_hz_(max_rate_hz), encode_(encode) {}
  // Appends the item's row: its reading, or the window its sample closes. An event or a sample
  // without a reading (a gap) makes none. Takes a sequence from the spool only for a row.
  void add(const hub::HubItem& item, Spool& spool, std::vector<SpoolRow>& out);
  // Writes the windows that ended a whole period or more before `now`, so a sensor gone quiet still
  // has its last window written; `close_all` writes every open one (at stop).
  void close_windows(std::chrono::system_clock::time_point now, Spool& spool, std::vector<SpoolRow>& out);
  void close_all(Spool& spool, std::vector<SpoolRow>& out);
  // Samples without a reading, since the start.
  [[nodiscard]] std::uint64_t skipped() const noexcept { return skipped_; }

 private:
  struct Window {
    std::int64_t slot = 0;    // which 1/max_rate_hz slot of the system clock
    ReadingStats good;        // the readings not marked suspect
    Sample last_good;         // the last of them
    std::size_t suspect = 0;  // readings marked suspect: out of count, min, max and last
    Sample last_suspect;      // written alone when the window has no other reading
  };
  [[nodiscard]] std::int64_t slot_of(std::chrono::system_clock::time_point time) const;
  void write(const std::string& sensor, const Sample& sample, const SinkReading& figures, Spool& spool,
             std::vector<SpoolRow>& out);
  void close(const std::string& sensor, Window& window, Spool& spool, std::vector<SpoolRow>& out);

  double max_rate_hz_;
  RowEncoder encode_;
  std::map<std::string, Window, std::less<>> windows_;  // per sensor, while open
  std::uint64_t skipped_ = 0;
};

}  // namespace rangekit::sinks
