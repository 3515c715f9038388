#include "cli/host_sources.hpp"

#include <memory>
#include <utility>

#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/uls/driver.hpp"

namespace rangekit::cli {
namespace {

// A stream whose driver the caller does not keep: this owns both (the stream goes
// first, so the unit is left as the stream's own stop says: LS5 SB, ULS U86).
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

Error named(const std::string& what, Error error) {
  error.message = what + ": " + error.message;
  return error;
}

}  // namespace

Result<TransportPtr> open_port(const std::string& path, const SerialSettings& settings) {
  return open_serial_link(path, settings);
}

Result<TransportPtr> open_serial(const std::string& path, std::uint32_t baud) {
  return open_port(path, SerialSettings{baud, Parity::none, 1});
}

std::function<Result<TransportPtr>()> reopen_port(const std::string& path, const SerialSettings& settings) {
  return [path, settings] { return open_port(path, settings); };
}

Result<SampleSourcePtr> start_uls_source(const UlsSourceOptions& options) {
  auto link = open_serial(options.port, options.baud);
  if (!link) return std::move(link).error();
  uls::DriverOptions driver_options;
  driver_options.address = options.address;
  driver_options.source = options.label.empty() ? options.port : options.label;
  auto driver = std::make_unique<uls::Driver>(std::move(link).value(), driver_options,
                                              reopen_port(options.port, SerialSettings{options.baud, Parity::none, 1}));
  auto stream = driver->start_stream();
  if (!stream) return named("ULS on " + options.port, stream.error());
  return own_both(std::move(driver), std::move(stream).value());
}

Result<SampleSourcePtr> start_ls5_source(const Ls5SourceOptions& options) {
  auto link = open_serial(options.port, options.baud);
  if (!link) return std::move(link).error();
  ls5::DriverOptions driver_options;
  driver_options.address = options.address;
  auto driver = std::make_unique<ls5::Driver>(std::move(link).value(), driver_options,
                                              reopen_port(options.port, SerialSettings{options.baud, Parity::none, 1}));
  ls5::Driver::StreamOptions stream_options;
  stream_options.thinning = options.thinning;
  auto stream = driver->start_stream(stream_options);
  if (!stream) return named("LS5 on " + options.port, stream.error());
  return own_both(std::move(driver), std::move(stream).value());
}

}  // namespace rangekit::cli
