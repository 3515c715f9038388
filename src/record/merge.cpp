#include "rangekit/record/merge.hpp"

#include <atomic>
#include <thread>

#include "rangekit/core/stream_queue.hpp"

namespace rangekit::record {
namespace {

constexpr std::chrono::milliseconds source_poll{50};

class MergedSource final : public SampleSource {
 public:
  explicit MergedSource(std::vector<SampleSourcePtr> sources) : sources_(std::move(sources)) {
    if (sources_.empty()) queue_.close();
    readers_.reserve(sources_.size());
    for (auto& source : sources_) readers_.emplace_back([this, &source] { read_all(*source); });
  }

  ~MergedSource() override {
    stop();
    for (auto& reader : readers_) reader.join();
  }

  std::optional<StreamItem> next(std::chrono::milliseconds timeout) override { return queue_.pop(timeout); }
  bool next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) override {
    return queue_.take_all(batch, timeout);
  }

  // Only once every reader has ended and its last items were taken.
  [[nodiscard]] bool finished() const override {
    return finished_sources_.load() == sources_.size() && queue_.size() == 0;
  }

  void stop() override {
    if (stopping_.exchange(true)) return;
    for (auto& source : sources_) source->stop();
  }

  [[nodiscard]] std::uint64_t lost() const override {
    std::uint64_t total = queue_.dropped();
    for (const auto& source : sources_) total += source->lost();
    return total;
  }

 private:
  void read_all(SampleSource& source) {
    while (!stopping_.load()) {
      auto item = source.next(source_poll);
      if (item) {
        queue_.push(std::move(*item));
      } else if (source.finished()) {
        break;
      }
    }
    if (finished_sources_.fetch_add(1) + 1 == sources_.size()) queue_.close();
  }

  std::vector<SampleSourcePtr> sources_;
  StreamQueue<StreamItem> queue_;
  std::atomic<bool> stopping_{false};
  std::atomic<std::size_t> finished_sources_{0};
  std::vector<std::thread> readers_;
};

}  // namespace

SampleSourcePtr merge_sources(std::vector<SampleSourcePtr> sources) {
  return std::make_unique<MergedSource>(std::move(sources));
}

}  // namespace rangekit::record
