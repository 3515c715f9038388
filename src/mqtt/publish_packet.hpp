// An MQTT 5 PUBLISH packet at QoS 0 (MQTT 5.0 §3.3), encoded by the bridge itself so that
// a drain's readings leave a session in one send() instead of one mosquitto_publish (and
// its two system calls) each: docs/mqtt.md, "The reading fast path". QoS 0 needs no
// packet identifier and no state in the client, which is why only it takes this path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace rangekit::mqtt {

// The Remaining Length of §2.1.4 as a Variable Byte Integer (§1.5.5): up to 268,435,455.
inline constexpr std::uint32_t max_remaining_length = 268'435'455;

// Appends the Variable Byte Integer of §1.5.5 (1 to 4 bytes); `value` at most max_remaining_length.
void append_variable_byte_integer(std::string& out, std::uint32_t value);

// The whole packet's size: fixed header (§3.3.1), topic name (§3.3.2.1), an empty property
// list (§3.3.2.3), payload (§3.3.3). Zero when the Remaining Length would not fit.
std::size_t publish_packet_size(std::string_view topic, std::string_view payload);

// Appends a QoS 0 PUBLISH of `payload` on `topic` (a valid topic name: UTF-8, no wildcard,
// at most 65,535 bytes; the caller checks it once). False, and nothing appended, when the
// packet cannot be encoded.
bool append_publish_qos0(std::string& out, std::string_view topic, std::string_view payload, bool retain);

}  // namespace rangekit::mqtt
