// Live measurement sources on serial ports, set up the way `demo` and `capture`
// need them: the port opened, the driver connected (with reconnect on the same
// path and baud) and the stream started, returned as one SampleSource.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"
#include "rangekit/core/serial_port.hpp"
#include "rangekit/core/transport.hpp"

namespace rangekit::cli {

// Opens a serial port or pty, the one way every subcommand does. Any failure to
// open (missing path, no permission, not a terminal, a speed the system cannot set)
// is Errc::io, exit 4 (docs/cli.md), with the port named once in the message.
Result<TransportPtr> open_port(const std::string& path, const SerialSettings& settings);
// 8N1 at `baud`, the factory byte format of the sensors this tool knows.
Result<TransportPtr> open_serial(const std::string& path, std::uint32_t baud);
// The reopen function a driver reconnects with: the same path and line settings.
std::function<Result<TransportPtr>()> reopen_port(const std::string& path, const SerialSettings& settings);
// The line settings of a byte format name, 8 data bits: "8N1", "8E2", "8O1" ...
Result<SerialSettings> serial_settings(std::uint32_t baud, std::string_view byte_format);

// The error with what failed in front of its message: "<what>: <message>".
Error named(const std::string& what, Error error);

// A stream whose driver the caller does not keep: this owns both (the stream goes
// first, so the unit is left as the stream's own stop says).
template <class DriverType, class StreamType>
class DriverAndStream final : public SampleSource {
 public:
  DriverAndStream(std::unique_ptr<DriverType> driver, std::unique_ptr<StreamType> stream)
      : driver_(std::move(driver)), stream_(std::move(stream)) {}
  std::optional<StreamItem> next(std::chrono::milliseconds timeout) override { return stream_->next(timeout); }
  bool next_batch(std::vector<StreamItem>& batch, std::chrono::milliseconds timeout) override {
    return stream_->next_batch(batch, timeout);
  }
  [[nodiscard]] bool finished() const override { return stream_->finished(); }
  void stop() override { stream_->stop(); }
  [[nodiscard]] std::uint64_t lost() const override { return stream_->lost(); }

 private:
  std::unique_ptr<DriverType> driver_;
  std::unique_ptr<StreamType> stream_;  // declared last: destroyed first
};

template <class DriverType, class StreamType>
SampleSourcePtr own_both(std::unique_ptr<DriverType> driver, std::unique_ptr<StreamType> stream) {
  return std::make_unique<DriverAndStream<DriverType, StreamType>>(std::move(driver), std::move(stream));
}

}  // namespace rangekit::cli
