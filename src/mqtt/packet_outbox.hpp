// The reading fast path's send buffer (docs/mqtt.md): QoS 0 PUBLISH packets the bridge
// encodes itself, written to a session's socket with one send() per drain. The socket is
// libmosquitto's too, so the bridge must know when part of a packet of ours is on the
// wire (mid_packet): until the rest has gone, nothing else may be written to it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <utility>

namespace rangekit::mqtt {

class PacketOutbox {
 public:
  enum class Write {
    done,     // everything went
    blocked,  // the socket is full: write again at POLLOUT
    failed,   // the connection is gone (what is left stays until drop())
  };

  // Appends a QoS 0 PUBLISH (publish_packet.hpp); false, nothing appended, when it cannot
  // be encoded or is larger than `max_packet` (the broker's limit, 0: none).
  bool add(std::string_view topic, std::string_view payload, std::uint32_t max_packet = 0);
  // Writes as much as the nonblocking socket `fd` takes, without SIGPIPE.
  Write write_to(int fd);
  // Drops what is left (a lost connection); returns how many packets that was.
  std::size_t drop();
  // Packets written whole since the last call.
  std::size_t take_completed() { return std::exchange(completed_, 0); }

  [[nodiscard]] bool empty() const { return bytes_.empty(); }
  [[nodiscard]] bool mid_packet() const { return partial_ > 0; }
  [[nodiscard]] std::size_t packets() const { return sizes_.size(); }

 private:
  std::string bytes_;              // packets not yet written, oldest first
  std::deque<std::size_t> sizes_;  // the size of each packet in bytes_
  std::size_t partial_ = 0;        // bytes of the first packet already written
  std::size_t completed_ = 0;
};

}  // namespace rangekit::mqtt
