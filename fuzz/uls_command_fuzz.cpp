// Fuzzes the ULS command path: a frame -> parse_frame -> command table checks;
// whatever parses must encode back to a frame that frames and parses the same.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "rangekit/core/text.hpp"
#include "rangekit/uls/uls.hpp"

namespace {

using namespace rangekit;
using namespace rangekit::uls;

bool same_mnemonic(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (text::to_upper(a[i]) != text::to_upper(b[i])) return false;
  }
  return true;
}

bool same_fields(const FrameView& a, const FrameView& b) {
  if (a.field_count != b.field_count) return false;
  for (std::size_t i = 0; i < a.field_count; ++i) {
    if (a.fields()[i] != b.fields()[i]) return false;
  }
  return true;
}

// Upper-case hex letters alone read as an event (U26): "$beef" parses as a
// mnemonic but cannot be written back.
bool lower_case_event_look_alike(const FrameView& view) {
  if (view.field_count != 0 || view.mnemonic.size() != 4) return false;
  for (const char c : view.mnemonic) {
    const char upper = text::to_upper(c);
    if (upper < 'A' || upper > 'F') return false;
  }
  return true;
}

void check_commands(const FrameView& view) {
  const CommandInfo* command = find_command(view.mnemonic);
  Verdict verdicts[2];
  for (const Units units : {Units::feet, Units::metres}) {
    const Verdict verdict = validate_request(view.mnemonic, view.fields(), units);
    verdicts[static_cast<int>(units)] = verdict;
    if (!verdict.ok() && find_error(verdict.error) == nullptr) __builtin_trap();  // only §10 numbers
  }
  if (command == nullptr) {
    if (verdicts[0].error != 1) __builtin_trap();  // unknown mnemonic: error 1
    return;
  }
  const FormResult form = request_form(*command, view.field_count);
  if (form.verdict.ok()) {
    const Verdict measuring = check_while_measuring(*command, form.form, true);
    if (!measuring.ok() && measuring.error != 31) __builtin_trap();
  }
}

void check_round_trip(const FrameView& view) {
  if (view.kind == FrameKind::time_between_events) {
    TimeBetweenEvents event{TimeBetweenEvents::Kind::no_presence, 0};
    if (view.event_text != "0") {
      const auto pulses = text::parse_hex(view.event_text, 4);
      if (!pulses) __builtin_trap();
      event = tbe_from_pulses(*pulses);
    }
    const Result<FrameText> written = encode_time_between_events(view.address, event);
    if (!written || written->frame().substr(view.address.addressed ? 2 : 1) != view.event_text) __builtin_trap();
    return;
  }
  const Result<FrameText> written = encode_frame(view.address, view.mnemonic, view.fields());
  if (!written) {
    if (lower_case_event_look_alike(view)) return;
    __builtin_trap();
  }
  // The written frame must frame as exactly one complete frame and parse the same.
  const FrameScan scan = scan_frame(written->bytes());
  if (scan.status != FrameStatus::complete || scan.consumed != written->size()) __builtin_trap();
  const Result<FrameView> again = parse_frame(scan.frame);
  if (!again || !(again->address == view.address) || again->kind != view.kind ||
      !same_mnemonic(again->mnemonic, view.mnemonic) || !same_fields(*again, view)) {
    __builtin_trap();
  }
  for (const Units units : {Units::feet, Units::metres}) {
    if (!(validate_request(again->mnemonic, again->fields(), units) ==
          validate_request(view.mnemonic, view.fields(), units))) {
      __builtin_trap();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Bytes input(data, size);
  const Result<FrameView> view = parse_frame(input);
  if (view) {
    check_commands(*view);
    check_round_trip(*view);
  } else if (view.error().message.empty()) {
    __builtin_trap();
  }
  const Result<FrameView> wire = parse_wire_frame(input);
  if (wire) {
    check_commands(*wire);
    check_round_trip(*wire);
  }
  return 0;
}
