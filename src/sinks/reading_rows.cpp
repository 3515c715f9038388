#include "sinks/reading_rows.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include "rangekit/core/family.hpp"

namespace rangekit::sinks {

std::int64_t ReadingRows::slot_of(std::chrono::system_clock::time_point time) const {
  // In whole nanoseconds, so a reading on a window's edge falls in the same one every time.
  const auto period_ns = std::max<std::int64_t>(1, std::llround(1e9 / max_rate_hz_));
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count();
  return ns / period_ns - (ns % period_ns < 0 ? 1 : 0);
}

void ReadingRows::write(const std::string& sensor, const Sample& sample, const SinkReading& figures, Spool& spool,
                        std::vector<SpoolRow>& out) {
  SinkReading reading = figures;
  reading.sensor = sensor;
  reading.family = sample.device;
  reading.sample = &sample;
  reading.seq = spool.next_seq(sensor);
  reading.time_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(sample.time.time_since_epoch()).count();
  SpoolRow row;
  row.sensor = sensor;
  row.seq = reading.seq;
  row.time_ns = reading.time_ns;
  row.line = encode_(reading);
  out.push_back(std::move(row));
}

void ReadingRows::add(const hub::HubItem& item, Spool& spool, std::vector<SpoolRow>& out) {
  const auto* sample = std::get_if<Sample>(&item.item);
  if (sample == nullptr) return;
  const auto reading = reading_of(*sample);
  if (!reading) {
    ++skipped_;
    return;
  }
  if (max_rate_hz_ <= 0) {
    SinkReading figures;
    figures.unit = reading->channel != nullptr ? unit_symbol(reading->channel->unit) : "";
    figures.value = reading->value;
    figures.suspect = sample->suspect;
    write(item.sensor, *sample, figures, spool, out);
    return;
  }
  const std::int64_t slot = slot_of(sample->time);
  auto [found, opened] = windows_.try_emplace(item.sensor);
  Window& window = found->second;
  if (!opened && window.slot != slot) {
    close(found->first, window, spool, out);
    window = Window{};
  }
  window.slot = slot;
  if (sample->suspect) {
    ++window.suspect;
    window.last_suspect = *sample;
  } else {
    window.good.add(*reading);
    window.last_good = *sample;
  }
}

void ReadingRows::close(const std::string& sensor, Window& window, Spool& spool, std::vector<SpoolRow>& out) {
  if (!window.good.empty()) {
    SinkReading figures;
    figures.unit = window.good.unit();
    figures.value = window.good.last();
    figures.count = window.good.count();
    figures.min = window.good.min();
    figures.max = window.good.max();
    write(sensor, window.last_good, figures, spool, out);
  } else if (window.suspect > 0) {
    // Only suspect readings: the last, marked, so the window is not silently missing.
    const auto reading = reading_of(window.last_suspect);
    SinkReading figures;
    figures.unit = reading && reading->channel != nullptr ? unit_symbol(reading->channel->unit) : "";
    figures.value = reading ? reading->value : 0;
    figures.suspect = true;
    write(sensor, window.last_suspect, figures, spool, out);
  }
}

void ReadingRows::close_windows(std::chrono::system_clock::time_point now, Spool& spool, std::vector<SpoolRow>& out) {
  const std::int64_t current = slot_of(now);
  for (auto it = windows_.begin(); it != windows_.end();) {
    if (it->second.slot + 1 < current) {
      close(it->first, it->second, spool, out);
      it = windows_.erase(it);
    } else {
      ++it;
    }
  }
}

void ReadingRows::close_all(Spool& spool, std::vector<SpoolRow>& out) {
  for (auto& [sensor, window] : windows_) close(sensor, window, spool, out);
  windows_.clear();
}

}  // namespace rangekit::sinks
