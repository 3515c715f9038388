#include "sinks/reading_rows.hpp"

#include <variant>

#include "rangekit/core/family.hpp"
#include "rangekit/sinks/line_protocol.hpp"

namespace rangekit::sinks {

std::optional<SpoolRow> ReadingRows::row_of(const hub::HubItem& item, Spool& spool) {
  const auto* sample = std::get_if<Sample>(&item.item);
  if (sample == nullptr) return std::nullopt;
  const auto reading = reading_of(*sample);
  if (!reading) {
    ++skipped_;
    return std::nullopt;
  }
  if (max_rate_hz_ > 0) {
    // Thinned, not aggregated: the first reading of each 1/rate period of its sensor.
    const auto period = std::chrono::duration_cast<std::chrono::system_clock::duration>(
        std::chrono::duration<double>(1.0 / max_rate_hz_));
    auto [last, first] = last_.try_emplace(item.sensor, sample->time);
    if (!first) {
      if (sample->time - last->second < period) {
        ++skipped_;
        return std::nullopt;
      }
      last->second = sample->time;
    }
  }
  SpoolRow row;
  row.sensor = item.sensor;
  row.seq = spool.next_seq(item.sensor);
  row.time_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(sample->time.time_since_epoch()).count();
  LineReading line;
  line.sensor = item.sensor;
  line.family = sample->device;
  line.unit = reading->channel != nullptr ? unit_symbol(reading->channel->unit) : "";
  line.value = reading->value;
  line.suspect = sample->suspect;
  line.seq = row.seq;
  line.time_ns = row.time_ns;
  row.line = encode_line(line);
  return row;
}

}  // namespace rangekit::sinks
