// An in-memory pair of connected transports: what one end writes, the other
// reads. Lets protocol logic (driver against emulator firmware, or a scripted
// device) be tested with no device, no pty and no timing.
#pragma once

#include <utility>

#include "rangekit/core/transport.hpp"

namespace rangekit {

struct LoopbackPair {
  TransportPtr a;
  TransportPtr b;
};

// Closing one end lets the other read what was already sent, then report closed.
LoopbackPair make_loopback_pair(std::string name_a = "loopback A", std::string name_b = "loopback B");

}  // namespace rangekit
