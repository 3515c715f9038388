// The ULS model's two serial ports (§4): framing, overruns, addressing on the RS-485 bus (§7),
// replies paced at the line's speed and the baud rate switch.
#include "rangekit/uls/emulator/firmware.hpp"

#include <algorithm>

namespace rangekit::uls::emulator {

void Firmware::take_until(Port& port, Nanos until) {
  while (port.pacer.next_completion() <= until) {
    const Nanos done = port.pacer.next_completion();
    sent_.clear();  // reused: no allocation per byte
    port.pacer.take_sent(done, sent_);
    const auto index = static_cast<std::size_t>(&port - ports_.data());
    for (const auto value : sent_) port.outbox.push_back(LineByte{done, value, settings_.baud[index]});
  }
}

void Firmware::drain(Port& port, Nanos now) {
  const std::size_t index = static_cast<std::size_t>(&port - ports_.data());
  auto switch_baud = [&] {
    settings_.baud[index] = *port.pending_baud;
    port.pacer.reconfigure(*port.pending_baud, uls_hundredths_of_bits, port.pending_at);
    port.pending_baud.reset();
  };
  if (port.pending_baud && port.pending_port != index && port.pending_at < now) {
    // BR for the other port: it switches once the $OK has left the port the command came
    // on, even while it streams; what it still has queued goes on at the new speed (U36).
    take_until(port, port.pending_at);
    switch_baud();
  }
  take_until(port, now);
  while (port.outbox.size() > 65536) port.outbox.pop_front();  // nobody reads this port
  if (port.pending_baud && port.pending_at < now && port.pacer.queued() == 0) {
    // Strictly after: the runtime hands the $OK's last byte to the host at the old speed first.
    // BR takes effect once the $OK has left the line (§8 Set/Get Baud Rate, U36).
    switch_baud();
  }
}

void Firmware::take_line_output(std::size_t port, Nanos now, std::vector<LineByte>& out) {
  if (port >= ports_.size()) return;
  advance(now);
  auto& p = ports_[port];
  while (!p.outbox.empty() && p.outbox.front().done <= now) {
    out.push_back(p.outbox.front());
    p.outbox.pop_front();
  }
}

void Firmware::receive(std::size_t port, std::uint8_t byte, Nanos now) {
  if (port >= ports_.size()) return;
  advance(now);
  // 10 bits a byte (a host's 8N1) at the port's baud, one byte after the other.
  const Nanos byte_time(10'000'000'000LL / settings_.baud[port]);
  ports_[port].received_at = std::max(now, ports_[port].received_at) + byte_time;
  if (ports_[port].overrun && continue_overrun(port, byte, now)) return;
  auto& input = ports_[port].input;
  input.push_back(byte);
  while (!input.empty()) {
    const FrameScan scan = scan_frame(Bytes(input.data(), input.size()));
    if (scan.status == FrameStatus::need_more) break;
    if (scan.status == FrameStatus::invalid && scan.consumed == max_frame_length &&
        input.size() == max_frame_length + 1 && input.back() != '$' && input.back() != '#') {
      // 64 valid frame bytes and a 65th that neither ends the frame nor starts a new one:
      // the receive buffer overran (F5, U78). The rest of the line is lost up to its CR.
      ports_[port].overrun = std::array<std::uint8_t, 2>{input[0], input[1]};
      input.clear();
      break;
    }
    if (scan.status == FrameStatus::complete) {
      const std::vector<std::uint8_t> frame(scan.frame.begin(), scan.frame.end());
      input.erase(input.begin(), input.begin() + static_cast<std::ptrdiff_t>(scan.consumed));
      auto parsed = parse_frame(Bytes(frame.data(), frame.size()));
      if (parsed) {
        handle_frame(port, *parsed, now);
      } else if (!frame.empty() && frame[0] == '$') {
        reply(port, false, encode_error_reply(Address::none(), 1), now);  // malformed '$' frame (U37)
      } else if (frame.size() > 1 && frame[0] == '#' && settings_.address != 0 && frame[1] == settings_.address) {
        reply(port, false, encode_error_reply(Address::unit(settings_.address), 1), now);
      }
      continue;
    }
    // Invalid bytes (noise, a cut frame): dropped silently (U37).
    input.erase(input.begin(), input.begin() + static_cast<std::ptrdiff_t>(std::max<std::size_t>(scan.consumed, 1)));
  }
}

bool Firmware::continue_overrun(std::size_t port, std::uint8_t byte, Nanos now) {
  auto& overrun = ports_[port].overrun;
  if (byte == '$' || byte == '#') {
    overrun.reset();  // a new frame cuts the line short (F3): no answer
    return false;
  }
  if (byte == '\r') {
    const auto [start, address] = *overrun;
    overrun.reset();
    // Answered like a refused frame (U37): '$' by every unit, '#' by the addressed one only.
    if (start == '$') {
      reply(port, false, encode_error_reply(Address::none(), error_number::rx_buffer_overrun), now);
    } else if (settings_.address != 0 && address == settings_.address) {
      reply(port, false, encode_error_reply(Address::unit(settings_.address), error_number::rx_buffer_overrun), now);
    }
    return true;
  }
  if (byte < 0x20 || byte >= 0x7F) overrun.reset();  // not frame text: the line was noise (F4), no answer
  return true;
}

void Firmware::reply(std::size_t port, bool silent, const Result<FrameText>& frame, Nanos now) {
  if (silent || !frame) return;
  // A reply starts once the request has crossed the line and the unit has turned round (U133).
  ports_[port].pacer.send(frame->bytes(), std::max(now, ports_[port].received_at + options_.turnaround));
}

void Firmware::reply_values(std::size_t port, Address to, bool silent, std::string_view mnemonic,
                            std::initializer_list<std::string_view> values, Nanos now) {
  const std::vector<std::string_view> list(values);
  reply(port, silent, encode_value_reply(to, mnemonic, list), now);
}

void Firmware::handle_frame(std::size_t port, const FrameView& frame, Nanos now) {
  Address to = Address::none();
  bool silent = false;
  if (frame.address.addressed) {
    if (frame.address.is_broadcast()) {
      silent = true;  // U4: every unit acts, none replies
      to = Address::unit(settings_.address);
    } else {
      if (settings_.address == 0 || frame.address.byte != settings_.address) return;  // U3
      to = Address::unit(settings_.address);
    }
  }
  if (frame.kind == FrameKind::time_between_events) {
    reply(port, silent, encode_error_reply(to, 1), now);
    return;
  }
  const CommandInfo* command = find_command(frame.mnemonic);
  if (command == nullptr) {
    reply(port, silent, encode_error_reply(to, 1), now);
    return;
  }
  const FormResult form = request_form(*command, frame.field_count);
  Verdict verdict = form.verdict;
  if (verdict.ok()) verdict = validate_request(*command, frame.fields(), settings_.units);
  if (verdict.ok()) verdict = check_while_measuring(*command, form.form, measuring_);
  if (!verdict.ok()) {
    reply(port, silent, encode_error_reply(to, verdict.error), now);
    return;
  }
  execute(port, to, silent, *command, form.form, frame, now);
}

Address Firmware::measurement_address() const noexcept {
  if (settings_.address != 0 && settings_.output_port == OutputPort::universal_rs485 &&
      measurement_port() == universal_port)
    return Address::unit(settings_.address);
  return Address::none();
}

std::size_t Firmware::measurement_port() const noexcept {
  // §3 "Time between events can be logged using the configuration port only", whatever MO
  // says: more specific than §4's look-down "configuration port ... system setup only" (U74).
  if (settings_.mode == Mode::look_down && settings_.time_between_events) return configuration_port;
  return settings_.output_port == OutputPort::configuration ? configuration_port : universal_port;
}

}  // namespace rangekit::uls::emulator
