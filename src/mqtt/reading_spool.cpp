#include "mqtt/reading_spool.hpp"

#include <array>
#include <cctype>
#include <cstdio>

namespace rangekit::mqtt {

Result<std::unique_ptr<ReadingSpool>> ReadingSpool::open(const std::string& path, std::uint64_t max_bytes,
                                                         std::string sensor) {
  auto spool = record::Spool::open(path, max_bytes);
  if (!spool) return std::move(spool).error();
  return std::unique_ptr<ReadingSpool>(new ReadingSpool(std::move(*spool), std::move(sensor)));
}

Result<std::uint64_t> ReadingSpool::store(const std::vector<std::string>& readings,
                                          std::chrono::system_clock::time_point now) {
  std::vector<record::SpoolRow> rows;
  rows.reserve(readings.size());
  const auto time_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now.time_since_epoch()).count();
  for (const std::string& reading : readings) {
    record::SpoolRow row;
    row.sensor = sensor_;
    row.seq = spool_->next_seq(sensor_);
    row.time_ns = time_ns;
    const bool object = reading.size() >= 2 && reading.front() == '{';
    row.line = "{\"seq\":" + std::to_string(row.seq);
    if (object) {
      if (reading[1] != '}') row.line += ',';
      row.line.append(reading, 1);
    } else {
      row.line += ",\"reading\":" + reading + "}";  // never made by the bridge; kept whole if ever
    }
    rows.push_back(std::move(row));
  }
  maybe_unsent_ = true;
  return spool_->append(rows);
}

Result<std::vector<record::SpoolRow>> ReadingSpool::next(std::size_t room) {
  // Nothing new stored, and every row handed out went: no query.
  if (room == 0 || (!maybe_unsent_ && last_sent_ >= handed_out_)) return std::vector<record::SpoolRow>{};
  auto rows = spool_->oldest(room, last_sent_);
  if (!rows) return rows;
  if (!rows->empty()) handed_out_ = rows->back().id;
  maybe_unsent_ = rows->size() == room;  // a full answer: more may wait behind it
  return rows;
}

void ReadingSpool::sent(int mid, std::int64_t id) {
  last_sent_ = std::max(last_sent_, id);
  in_flight_[id] = false;
  mids_[mid] = id;
}

void ReadingSpool::acknowledged(int mid) {
  const auto found = mids_.find(mid);
  if (found == mids_.end()) return;  // of a session before resend_in_flight: sent again since
  if (auto row = in_flight_.find(found->second); row != in_flight_.end()) row->second = true;
  mids_.erase(found);
}

void ReadingSpool::give_up(std::int64_t id) {
  last_sent_ = std::max(last_sent_, id);
  in_flight_[id] = true;
}

Status ReadingSpool::forget_acknowledged() {
  std::int64_t through = 0;
  while (!in_flight_.empty() && in_flight_.begin()->second) {
    through = in_flight_.begin()->first;
    in_flight_.erase(in_flight_.begin());
  }
  if (through == 0) return ok_status();
  return spool_->remove_through(through);
}

void ReadingSpool::resend_in_flight() {
  // The acknowledged prefix may still be on disk: forget_acknowledged() runs before this.
  std::int64_t before = last_sent_;
  for (const auto& [id, acked] : in_flight_) {
    if (!acked) {
      before = id - 1;
      break;
    }
  }
  // Rows after the first unacknowledged one go again, acknowledged ones among them too (a
  // seq heard twice): the spool forgets in order only.
  for (auto it = in_flight_.begin(); it != in_flight_.end();)
    it = it->first > before ? in_flight_.erase(it) : std::next(it);
  mids_.clear();
  last_sent_ = before;
  maybe_unsent_ = true;
}

std::string reading_spool_name(const std::string& client_id, const std::string& sensor) {
  const std::string both = client_id + "-" + sensor;
  std::string name = "mqtt-";
  bool changed = false;
  for (const char c : both) {
    const bool plain = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '.';
    name += plain ? c : '_';
    changed = changed || !plain;
  }
  if (changed) {
    // "bay A" and "bay_A" are two sensors: a changed name gets its own FNV-1a hash, so they get two files.
    std::uint32_t hash = 2166136261U;
    for (const char c : both) hash = (hash ^ static_cast<unsigned char>(c)) * 16777619U;
    std::array<char, 9> hex{};
    std::snprintf(hex.data(), hex.size(), "%08x", hash);
    name += std::string("-") + hex.data();
  }
  return name + ".spool";
}

}  // namespace rangekit::mqtt
