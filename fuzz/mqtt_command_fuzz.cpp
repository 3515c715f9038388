// MQTT command payloads of any JSON type and of non-JSON bytes, through the answer the
// bridge publishes (mqtt/command_answer.hpp) on a hub whose sensors are not connected: the
// body is read and checked before any sensor is asked. Every payload gets one object with
// "ok" or "error" that the bridge can publish, and nothing throws (one `{"action":1}` once
// ended the service). The first byte picks set or action and the sensor's family.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "mqtt/command_answer.hpp"
#include "rangekit/hub/site_config.hpp"

namespace {

rangekit::hub::Hub& hub() {
  static const auto site = rangekit::hub::parse_site_config(
      "[[sensor]]\nname = \"l\"\nfamily = \"ls5\"\nport = \"/nonexistent/rangekit-fuzz-ls5\"\n"
      "[[sensor]]\nname = \"u\"\nfamily = \"uls\"\nport = \"/nonexistent/rangekit-fuzz-uls\"\n",
      "site.toml");
  if (!site) std::abort();
  static const auto started = rangekit::hub::Hub::start(*site);
  return *started;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const auto kind = (data[0] & 1) != 0 ? rangekit::mqtt::CommandKind::set : rangekit::mqtt::CommandKind::action;
  const std::string sensor = (data[0] & 2) != 0 ? "u" : "l";
  const std::string_view payload(reinterpret_cast<const char*>(data + 1), size - 1);
  const nlohmann::json answer = rangekit::mqtt::answer_command(hub(), sensor, kind, payload);
  if (!answer.is_object() || (!answer.contains("ok") && !answer.contains("error"))) std::abort();
  // As the bridge publishes it: text that is not UTF-8 is replaced, never thrown.
  (void)answer.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return 0;
}
