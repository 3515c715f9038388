// The drivers' reply matching on an arbitrary line: a ULS and an LS5 driver ask their
// usual requests (identification, status, settings, a measurement) and read whatever
// the "device" sends: garbage, half frames, echoes of the request, replies to other
// requests or addresses. Each call returns a value or an error naming the problem.
// The first byte picks the addressing (ULS `$` or `#a`, LS5 address 1 or broadcast).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>

#include "rangekit/ls5/driver.hpp"
#include "rangekit/uls/driver.hpp"
#include "scripted_transport.hpp"

namespace {

using namespace std::chrono_literals;

template <class T>
void check(const rangekit::Result<T>& result) {
  if (!result && result.error().message.empty()) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t flags = data[0];
  const rangekit::Bytes script(data + 1, size - 1);
  {
    rangekit::uls::DriverOptions options;
    if ((flags & 1) != 0) options.address = 'A';
    options.timeout = 20ms;  // never reached: the script reads as closed once used up
    options.measure_timeout = 20ms;
    options.read_retries = 0;
    rangekit::uls::Driver driver(std::make_unique<rangekit::fuzz::ScriptedTransport>(script, rangekit::Errc::closed),
                                 options);
    check(driver.info());
    check(driver.get("MO"));
    check(driver.get("PF"));
    check(driver.status());
  }
  {
    rangekit::ls5::DriverOptions options;
    options.address = (flags & 2) != 0 ? 0x00 : 0x01;
    options.timeout = 20ms;
    options.read_retries = 0;
    rangekit::ls5::Driver driver(std::make_unique<rangekit::fuzz::ScriptedTransport>(script, rangekit::Errc::closed),
                                 options);
    check(driver.identify());
    check(driver.read_parameter(0x01));
    check(driver.read_last());
    check(driver.get("median-points"));
  }
  return 0;
}
