// The TOML loaders on arbitrary text: both emulator scenes, both host configuration
// files and the site file of `rangekit serve`. Each accepts the text or returns an
// error naming the problem, and never prints a raw control character.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "rangekit/hub/site_config.hpp"
#include "rangekit/ls5/emulator/firmware.hpp"
#include "rangekit/ls5/host_config.hpp"
#include "rangekit/uls/emulator/scene.hpp"
#include "rangekit/uls/host_config.hpp"

namespace {

template <class T>
void check(const rangekit::Result<T>& result, bool escaped = true) {
  if (result) return;
  const std::string& message = result.error().message;
  if (message.empty()) std::abort();
  if (!escaped) return;
  for (const char c : message) {
    if ((static_cast<unsigned char>(c) < 0x20 && c != '\n') || c == 0x7f) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  check(rangekit::uls::emulator::parse_scene(text, "scene.toml"));
  check(rangekit::ls5::emulator::parse_scene(text, "scene.toml"));
  check(rangekit::uls::config_from_toml(text, "uls.toml"));
  check(rangekit::ls5::parse_config_toml(text, "ls5.toml"));
  // The site file's messages are the hub's own (src/hub); only checked for a reason here.
  check(rangekit::hub::parse_site_config(text, "site.toml"), false);
  return 0;
}
