// Time for the emulators' firmware models: a virtual clock that tests advance by
// hand, or the steady clock scaled (time-scale > 1 runs the firmware faster).
// Firmware models read only this, never the system clock, so every timing rule
// can be tested without sleeping.
#pragma once

#include <chrono>
#include <cstdint>

namespace rangekit {

using Nanos = std::chrono::nanoseconds;

class Clock {
 public:
  virtual ~Clock() = default;
  // Time since the clock started.
  [[nodiscard]] virtual Nanos now() const = 0;
};

class VirtualClock final : public Clock {
 public:
  [[nodiscard]] Nanos now() const override { return now_; }
  void advance(Nanos step) { now_ += step; }
  void advance_to(Nanos when) {
    if (when > now_) now_ = when;
  }

 private:
  Nanos now_{0};
};

class ScaledSteadyClock final : public Clock {
 public:
  explicit ScaledSteadyClock(double scale = 1.0) : scale_(scale), start_(std::chrono::steady_clock::now()) {}
  [[nodiscard]] Nanos now() const override {
    const auto real = std::chrono::steady_clock::now() - start_;
    return Nanos(static_cast<std::int64_t>(static_cast<double>(Nanos(real).count()) * scale_));
  }
  // Real time that passes while this clock advances by `span`.
  [[nodiscard]] Nanos real_duration(Nanos span) const {
    return Nanos(static_cast<std::int64_t>(static_cast<double>(span.count()) / scale_));
  }
  [[nodiscard]] double scale() const noexcept { return scale_; }

 private:
  double scale_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace rangekit
