// An LS5 streaming on a serial port as one SampleSource, for `capture` and `demo`; the
// stream's stop (SB) leaves the sensor as found.
#include <memory>
#include <vector>

#include "cli/host_sources.hpp"
#include "ls5/cli/ls5_cli.hpp"
#include "rangekit/ls5/driver.hpp"

namespace rangekit::cli {
namespace {

struct Ls5CaptureOptions {
  std::vector<std::string> ports;
  std::uint32_t baud = 115200;
  unsigned address = 1;
  std::optional<unsigned> thinning;
};

}  // namespace

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

SourceStarter add_ls5_capture_options(CLI::App& capture) {
  auto options = std::make_shared<Ls5CaptureOptions>();
  capture.add_option("--ls5", options->ports, "LS5 serial port (repeat for several)");
  capture.add_option("--ls5-baud", options->baud, "baud rate of the LS5 ports")->capture_default_str();
  capture.add_option("--ls5-address", options->address, "LS5 network address")
      ->check(CLI::Range(1, 255))
      ->capture_default_str();
  capture.add_option("--ls5-thinning", options->thinning, "LS5 stream thinning: every n-th result")
      ->check(CLI::Range(1, 255));
  return [options]() -> Result<std::vector<SampleSourcePtr>> {
    std::optional<std::uint8_t> thinning;
    if (options->thinning) thinning = static_cast<std::uint8_t>(*options->thinning);
    std::vector<SampleSourcePtr> sources;
    for (const auto& port : options->ports) {
      auto source = start_ls5_source(
          Ls5SourceOptions{port, options->baud, static_cast<std::uint8_t>(options->address), thinning});
      if (!source) return std::move(source).error();
      sources.push_back(std::move(source).value());
    }
    return sources;
  };
}

}  // namespace rangekit::cli
