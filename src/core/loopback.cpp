#include "rangekit/core/loopback.hpp"

#include <condition_variable>
#include <deque>
#include <mutex>

namespace rangekit {
namespace {

// One direction of the pair: a byte queue and whether its writer has closed.
struct Pipe {
  std::deque<std::uint8_t> bytes;
  bool writer_closed = false;
  bool reader_closed = false;
};

struct Shared {
  std::mutex mutex;
  std::condition_variable changed;
  Pipe a_to_b;
  Pipe b_to_a;
};

class LoopbackEnd final : public Transport {
 public:
  LoopbackEnd(std::shared_ptr<Shared> shared, bool is_a, std::string name)
      : shared_(std::move(shared)), is_a_(is_a), name_(std::move(name)) {}
  ~LoopbackEnd() override { shut(); }

  Status write_all(Bytes data) override {
    std::lock_guard lock(shared_->mutex);
    Pipe& out = outgoing();
    if (out.writer_closed) return make_error(Errc::closed, name_ + ": write after close");
    if (out.reader_closed) return make_error(Errc::closed, name_ + ": the other end is closed");
    out.bytes.insert(out.bytes.end(), data.begin(), data.end());
    shared_->changed.notify_all();
    return ok_status();
  }

  Result<std::size_t> read_some(std::span<std::uint8_t> out, std::chrono::milliseconds timeout) override {
    std::unique_lock lock(shared_->mutex);
    Pipe& in = incoming();
    if (in.reader_closed) return make_error(Errc::closed, name_ + ": read after close");
    const bool ready = shared_->changed.wait_for(
        lock, timeout, [&] { return !in.bytes.empty() || in.writer_closed || in.reader_closed; });
    if (in.reader_closed) return make_error(Errc::closed, name_ + ": closed while reading");
    if (!ready)
      return make_error(Errc::timeout, name_ + ": no bytes within " + std::to_string(timeout.count()) + " ms");
    if (in.bytes.empty()) return make_error(Errc::closed, name_ + ": the other end closed");
    std::size_t count = 0;
    while (count < out.size() && !in.bytes.empty()) {
      out[count++] = in.bytes.front();
      in.bytes.pop_front();
    }
    return count;
  }

  void close() noexcept override { shut(); }

  [[nodiscard]] std::string name() const override { return name_; }

 private:
  void shut() noexcept {
    std::lock_guard lock(shared_->mutex);
    outgoing().writer_closed = true;
    incoming().reader_closed = true;
    shared_->changed.notify_all();
  }

  Pipe& outgoing() { return is_a_ ? shared_->a_to_b : shared_->b_to_a; }
  Pipe& incoming() { return is_a_ ? shared_->b_to_a : shared_->a_to_b; }

  std::shared_ptr<Shared> shared_;
  bool is_a_;
  std::string name_;
};

}  // namespace

LoopbackPair make_loopback_pair(std::string name_a, std::string name_b) {
  auto shared = std::make_shared<Shared>();
  return LoopbackPair{std::make_unique<LoopbackEnd>(shared, true, std::move(name_a)),
                      std::make_unique<LoopbackEnd>(shared, false, std::move(name_b))};
}

}  // namespace rangekit
