#include "mqtt/packet_outbox.hpp"

#include <sys/socket.h>

#include <cerrno>

#include "mqtt/publish_packet.hpp"

namespace rangekit::mqtt {

bool PacketOutbox::add(std::string_view topic, std::string_view payload, std::uint32_t max_packet) {
  const std::size_t size = publish_packet_size(topic, payload);
  if (size == 0 || (max_packet > 0 && size > max_packet)) return false;
  append_publish_qos0(bytes_, topic, payload, false);
  sizes_.push_back(size);
  return true;
}

PacketOutbox::Write PacketOutbox::write_to(int fd) {
  while (!bytes_.empty()) {
    const ssize_t sent = ::send(fd, bytes_.data(), bytes_.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (sent < 0) {
      if (errno == EINTR) continue;
      return errno == EAGAIN || errno == EWOULDBLOCK ? Write::blocked : Write::failed;
    }
    const auto count = static_cast<std::size_t>(sent);
    bytes_.erase(0, count);
    partial_ += count;
    while (!sizes_.empty() && partial_ >= sizes_.front()) {
      partial_ -= sizes_.front();
      sizes_.pop_front();
      ++completed_;
    }
  }
  return Write::done;
}

std::size_t PacketOutbox::drop() {
  const std::size_t dropped = sizes_.size();
  bytes_.clear();
  sizes_.clear();
  partial_ = 0;
  return dropped;
}

}  // namespace rangekit::mqtt
