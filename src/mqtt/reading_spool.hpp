// One sensor's store-and-forward for QoS >= 1 readings ([mqtt] spool): each reading is on
// disk before it is published, and leaves only when the broker acknowledged it (PUBACK, or
// PUBCOMP for QoS 2), in order. A reading carries its sensor's seq so a subscriber can tell a
// replay after a reconnect or a restart from a new reading.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/record/spool.hpp"

namespace rangekit::mqtt {

class ReadingSpool {
 public:
  static Result<std::unique_ptr<ReadingSpool>> open(const std::string& path, std::uint64_t max_bytes,
                                                    std::string sensor);

  // Stores the readings (JSON objects) in one transaction, each with the sensor's next seq
  // as its first member. Returns how many of the oldest went past the cap.
  Result<std::uint64_t> store(const std::vector<std::string>& readings, std::chrono::system_clock::time_point now);
  // The readings to publish next, after those in flight: at most `room` of them.
  Result<std::vector<record::SpoolRow>> next(std::size_t room);
  // The row went out as message `mid`; `acknowledged(mid)` when the broker confirmed it.
  void sent(int mid, std::int64_t id);
  void acknowledged(int mid);
  // A row that can never be published (too large for the broker): it leaves as if acknowledged.
  void give_up(std::int64_t id);
  // Removes from disk the acknowledged rows before the first one still waiting.
  Status forget_acknowledged();
  // A new session: what was in flight goes again (the broker may hear it twice; seq tells).
  void resend_in_flight();
  [[nodiscard]] std::size_t in_flight() const { return in_flight_.size(); }
  [[nodiscard]] record::SpoolStats stats() const { return spool_->stats(); }

 private:
  ReadingSpool(std::unique_ptr<record::Spool> spool, std::string sensor)
      : spool_(std::move(spool)), sensor_(std::move(sensor)) {}
  std::unique_ptr<record::Spool> spool_;
  std::string sensor_;
  std::int64_t last_sent_ = 0;  // the newest row handed to the broker's session
  // Whether rows past the last next() handed out may wait on disk, and the newest it handed out:
  // the network loop asks next() every turn, and a caught-up spool answers without a query.
  bool maybe_unsent_ = true;
  std::int64_t handed_out_ = 0;
  std::map<std::int64_t, bool> in_flight_;      // rows sent, oldest first: acknowledged yet?
  std::unordered_map<int, std::int64_t> mids_;  // message id -> row
};

// "mqtt-rangekit-bay_A.spool": a sensor's spool file, from the client id and sensor name.
std::string reading_spool_name(const std::string& client_id, const std::string& sensor);

}  // namespace rangekit::mqtt
