// A ULS streaming on a serial port as one SampleSource, for `capture` and `demo`; the
// stream's stop leaves the unit as found (U86).
#include <memory>
#include <vector>

#include "cli/host_sources.hpp"
#include "rangekit/uls/driver.hpp"
#include "uls/cli/uls_cli.hpp"

namespace rangekit::cli {
namespace {

struct UlsCaptureOptions {
  std::vector<std::string> ports;
  std::uint32_t baud = 115200;
};

}  // namespace

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

SourceStarter add_uls_capture_options(CLI::App& capture) {
  auto options = std::make_shared<UlsCaptureOptions>();
  capture.add_option("--uls", options->ports, "ULS serial port (repeat for several)");
  capture.add_option("--uls-baud", options->baud, "baud rate of the ULS ports")->capture_default_str();
  return [options]() -> Result<std::vector<SampleSourcePtr>> {
    std::vector<SampleSourcePtr> sources;
    for (const auto& port : options->ports) {
      auto source = start_uls_source(UlsSourceOptions{port, options->baud, std::nullopt, port});
      if (!source) return std::move(source).error();
      sources.push_back(std::move(source).value());
    }
    return sources;
  };
}

}  // namespace rangekit::cli
