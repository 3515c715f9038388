// The LS5 probe of `rangekit detect` (and the ULS one beside it) on an arbitrary line:
// it listens first, then asks ID and waits for the matching reply. Whatever arrives,
// the probe reports a sensor, no sensor or an error with a message.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "rangekit/ls5/driver.hpp"
#include "rangekit/uls/driver.hpp"
#include "scripted_transport.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const rangekit::Bytes script(data + 1, size - 1);
  {
    rangekit::fuzz::ScriptedTransport transport(script, rangekit::Errc::timeout);
    const auto found = rangekit::ls5::probe(transport, data[0], std::chrono::milliseconds(20));
    if (!found && found.error().message.empty()) std::abort();
  }
  {
    // The ULS probe is a driver asking ID and US, which reads on to its deadline after a
    // timeout: the line closes when the script is used up instead, so nothing waits.
    rangekit::fuzz::ScriptedTransport transport(script, rangekit::Errc::closed);
    const std::optional<std::uint8_t> address =
        (data[0] & 1) != 0 ? std::optional<std::uint8_t>(static_cast<std::uint8_t>(0x30 + data[0] % 0xC0))
                           : std::nullopt;
    const auto found = rangekit::uls::probe(transport, address, std::chrono::milliseconds(20));
    if (!found && found.error().message.empty()) std::abort();
  }
  return 0;
}
