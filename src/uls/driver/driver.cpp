// The request/reply engine of the ULS driver: local validation, framing,
// matching replies to the request in flight, and handing every other frame
// (measurement lines, stream errors) to the measurement path.
#include "rangekit/uls/driver.hpp"

#include <algorithm>
#include <array>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/describe.hpp"
#include "rangekit/uls/errors.hpp"
#include "rangekit/uls/family.hpp"
#include "rangekit/uls/formulas.hpp"
#include "rangekit/uls/frame.hpp"
#include "uls/driver/binning_array.hpp"

namespace rangekit::uls {

using namespace std::chrono_literals;

namespace {

// Stream errors (U13) are never a command's answer (U60).
bool is_stream_error(int number) {
  return number == error_number::target_not_found || number == error_number::average_not_filled;
}

bool same_mnemonic(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (text::to_upper(a[i]) != text::to_upper(b[i])) return false;
  return true;
}

// The settings a measurement line is decoded with (U11): a set of one makes the context stale.
bool changes_context(std::string_view mnemonic) {
  return mnemonic == "MM" || mnemonic == "DM" || mnemonic == "MU" || mnemonic == "TB";
}

std::string join(std::span<const std::string_view> fields) {
  std::string text;
  for (const auto field : fields) {
    if (!text.empty()) text += ",";
    text += field;
  }
  return text;
}

}  // namespace

// Collects one binning target array `BM,i,m,...` into one list (U10).
struct BinAssembly {
  std::vector<TargetHit> targets;
  // True when the array is complete; an out-of-order line drops what was collected.
  bool add(const BinningTarget& target, bool& broken) {
    const detail::BinningArray step = detail::collect_binning_target(targets, target);
    broken = step == detail::BinningArray::out_of_order;
    return step == detail::BinningArray::complete;
  }
};

struct Driver::Pending {
  const CommandInfo* command = nullptr;
  Expect expect = Expect::ok;
  bool done = false;
  std::optional<Error> error;
  std::vector<std::string> values;
  Sample* measurement = nullptr;
  BinAssembly bins;
};

StatusInfo decode_status(std::uint8_t value) noexcept {
  StatusInfo info;
  info.value = value;
  info.active = (value & status_bit::active) != 0;
  info.laser_firing = (value & status_bit::laser_firing) != 0;
  info.averaging_calc = (value & status_bit::averaging_calc) != 0;
  info.binning_calc = (value & status_bit::binning_calc) != 0;
  if (info.laser_firing)
    info.mode = info.binning_calc ? Mode::binning : info.averaging_calc ? Mode::averaging : Mode::look_down;
  return info;
}

Sample sample_from_reading(const Reading& reading, int address, const SharedName& source) {
  Sample sample;
  sample.time = std::chrono::system_clock::now();
  sample.device = family().name;
  sample.source = source;
  sample.address = address;
  if (const auto* averaging = std::get_if<AveragingReading>(&reading)) {
    sample.kind = kind::averaging;
    if (averaging->range) sample.set(channel::distance_m, averaging->range->metres);
    sample.set(channel::pulse_width_ps, averaging->pulse_width_ps);
  } else if (const auto* target = std::get_if<BinningTarget>(&reading)) {
    sample.kind = kind::binning;
    sample.targets.push_back(TargetHit{target->range.metres, target->strength});
  } else if (const auto* look = std::get_if<LookDownReading>(&reading)) {
    sample.kind = kind::look_down;
    sample.set(channel::presence, look->present);
  } else if (const auto* event = std::get_if<TimeBetweenEvents>(&reading)) {
    sample.kind = kind::look_down;
    sample.set(channel::presence, event->kind != TimeBetweenEvents::Kind::no_presence);
    // U88: `$0000` is more than 65535 pulses, not 0.
    if (event->kind == TimeBetweenEvents::Kind::pulses) sample.set(channel::pulses_between_events, event->pulses);
    sample.set(channel::pulses_overflow, event->kind == TimeBetweenEvents::Kind::overflow);
  } else if (const auto* error = std::get_if<MeasurementError>(&reading)) {
    sample.kind = kind::error;
    sample.set(channel::error, error->number);
  }
  return sample;
}

Driver::Driver(TransportPtr transport, DriverOptions options, ReopenFunction reopen)
    : options_(std::move(options)),
      reopen_(std::move(reopen)),
      transport_(std::move(transport)),
      assembler_(&scan_frame) {
  if (options_.source.empty() && transport_) options_.source = transport_->name();
  source_name_ = options_.source;
}

// A unit the stream started is not left measuring by a driver that goes away (U86). The
// reader is joined here, before any member goes; the stream object forgets the driver.
Driver::~Driver() {
  std::lock_guard control(stream_control_mutex_);
  if (live_) detail::stop_live_stream(*live_, AfterStream::as_found, true);
}

Address Driver::request_address() const noexcept {
  return options_.address ? Address::unit(*options_.address) : Address::none();
}

Status Driver::set_address(std::optional<std::uint8_t> address) {
  if (address && !Address::unit(*address).is_unit())
    return make_error(Errc::out_of_range, "unit addresses are 0x30..0xEF");
  std::lock_guard request_lock(request_mutex_);
  std::lock_guard lock(state_mutex_);
  if (streaming_) return make_error(Errc::unsupported, "cannot change the address while streaming");
  options_.address = address;
  units_.reset();
  // Another unit: known when this driver has read it and changed nothing of it since.
  const auto known = unit_contexts_.find(context_key(address));
  context_known_ = known != unit_contexts_.end();
  if (context_known_) context_ = known->second;
  return ok_status();
}

bool Driver::on_reader_thread() const { return std::this_thread::get_id() == reader_id_.load(); }

bool Driver::connected() const {
  std::lock_guard lock(transport_mutex_);
  return transport_ != nullptr;
}

Status Driver::replace_transport(TransportPtr transport) {
  // A caller's request reads the transport and the assembler without transport_mutex_:
  // the old link is destroyed only after the request in flight has finished. The
  // reader thread (reconnecting) owns both while it streams and takes no request lock.
  std::unique_lock request_lock(request_mutex_, std::defer_lock);
  if (!on_reader_thread()) request_lock.lock();
  // The reader uses the transport and the assembler without holding the lock.
  if (streaming_ && !on_reader_thread()) {
    return make_error(Errc::unsupported, "cannot replace the transport while streaming: stop the stream first");
  }
  {
    std::lock_guard lock(state_mutex_);
    context_known_ = false;  // perhaps another unit, or the same one reconfigured
    unit_contexts_.clear();
  }
  std::lock_guard lock(transport_mutex_);
  transport_ = std::move(transport);
  assembler_.clear();
  return ok_status();
}

DriverCounters Driver::counters() const {
  std::lock_guard lock(state_mutex_);
  return counters_;
}

Status Driver::write_frame(Bytes bytes) {
  {
    std::lock_guard lock(state_mutex_);
    std::string sent(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (!sent.empty() && sent.back() == '\r') sent.pop_back();
    // A few, not one: a broadcast's echo is read only with the next request's reply.
    if (recent_sent_.size() == 4) recent_sent_.pop_front();
    recent_sent_.push_back(std::move(sent));
  }
  std::lock_guard lock(transport_mutex_);
  if (!transport_) return make_error(Errc::closed, options_.source + ": not connected");
  return transport_->write_all(bytes);
}

Status Driver::pump(std::chrono::milliseconds wait, std::size_t* bytes_read) {
  Transport* transport = nullptr;
  {
    std::lock_guard lock(transport_mutex_);
    transport = transport_.get();
  }
  if (transport == nullptr) return make_error(Errc::closed, options_.source + ": not connected");
  std::array<std::uint8_t, 512> buffer{};
  auto got = transport->read_some(buffer, wait);
  if (!got) {
    if (got.error().code == Errc::timeout) return ok_status();
    return got.error();
  }
  if (bytes_read != nullptr) *bytes_read = *got;
  auto on_rejected = [&](const FrameAssembler::Event& event) {
    if (event.reason == nullptr) return;
    {
      std::lock_guard lock(state_mutex_);
      counters_.rejected_bytes += event.rejected_bytes;
      ++counters_.bad_frames;
    }
    if (collecting_) emit_event(StreamEventKind::bad_frame, event.reason);
  };
  feed_all(assembler_, Bytes(buffer.data(), *got), [&] {
    MeasurementContext context;
    bool context_known = false;
    {
      std::lock_guard lock(state_mutex_);
      context = context_;
      context_known = context_known_;
    }
    if (context_known) {
      // Good averaging lines straight from the buffer; dispatch checks the
      // context is still this one and decodes again if not.
      decode_measurements(
          assembler_, context,
          [&](Bytes frame, const Measurement& measurement) { dispatch(frame, &measurement, &context); },
          [&](Bytes frame) { dispatch(frame); }, on_rejected);
    } else {
      FrameAssembler::Event event;
      while (assembler_.next(event)) {
        if (event.kind == FrameAssembler::Event::Kind::frame) {
          dispatch(event.frame);
        } else {
          on_rejected(event);
        }
      }
    }
  });
  return ok_status();
}

void Driver::dispatch(Bytes frame_bytes, const Measurement* direct, const MeasurementContext* direct_context) {
  {
    // A 2-wire RS-485 adapter without echo suppression reads back what the host
    // sent, before the unit's reply. A copy of a request sent since the last reply
    // is its echo: skipped (U67).
    std::lock_guard lock(state_mutex_);
    const std::string_view frame_text(reinterpret_cast<const char*>(frame_bytes.data()), frame_bytes.size());
    const auto sent = std::find(recent_sent_.begin(), recent_sent_.end(), frame_text);
    if (sent != recent_sent_.end()) {
      ++counters_.echoes;
      recent_sent_.erase(recent_sent_.begin(), sent + 1);  // echoes come back in order
      return;
    }
  }
  // A direct line is a good "$BM" averaging line (decode_measurements): parse_frame
  // would read it as a BM message from measurement.source.
  Result<FrameView> parsed = FrameView{};
  if (direct == nullptr) parsed = parse_frame(frame_bytes);
  if (!parsed) {
    {
      std::lock_guard lock(state_mutex_);
      ++counters_.bad_frames;
    }
    if (collecting_) emit_event(StreamEventKind::bad_frame, parsed.error().message);
    return;
  }
  const FrameView& frame = *parsed;
  const Address address = direct != nullptr ? direct->source : frame.address;
  const bool measurement_line = direct != nullptr || frame.kind == FrameKind::time_between_events || frame.is("BM");
  int error_number = 0;
  if (direct == nullptr && frame.is("ER") && frame.field_count == 1) {
    error_number = static_cast<int>(text::parse_unsigned(frame.field_slots[0], 3).value_or(0));
  }
  std::unique_lock lock(state_mutex_);
  const bool ours = address == request_address();  // set_address writes it under this lock
  Pending* pending = (pending_ != nullptr && !pending_->done && ours) ? pending_ : nullptr;

  if (measurement_line || is_stream_error(error_number)) {
    // A unit already measuring sends lines before MM/DM/MU/TB are known: a line
    // decoded with a guessed context would be a false bad_frame or a wrong value (U85).
    if (!context_known_) {
      ++counters_.undecoded;
      return;
    }
    if (direct != nullptr && *direct_context != context_) {
      // The context changed since the line was read: read it again with the new one.
      lock.unlock();
      dispatch(frame_bytes);
      return;
    }
    Result<Measurement> decoded =
        direct != nullptr ? Result<Measurement>(*direct) : decode_measurement(frame, context_);
    if (!decoded) {
      ++counters_.bad_frames;
      lock.unlock();
      if (collecting_) emit_event(StreamEventKind::bad_frame, decoded.error().message);
      return;
    }
    ++counters_.measurements;
    if (pending != nullptr && pending->expect == Expect::measurement) {
      const int sample_address = address.addressed ? address.byte : -1;
      Sample sample = sample_from_reading(decoded->reading, sample_address, source_name_);
      if (const auto* target = std::get_if<BinningTarget>(&decoded->reading)) {
        bool broken = false;
        if (!pending->bins.add(*target, broken)) return;
        sample.targets.assign(pending->bins.targets.begin(), pending->bins.targets.end());
      }
      *pending->measurement = std::move(sample);
      pending->done = true;
      recent_sent_.clear();  // echoes precede replies: none of what was sent can still come back
      lock.unlock();
      reply_ready_.notify_all();
      return;
    }
    lock.unlock();
    handle_measurement(*decoded);
    return;
  }

  if (pending == nullptr) {
    ++(ours ? counters_.unexpected : counters_.other_units);
    return;
  }
  if (error_number != 0) {
    pending->error = device_error(error_number, "$" + std::string(pending->command->mnemonic));
  } else if (frame.is("OK") && frame.field_count == 0) {
    if (pending->expect != Expect::ok) {
      ++counters_.unexpected;
      return;
    }
  } else if (pending->expect == Expect::value && same_mnemonic(frame.mnemonic, pending->command->mnemonic)) {
    for (const auto field : frame.fields()) pending->values.emplace_back(field);
  } else {
    ++counters_.unexpected;
    return;
  }
  ++counters_.replies;
  pending->done = true;
  // Echoes precede replies on the wire: what was sent up to now can no longer come back, and a
  // later reply equal to an earlier request ("$SG,12.500" after a set) is a reply (U67).
  recent_sent_.clear();
  lock.unlock();
  reply_ready_.notify_all();
}

Status Driver::check_locally(const CommandInfo& command, std::span<const std::string_view> fields) {
  const FormResult form = request_form(command, fields.size());
  Units units = Units::metres;
  const bool distance = command.is_distance();
  if (form.verdict.ok() && form.form == RequestForm::set && distance) {
    auto current = cached_units();
    if (!current) return current.error();
    units = *current;
  }
  Verdict verdict = form.verdict;
  if (verdict.ok()) verdict = validate_request(command, fields, units);
  if (verdict.ok()) return ok_status();
  return local_refusal(command, join(fields), verdict.error, units);
}

Result<std::vector<std::string>> Driver::transact(const CommandInfo& command, std::span<const std::string_view> fields,
                                                  Expect expect, int attempts, std::chrono::milliseconds timeout,
                                                  Sample* measurement) {
  // The reader thread keeps pumping while it waits for a caller's request.
  std::unique_lock request_lock(request_mutex_, std::defer_lock);
  if (on_reader_thread()) {
    while (!request_lock.try_lock()) {
      auto pumped = pump(10ms);
      if (!pumped) return pumped.error();
    }
  } else {
    request_lock.lock();
  }

  // Built under the request lock: set_address changes the address under it.
  const FormResult form = request_form(command, fields.size());
  const Address address = request_address();
  Result<FrameText> frame = form.form == RequestForm::action ? encode_action(address, command.mnemonic)
                            : form.form == RequestForm::get  ? encode_get(address, command.mnemonic, fields)
                                                             : encode_set(address, command.mnemonic, fields);
  if (!frame) return frame.error();

  for (int attempt = 0; attempt < attempts; ++attempt) {
    Pending pending;
    pending.command = &command;
    pending.expect = expect;
    pending.measurement = measurement;
    {
      std::lock_guard lock(state_mutex_);
      pending_ = &pending;
      if (attempt > 0) ++counters_.retries;
    }
    auto clear = [&] {
      std::lock_guard lock(state_mutex_);
      pending_ = nullptr;
    };
    if (auto written = write_frame(frame->bytes()); !written) {
      clear();
      return written.error();
    }
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    std::optional<Error> link_error;
    while (true) {
      {
        std::lock_guard lock(state_mutex_);
        if (pending.done) break;
      }
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left <= 0ms) break;
      if (streaming_ && !on_reader_thread()) {
        // The reader reads the link and hands the reply over; when the stream ends
        // meanwhile (stopped from another thread), this caller reads for itself.
        std::unique_lock lock(state_mutex_);
        reply_ready_.wait_until(lock, deadline, [&] { return pending.done || !streaming_; });
        continue;
      }
      auto pumped = pump(std::min<std::chrono::milliseconds>(left, 50ms));
      if (!pumped) {
        link_error = pumped.error();
        break;
      }
    }
    clear();
    if (pending.done) {
      if (pending.error) return *pending.error;
      return std::move(pending.values);
    }
    if (link_error) return *link_error;
  }
  const std::string who = options_.address ? " at address '" + address_text(*options_.address) + "'" : std::string();
  return make_error(Errc::timeout, "no reply to $" + std::string(command.mnemonic) + " from " + options_.source + who +
                                       " within " + std::to_string(timeout.count()) +
                                       " ms (check the port, the baud rate and the address)");
}

Result<std::vector<std::string>> Driver::get(std::string_view mnemonic, std::span<const std::string_view> arguments) {
  const CommandInfo* command = find_command(mnemonic);
  if (command == nullptr)
    return make_error(Errc::unknown_command, "unknown ULS command '" + std::string(mnemonic) + "'");
  if (!command->has_get() || request_form(*command, arguments.size()).form != RequestForm::get)
    return local_refusal(*command, "", 1, Units::metres);
  if (auto checked = check_locally(*command, arguments); !checked) return checked.error();
  if (command->mnemonic == "BM")
    return make_error(Errc::wrong_form, "use measure() for BM: its reply is a measurement");
  return transact(*command, arguments, Expect::value, 1 + options_.read_retries, options_.timeout);
}

Status Driver::set(std::string_view mnemonic, std::span<const std::string_view> values) {
  const CommandInfo* command = find_command(mnemonic);
  if (command == nullptr)
    return make_error(Errc::unknown_command, "unknown ULS command '" + std::string(mnemonic) + "'");
  if (!command->has_set()) return local_refusal(*command, join(values), 1, Units::metres);
  if (values.empty()) return make_error(Errc::wrong_form, std::string(command->mnemonic) + ": a set needs a value");
  if (auto checked = check_locally(*command, values); !checked) return checked.error();
  if (command->mnemonic == "BR" && values.size() == 1)
    return make_error(Errc::wrong_form, "BR: a set needs the port and the baud");
  auto done = transact(*command, values, Expect::ok, 1, options_.timeout);
  if (!done) return done.error();
  if (command->mnemonic == "MU") {
    std::lock_guard lock(state_mutex_);
    units_.reset();
  }
  if (changes_context(command->mnemonic)) {
    std::lock_guard lock(state_mutex_);
    context_known_ = false;  // read again before the next line is decoded (U85)
    unit_contexts_.erase(context_key(options_.address));
  }
  return ok_status();
}

Status Driver::set(std::string_view mnemonic, std::string_view value) {
  const std::array<std::string_view, 1> values{value};
  return set(mnemonic, values);
}

Status Driver::action(std::string_view mnemonic) {
  const CommandInfo* command = find_command(mnemonic);
  if (command == nullptr)
    return make_error(Errc::unknown_command, "unknown ULS command '" + std::string(mnemonic) + "'");
  if (command->access != Access::action)
    return make_error(Errc::wrong_form, std::string(command->mnemonic) + " is not an action (GO, ST, SU)");
  auto done = transact(*command, {}, Expect::ok, 1, options_.timeout);
  if (!done) return done.error();
  return ok_status();
}

Status Driver::broadcast(std::string_view mnemonic, std::span<const std::string_view> values, std::uint8_t address) {
  const CommandInfo* command = find_command(mnemonic);
  if (command == nullptr)
    return make_error(Errc::unknown_command, "unknown ULS command '" + std::string(mnemonic) + "'");
  if (address < first_broadcast_address) return make_error(Errc::out_of_range, "broadcast addresses are 0xF0..0xFF");
  const FormResult form = request_form(*command, values.size());
  if (form.form == RequestForm::get && command->access != Access::action && command->mnemonic != "BM")
    return make_error(Errc::wrong_form,
                      "a broadcast gets no reply, so it cannot read " + std::string(command->mnemonic));
  if (auto checked = check_locally(*command, values); !checked) return checked.error();
  const Address to = Address::broadcast(address);
  Result<FrameText> frame =
      values.empty() ? encode_action(to, command->mnemonic) : encode_set(to, command->mnemonic, values);
  if (command->mnemonic == "BM") frame = encode_get(to, "BM");
  if (!frame) return frame.error();
  std::lock_guard request_lock(request_mutex_);
  auto written = write_frame(frame->bytes());
  if (written && changes_context(command->mnemonic)) {
    std::lock_guard lock(state_mutex_);
    context_known_ = false;  // read again before the next line is decoded (U85)
    unit_contexts_.clear();  // every unit heard it
  }
  return written;
}

Result<Units> Driver::cached_units() {
  {
    std::lock_guard lock(state_mutex_);
    if (units_) return *units_;
  }
  const CommandInfo* command = find_command("MU");
  auto values = transact(*command, {}, Expect::value, 1 + options_.read_retries, options_.timeout);
  if (!values) return values.error();
  const auto units = values->size() == 1 ? to_units(text::parse_unsigned((*values)[0], 1).value_or(9)) : std::nullopt;
  if (!units) return make_error(Errc::invalid_frame, "MU reply is not 0 or 1");
  std::lock_guard lock(state_mutex_);
  units_ = *units;
  return *units;
}

}  // namespace rangekit::uls
