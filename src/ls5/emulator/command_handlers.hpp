// What the LS5 command handlers share: the exchange a handler acts on and answers with.
#pragma once
#include <cstdint>

#include "rangekit/ls5/emulator/firmware.hpp"

namespace rangekit::ls5::emulator {

// A request for this sensor or a broadcast (L14: only well-formed ones get this far).
struct Firmware::Exchange {
  const Request& request;
  std::uint8_t own;  // the network address the request found: replies carry it
  bool answer;       // false for a broadcast (table 9.1 note 2)
  Nanos now;
};

}  // namespace rangekit::ls5::emulator
