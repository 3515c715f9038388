// The emulators' control socket (answer_control_line, both firmwares' handlers) on arbitrary
// lines: every line gets one JSON reply with "ok" or "error", and nothing throws, invalid
// UTF-8 included. Fresh firmwares per input, so a crash reproduces from its input alone.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "rangekit/ls5/emulator/firmware.hpp"
#include "rangekit/sim/control_socket.hpp"
#include "rangekit/uls/emulator/firmware.hpp"

namespace {

using rangekit::Nanos;

void check_reply(const std::string& reply) {
  const auto parsed = nlohmann::json::parse(reply, nullptr, false);
  if (parsed.is_discarded() || !parsed.is_object()) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  rangekit::uls::emulator::Firmware uls{rangekit::uls::emulator::FirmwareOptions{}};
  auto ls5 = rangekit::ls5::emulator::Firmware::create(rangekit::ls5::emulator::FirmwareConfig{});
  if (!ls5) std::abort();
  Nanos now{0};
  const auto uls_handler = [&](const nlohmann::json& request) { return uls.control(request, now); };
  const auto ls5_handler = [&](const nlohmann::json& request) { return (*ls5)->control(request, now); };
  // One request a line, as the socket splits them; time moves 10 ms between lines.
  std::size_t start = 0;
  while (start <= input.size()) {
    std::size_t end = input.find('\n', start);
    if (end == std::string::npos) end = input.size();
    const std::string line = input.substr(start, end - start);
    check_reply(rangekit::answer_control_line(uls_handler, line));
    check_reply(rangekit::answer_control_line(ls5_handler, line));
    now += std::chrono::milliseconds(10);
    start = end + 1;
  }
  return 0;
}
