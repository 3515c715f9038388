#include "mqtt/publish_packet.hpp"

namespace rangekit::mqtt {
namespace {

constexpr std::size_t max_topic_length = 65535;  // a UTF-8 Encoded String's two-byte length (§1.5.4)

// Remaining Length: topic length and name, the property length (one byte, zero), the payload.
std::size_t remaining_length(std::string_view topic, std::string_view payload) {
  return 2 + topic.size() + 1 + payload.size();
}

std::size_t variable_byte_integer_size(std::size_t value) {
  if (value < 128) return 1;
  if (value < 16'384) return 2;
  if (value < 2'097'152) return 3;
  return 4;
}

}  // namespace

void append_variable_byte_integer(std::string& out, std::uint32_t value) {
  do {
    auto byte = static_cast<unsigned char>(value % 128);
    value /= 128;
    if (value > 0) byte |= 0x80U;  // more bytes follow
    out.push_back(static_cast<char>(byte));
  } while (value > 0);
}

std::size_t publish_packet_size(std::string_view topic, std::string_view payload) {
  if (topic.size() > max_topic_length) return 0;
  const std::size_t remaining = remaining_length(topic, payload);
  if (remaining > max_remaining_length) return 0;
  return 1 + variable_byte_integer_size(remaining) + remaining;
}

bool append_publish_qos0(std::string& out, std::string_view topic, std::string_view payload, bool retain) {
  if (publish_packet_size(topic, payload) == 0) return false;
  // Fixed header: type 3 (PUBLISH) in the high nibble; DUP 0, QoS 0, RETAIN in the low one.
  out.push_back(static_cast<char>(0x30U | (retain ? 0x01U : 0x00U)));
  append_variable_byte_integer(out, static_cast<std::uint32_t>(remaining_length(topic, payload)));
  out.push_back(static_cast<char>(topic.size() >> 8U));
  out.push_back(static_cast<char>(topic.size() & 0xFFU));
  out.append(topic);
  out.push_back('\0');  // Property Length 0: no properties
  out.append(payload);
  return true;
}

}  // namespace rangekit::mqtt
