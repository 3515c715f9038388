#include "rangekit/record/format.hpp"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "rangekit/core/family.hpp"

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

template <class... Args>
void append_printf(std::string& out, const char* format, Args... args) {
  char buffer[512];  // room for any double in %.4f
  const int length = std::snprintf(buffer, sizeof buffer, format, args...);
  if (length > 0)
    out.append(buffer,
               static_cast<std::size_t>(length) < sizeof buffer ? static_cast<std::size_t>(length) : sizeof buffer - 1);
}

void append_metres(std::string& out, double metres) { append_printf(out, "%.4f", metres); }

// As many decimals as the sensor's discreteness has (0.0001 mm: 4, 0.1 mm: 1; LS5
// table 3.1, L63); 2 when it is not known, which is how captures without it printed.
int millimetre_decimals(const Sample& sample) {
  const int decimals = sample.resolution_mm ? decimals_of_step(*sample.resolution_mm) : -1;
  return decimals < 0 ? 2 : std::min(decimals, 6);
}

// Appends millimetres with the sample's decimals; JSON has no NaN or infinity, so
// such a value is written as null.
struct Millimetres {
  int decimals;
  void operator()(std::string& out, double millimetres) const {
    if (std::isfinite(millimetres)) {
      append_printf(out, "%.*f", decimals, millimetres);
    } else {
      out += "null";
    }
  }
};
// JSON has no NaN or infinity: such a value is written as null.
void append_json_metres(std::string& out, double metres) {
  if (std::isfinite(metres)) {
    append_metres(out, metres);
  } else {
    out += "null";
  }
}
void append_unsigned(std::string& out, std::uint64_t value) { append_printf(out, "%" PRIu64, value); }
void append_signed(std::string& out, std::int64_t value) { append_printf(out, "%" PRId64, value); }

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

template <class T, class Append>
void append_json_optional(std::string& out, const std::optional<T>& value, Append append) {
  if (value) {
    append(out, *value);
  } else {
    out += "null";
  }
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

template <class T, class Append>
void append_csv_optional(std::string& out, const std::optional<T>& value, Append append) {
  if (value) append(out, *value);
}

void append_bool(std::string& out, bool value) { out += value ? "true" : "false"; }
void append_u32(std::string& out, std::uint32_t value) { append_unsigned(out, value); }
// Integer picoseconds (the wire's) as nanoseconds with 3 decimals: exact, no binary rounding.
void append_ps_as_ns(std::string& out, std::uint32_t picoseconds) {
  append_printf(out, "%" PRIu32 ".%03" PRIu32, picoseconds / 1000, picoseconds % 1000);
}
void append_int(std::string& out, int value) { append_signed(out, value); }
void append_u16(std::string& out, std::uint16_t value) { append_unsigned(out, value); }
void append_signal_json(std::string& out, SignalState state) {
  out += '"';
  out += signal_state_name(state);
  out += '"';
}
void append_signal_csv(std::string& out, SignalState state) { out += signal_state_name(state); }

void append_clock_time(std::string& out, std::chrono::system_clock::time_point time) {
  const auto civil = civil_utc(time);
  append_printf(out, "%02d:%02d:%02d.%03d", civil.fields.tm_hour, civil.fields.tm_min, civil.fields.tm_sec,
                civil.millis);
}

}  // namespace

void append_iso_time(std::string& out, std::chrono::system_clock::time_point time) {
  const auto civil = civil_utc(time);
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
  append_json_key(out, "kind");
  out += '"';
  out += sample_kind_name(sample.kind);
  out += '"';
  switch (sample.kind) {
    case SampleKind::uls_averaging:
      append_json_key(out, "distance_m");
      append_json_optional(out, sample.distance_m, append_json_metres);
      append_json_key(out, "pulse_width_ns");
      append_json_optional(out, sample.pulse_width, append_ps_as_ns);
      break;
    case SampleKind::uls_binning: {
      append_json_key(out, "targets");
      out += '[';
      bool first = true;
      for (const auto& target : sample.targets) {
        if (!first) out += ',';
        first = false;
        out += "{\"distance_m\":";
        append_json_metres(out, target.distance_m);
        out += ",\"strength\":";
        append_u32(out, target.strength);
        out += '}';
      }
      out += ']';
      break;
    }
    case SampleKind::uls_look_down:
      append_json_key(out, "presence");
      append_json_optional(out, sample.presence, append_bool);
      append_json_key(out, "pulses_between_events");
      append_json_optional(out, sample.pulses_between_events, append_u32);
      append_json_key(out, "pulses_overflow");
      append_bool(out, sample.pulses_overflow);
      break;
    case SampleKind::uls_error:
      append_json_key(out, "error");
      append_json_optional(out, sample.device_error, append_int);
      append_json_key(out, "error_text");
      if (sample.device_error) {
        append_json_string(out, error_text_of(sample, *sample.device_error));
      } else {
        out += "null";
      }
      break;
    case SampleKind::ls5_result:
    case SampleKind::ls5_derivative: {
      // The same record; only its value's meaning differs (formula 8.1 or 8.2, L60).
      const bool derivative = sample.kind == SampleKind::ls5_derivative;
      append_json_key(out, "code");
      append_json_optional(out, sample.code, append_u16);
      append_json_key(out, derivative ? "derivative_mm" : "distance_mm");
      append_json_optional(out, derivative ? sample.derivative_mm : sample.distance_mm,
                           Millimetres{millimetre_decimals(sample)});
      append_json_key(out, "signal");
      append_json_optional(out, sample.signal, append_signal_json);
      break;
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

const char* csv_header() noexcept {
  return "time,device,address,source,kind,distance_m,pulse_width_ns,targets,presence,pulses_between_events,error,code,"
         "distance_mm,signal,derivative_mm,pulses_overflow,error_text,suspect,suspect_reason\n";
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
  out += sample_kind_name(sample.kind);
  out += ',';
  append_csv_optional(out, sample.distance_m, append_metres);
  out += ',';
  append_csv_optional(out, sample.pulse_width, append_ps_as_ns);
  out += ',';
  bool first = true;
  for (const auto& target : sample.targets) {
    if (!first) out += ';';
    first = false;
    append_metres(out, target.distance_m);
    out += ':';
    append_u32(out, target.strength);
  }
  out += ',';
  append_csv_optional(out, sample.presence, append_bool);
  out += ',';
  append_csv_optional(out, sample.pulses_between_events, append_u32);
  out += ',';
  append_csv_optional(out, sample.device_error, append_int);
  out += ',';
  append_csv_optional(out, sample.code, append_u16);
  out += ',';
  const Millimetres millimetres{millimetre_decimals(sample)};
  append_csv_optional(out, sample.distance_mm, millimetres);
  out += ',';
  append_csv_optional(out, sample.signal, append_signal_csv);
  out += ',';
  append_csv_optional(out, sample.derivative_mm, millimetres);
  out += ',';
  if (sample.kind == SampleKind::uls_look_down) append_bool(out, sample.pulses_overflow);
  out += ',';
  if (sample.device_error) append_csv_text(out, error_text_of(sample, *sample.device_error));
  out += ',';
  append_bool(out, sample.suspect);
  out += ',';
  append_csv_text(out, sample.suspect_reason);
  out += '\n';
}

void append_text(std::string& out, const Sample& sample) {
  append_clock_time(out, sample.time);
  out += ' ';
  out += sample.device;
  if (sample.address >= 0) {  // as the family writes it, the site file's "A" for a bus unit
    out += ' ';
    out += address_text_of(sample.device, sample.address);
  }
  switch (sample.kind) {
    case SampleKind::uls_averaging:
      if (sample.distance_m) append_printf(out, "  %.3f m", *sample.distance_m);
      // Picoseconds on the wire (U8), shown in ns with its unit (U92).
      if (sample.pulse_width) {
        out += "  pw ";
        append_ps_as_ns(out, *sample.pulse_width);
        out += " ns";
      }
      break;
    case SampleKind::uls_binning:
      if (sample.targets.empty()) {
        out += "  no targets";
      }
      for (const auto& target : sample.targets) {
        append_printf(out, "  %.3f m (%" PRIu32 ")", target.distance_m, target.strength);
      }
      break;
    case SampleKind::uls_look_down:
      if (sample.presence) out += *sample.presence ? "  present" : "  absent";
      if (sample.pulses_between_events) append_printf(out, "  pulses %" PRIu32, *sample.pulses_between_events);
      if (sample.pulses_overflow) out += "  pulses >65535";
      break;
    case SampleKind::uls_error:
      out += "  error";
      if (sample.device_error) {
        append_printf(out, " %d: ", *sample.device_error);
        out += error_text_of(sample, *sample.device_error);  // the family's words: ULS §10 (U90)
      }
      break;
    case SampleKind::ls5_result:
    case SampleKind::ls5_derivative: {
      const bool derivative = sample.kind == SampleKind::ls5_derivative;
      const auto& value = derivative ? sample.derivative_mm : sample.distance_mm;
      if (derivative) out += "  derivative";
      if (value) {
        append_printf(out, derivative ? " %+.*f mm" : "  %.*f mm", millimetre_decimals(sample), *value);
      } else if (sample.signal == SignalState::none_yet) {
        out += "  no measurement yet";
      } else if (sample.signal == SignalState::lost) {
        out += "  no signal";
      }
      if (sample.code) append_printf(out, "  code %u", static_cast<unsigned>(*sample.code));
      break;
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
