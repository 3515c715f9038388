// rangekit library example: read a ULS and an LS5 through the host drivers.
//
//   build/examples/stream_both ULS_PORT LS5_PORT [SECONDS]
//
// Try it without hardware: `build/rangekit sim uls --config-port /tmp/uls` and
// `build/rangekit sim ls5 --port /tmp/ls5` in two shells, then
// `build/examples/stream_both /tmp/uls /tmp/ls5 5`. Errors are values: each call
// returns a Result that says what went wrong (docs/host-uls.md, docs/host-ls5.md).
#include <chrono>
#include <cstdio>
#include <string>
#include <variant>

#include "rangekit/core/serial_port.hpp"
#include "rangekit/ls5/driver.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/uls/driver.hpp"
#include "rangekit/uls/family.hpp"

namespace {

rangekit::Result<rangekit::TransportPtr> open_port(const std::string& path) {
  auto port = rangekit::SerialPort::open(path, rangekit::SerialSettings{});  // 115200 8N1, both factories
  if (!port) return std::move(port).error();
  return rangekit::TransportPtr(std::move(port).value());
}

int fail(const char* what, const rangekit::Error& error) {
  std::fprintf(stderr, "%s: %s\n", what, error.describe().c_str());
  return 1;
}

// Prints what the source yields for `seconds`: samples and link events.
void drain(rangekit::SampleSource& source, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end && !source.finished()) {
    auto item = source.next(std::chrono::milliseconds(100));
    if (!item) continue;
    if (const auto* sample = std::get_if<rangekit::Sample>(&*item)) {
      // The one number a sample reports, with its channel's unit, whichever family sent it.
      if (const auto reading = rangekit::reading_of(*sample)) {
        std::printf("%s %.*f %s\n", sample->device.c_str(), std::max(reading->decimals, 0), reading->value,
                    rangekit::unit_symbol(reading->channel->unit));
      } else {
        std::printf("%s %s: no reading\n", sample->device.c_str(),
                    std::string(rangekit::kind_name_of(*sample)).c_str());
      }
    } else {
      const auto& event = std::get<rangekit::StreamEvent>(*item);
      std::printf("event %s: %s\n", rangekit::stream_event_kind_name(event.kind), event.message.c_str());
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s ULS_PORT LS5_PORT [SECONDS]\n", argv[0]);
    return 2;
  }
  // The families this program reads, so that a sample's reading, kind and output formats are known
  // (the rangekit binary registers every family it was built with).
  rangekit::register_family(rangekit::uls::family());
  rangekit::register_family(rangekit::ls5::family());
  const std::string uls_path = argv[1];
  const std::string ls5_path = argv[2];
  const double seconds = argc > 3 ? std::stod(argv[3]) : 5.0;

  // ULS: typed calls in readable units, checked against §8 before sending.
  auto uls_link = open_port(uls_path);
  if (!uls_link) return fail("ULS port", uls_link.error());
  rangekit::uls::Driver uls(std::move(uls_link).value(), {}, [uls_path] { return open_port(uls_path); });
  auto version = uls.version();
  if (!version) return fail("ULS ID", version.error());
  std::printf("ULS %s\n", version->c_str());
  if (auto set = uls.set_prf(5000); !set) return fail("ULS PF", set.error());
  // The stream is its own object; destroying it (or the driver) ends it, ST only if it started the unit.
  auto uls_stream = uls.start_stream();
  if (!uls_stream) return fail("ULS stream", uls_stream.error());
  drain(**uls_stream, seconds);
  (*uls_stream)->stop();

  // LS5: identification, then a thinned stream (§8.4) that reconnects on its own.
  auto ls5_link = open_port(ls5_path);
  if (!ls5_link) return fail("LS5 port", ls5_link.error());
  rangekit::ls5::Driver ls5(std::move(ls5_link).value(), rangekit::ls5::DriverOptions{},
                            [ls5_path] { return open_port(ls5_path); });
  auto info = ls5.info();
  if (!info) return fail("LS5 ID", info.error());
  std::printf("LS5 %s, range %.3f mm\n", std::string(info->identification.version_text.view()).c_str(),
              info->identification.range_mm);
  rangekit::ls5::Driver::StreamOptions options;
  options.thinning = 20;
  auto stream = ls5.start_stream(options);
  if (!stream) return fail("LS5 stream", stream.error());
  drain(**stream, seconds);
  return 0;
}
