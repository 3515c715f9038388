#include "rangekit/record/format.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <optional>
#include <string_view>
#include <vector>

#include "rangekit/core/family.hpp"
#include "rangekit/core/text.hpp"

namespace rangekit::record {
namespace {

using std::chrono::system_clock;

struct CivilTime {
  std::tm fields{};
  int millis = 0;
};

CivilTime civil_utc(system_clock::time_point time) {
  const auto since_epoch = std::chrono::duration_cast<std::chrono::milliseconds>(time.time_since_epoch());
  auto seconds = since_epoch.count() / 1000;
  auto millis = since_epoch.count() % 1000;
  if (millis < 0) {  // before 1970: floor, not truncate toward zero
    millis += 1000;
    --seconds;
  }
  CivilTime civil;
  const auto as_time_t = static_cast<std::time_t>(seconds);
  ::gmtime_r(&as_time_t, &civil.fields);
  civil.millis = static_cast<int>(millis);
  return civil;
}

using text::append_printf;

// Numbers by to_chars, the bytes printf writes without its format parsing: a sink formats
// every reading of its sensors.
template <class Integer>
void append_integer(std::string& out, Integer value) {
  std::array<char, 24> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  out.append(buffer.data(), end);
}
void append_unsigned(std::string& out, std::uint64_t value) { append_integer(out, value); }
void append_signed(std::string& out, std::int64_t value) { append_integer(out, value); }

// printf's %0*d for a value of at least 0.
void append_zero_padded(std::string& out, int value, int width) {
  std::array<char, 16> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  for (auto length = end - buffer.data(); length < width; ++length) out += '0';
  out.append(buffer.data(), end);
}

// printf's %.*f: to_chars with a precision writes what printf does in the C locale.
void append_fixed(std::string& out, double value, int decimals) {
  std::array<char, 64> buffer{};
  const auto [end, error] =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), value, std::chars_format::fixed, decimals);
  if (error == std::errc{}) {
    out.append(buffer.data(), end);
  } else {
    append_printf(out, "%.*f", decimals, value);  // longer than the buffer: a value far out of any range
  }
}

void append_json_string(std::string& out, const std::string& text) {
  out += '"';
  for (const char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          append_printf(out, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
        } else {
          out += c;
        }
    }
  }
  out += '"';
}

void append_json_key(std::string& out, const char* key) {
  out += ",\"";
  out += key;
  out += "\":";
}

// Quotes a CSV field only when it needs it (RFC 4180).
void append_csv_text(std::string& out, const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) {
    out += text;
    return;
  }
  out += '"';
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

void append_bool(std::string& out, bool value) { out += value ? "true" : "false"; }
void append_int(std::string& out, int value) { append_signed(out, value); }

// A value of the channel; JSON has no NaN or infinity, so such a value is written as null,
// and a state is a quoted name there.
void append_value(std::string& out, const ChannelDescriptor& channel, const Sample& sample, double value, bool json) {
  switch (channel.form) {
    case ChannelForm::flag:
      append_bool(out, value != 0);
      return;
    case ChannelForm::state: {
      const auto index = static_cast<std::size_t>(value);
      const std::string_view name = value >= 0 && index < channel.states.size() ? channel.states[index] : "unknown";
      if (json) out += '"';
      out += name;
      if (json) out += '"';
      return;
    }
    case ChannelForm::number:
    case ChannelForm::targets:
      break;
  }
  if (std::isfinite(value)) {
    append_fixed(out, value, channel_decimals(channel, sample));
  } else {
    out += "null";
  }
}

void append_json_targets(std::string& out, const TargetList& targets) {
  out += '[';
  bool first = true;
  for (const auto& target : targets) {
    if (!first) out += ',';
    first = false;
    out += "{\"distance_m\":";
    if (std::isfinite(target.distance_m)) {
      append_fixed(out, target.distance_m, 4);
    } else {
      out += "null";
    }
    out += ",\"strength\":";
    append_unsigned(out, target.strength);
    out += '}';
  }
  out += ']';
}

void append_csv_targets(std::string& out, const TargetList& targets) {
  bool first = true;
  for (const auto& target : targets) {
    if (!first) out += ';';
    first = false;
    append_printf(out, "%.4f:%" PRIu32, target.distance_m, target.strength);
  }
}

// The channel's value as a line of its kind shows it: its own, or the one it has when absent.
std::optional<double> shown_value(const ChannelDescriptor& channel, const Sample& sample, std::size_t index) {
  if (const auto value = sample.values.get(index)) return value;
  return channel.otherwise;
}

// The CSV columns between the sample's kind and error_text: every registered family's channels
// shown in the stream, in registration order, a key two families share once.
std::vector<std::string_view> csv_channel_keys() {
  std::vector<std::string_view> keys;
  for (const FamilyDescriptor* family : families()) {
    for (const ChannelDescriptor& channel : family->channels) {
      if (channel.in_stream && std::find(keys.begin(), keys.end(), channel.key) == keys.end()) {
        keys.push_back(channel.key);
      }
    }
  }
  return keys;
}

const std::vector<std::string_view>& csv_keys() {
  static const std::vector<std::string_view> keys = csv_channel_keys();
  return keys;
}

void append_clock_time(std::string& out, std::chrono::system_clock::time_point time) {
  const auto civil = civil_utc(time);
  append_printf(out, "%02d:%02d:%02d.%03d", civil.fields.tm_hour, civil.fields.tm_min, civil.fields.tm_sec,
                civil.millis);
}

}  // namespace

void append_iso_time(std::string& out, std::chrono::system_clock::time_point time) {
  const auto civil = civil_utc(time);
  if (civil.fields.tm_year >= -1900) {
    append_zero_padded(out, civil.fields.tm_year + 1900, 4);
    out += '-';
    append_zero_padded(out, civil.fields.tm_mon + 1, 2);
    out += '-';
    append_zero_padded(out, civil.fields.tm_mday, 2);
    out += 'T';
    append_zero_padded(out, civil.fields.tm_hour, 2);
    out += ':';
    append_zero_padded(out, civil.fields.tm_min, 2);
    out += ':';
    append_zero_padded(out, civil.fields.tm_sec, 2);
    out += '.';
    append_zero_padded(out, civil.millis, 3);
    out += 'Z';
    return;
  }
  append_printf(out, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", civil.fields.tm_year + 1900, civil.fields.tm_mon + 1,
                civil.fields.tm_mday, civil.fields.tm_hour, civil.fields.tm_min, civil.fields.tm_sec, civil.millis);
}

void append_jsonl(std::string& out, const Sample& sample) {
  out += "{\"time\":\"";
  append_iso_time(out, sample.time);
  out += '"';
  append_json_key(out, "device");
  append_json_string(out, sample.device);
  append_json_key(out, "address");
  if (sample.address < 0) {
    out += "null";
  } else {
    append_int(out, sample.address);
  }
  append_json_key(out, "source");
  append_json_string(out, sample.source.str());
  const FamilyDescriptor* family = family_of(sample);
  const KindDescriptor* kind = kind_of(family, sample);
  append_json_key(out, "kind");
  out += '"';
  out += kind_name_of(kind);
  out += '"';
  if (family != nullptr && kind != nullptr) {
    for (const std::uint8_t index : kind->channels) {
      const ChannelDescriptor& channel = family->channels[index];
      out += ",\"";
      out += channel.key;
      out += "\":";
      if (channel.form == ChannelForm::targets) {
        append_json_targets(out, sample.targets);
        continue;
      }
      const auto value = shown_value(channel, sample, index);
      if (value) {
        append_value(out, channel, sample, *value, true);
      } else {
        out += "null";
      }
      if (channel.quantity == Quantity::error_number) {
        append_json_key(out, "error_text");
        if (value) {
          append_json_string(out, error_text_of(sample, static_cast<int>(*value)));
        } else {
          out += "null";
        }
      }
    }
  }
  // Only a suspect sample carries the keys, so a clean stream's lines carry nothing extra.
  if (sample.suspect) {
    append_json_key(out, "suspect");
    append_bool(out, true);
    append_json_key(out, "suspect_reason");
    append_json_string(out, sample.suspect_reason);
  }
  out += "}\n";
}

void append_jsonl(std::string& out, const StreamEvent& event) {
  out += "{\"time\":\"";
  append_iso_time(out, event.time);
  out += '"';
  append_json_key(out, "event");
  out += '"';
  out += stream_event_kind_name(event.kind);
  out += '"';
  append_json_key(out, "message");
  append_json_string(out, event.message);
  append_json_key(out, "count");
  append_unsigned(out, event.count);
  out += "}\n";
}

std::string csv_header() {
  std::string header = "time,device,address,source,kind";
  for (const std::string_view key : csv_keys()) {
    header += ',';
    header += key;
  }
  header += ",error_text,suspect,suspect_reason\n";
  return header;
}

void append_csv(std::string& out, const Sample& sample) {
  append_iso_time(out, sample.time);
  out += ',';
  append_csv_text(out, sample.device);
  out += ',';
  if (sample.address >= 0) append_int(out, sample.address);
  out += ',';
  append_csv_text(out, sample.source.str());
  out += ',';
  const FamilyDescriptor* family = family_of(sample);
  const KindDescriptor* kind = kind_of(family, sample);
  out += kind_name_of(kind);
  std::optional<double> error_number;
  for (const std::string_view key : csv_keys()) {
    out += ',';
    if (family == nullptr) continue;
    const auto index = channel_index(*family, key);
    if (!index) continue;
    const ChannelDescriptor& channel = family->channels[*index];
    if (channel.form == ChannelForm::targets) {
      append_csv_targets(out, sample.targets);
      continue;
    }
    auto value = sample.values.get(*index);
    // The value an absent channel has is shown on the lines of kinds that list it.
    if (!value && kind != nullptr && kind->shows(*index)) {
      value = channel.otherwise;
    }
    if (!value) continue;
    append_value(out, channel, sample, *value, false);
    if (channel.quantity == Quantity::error_number) error_number = value;
  }
  out += ',';
  if (error_number) append_csv_text(out, error_text_of(sample, static_cast<int>(*error_number)));
  out += ',';
  append_bool(out, sample.suspect);
  out += ',';
  append_csv_text(out, sample.suspect_reason);
  out += '\n';
}

// The kind's channels as key=value, for a family without words of its own.
void append_channels_text(std::string& out, const FamilyDescriptor& family, const Sample& sample) {
  const KindDescriptor* kind = kind_of(&family, sample);
  if (kind == nullptr) return;
  for (const std::uint8_t index : kind->channels) {
    const ChannelDescriptor& channel = family.channels[index];
    const auto value = shown_value(channel, sample, index);
    if (!value && channel.form != ChannelForm::targets) continue;
    out += "  ";
    out += channel.key;
    out += '=';
    if (channel.form == ChannelForm::targets) {
      append_csv_targets(out, sample.targets);
    } else {
      append_value(out, channel, sample, *value, false);
    }
  }
}

void append_text(std::string& out, const Sample& sample) {
  append_clock_time(out, sample.time);
  out += ' ';
  out += sample.device;
  if (sample.address >= 0) {  // as the family writes it, the site file's "A" for a bus unit
    out += ' ';
    out += address_text_of(sample.device, sample.address);
  }
  if (const FamilyDescriptor* family = family_of(sample)) {
    if (family->append_text != nullptr) {
      family->append_text(out, sample);
    } else {
      append_channels_text(out, *family, sample);
    }
  }
  if (sample.suspect) {
    out += "  SUSPECT: ";
    out += sample.suspect_reason;
  }
  out += '\n';
}

void append_text(std::string& out, const StreamEvent& event) {
  append_clock_time(out, event.time);
  out += ' ';
  out += stream_event_kind_name(event.kind);
  if (!event.message.empty()) {
    out += ": ";
    out += event.message;
  }
  if (event.kind == StreamEventKind::lost_records) {
    out += " (";
    append_unsigned(out, event.count);
    out += " lost)";
  }
  out += '\n';
}

}  // namespace rangekit::record
