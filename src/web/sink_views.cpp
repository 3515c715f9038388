#include "web/sink_views.hpp"

#include <cstdio>

namespace rangekit::web {
namespace {

// A label value of the text format: backslash, double quote and line feed escaped.
std::string label_value(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '\\' || c == '"') out += '\\';
    out += c == '\n' ? std::string("\\n") : std::string(1, c);
  }
  return out;
}

template <class Value>
void family(std::string& out, const char* name, const char* type, const char* help,
            const std::vector<SinkHealth>& sinks, Value value) {
  out.append("# HELP ").append(name).append(" ").append(help).append("\n");
  out.append("# TYPE ").append(name).append(" ").append(type).append("\n");
  for (const SinkHealth& sink : sinks) {
    out.append(name).append("{kind=\"").append(label_value(sink.kind)).append("\",url=\"");
    out.append(label_value(sink.url)).append("\"} ").append(value(sink)).append("\n");
  }
}

std::string sink_count(std::uint64_t value) { return std::to_string(value); }

std::string seconds(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", value);
  return text;
}

}  // namespace

nlohmann::json sink_json(const SinkHealth& sink) {
  return {{"kind", sink.kind},
          {"url", sink.url},
          {"up", sink.up},
          {"error", sink.error},
          {"written", sink.written},
          {"spooled", sink.spooled},
          {"spool_bytes", sink.spool_bytes},
          {"dropped", sink.dropped},
          {"rejected", sink.rejected},
          {"failures", sink.failures},
          {"oldest_age_s", sink.oldest_age_s}};
}

bool sink_down(const SinkHealth& sink) { return !sink.up && !sink.error.empty(); }

void append_sink_metrics(std::string& out, const std::vector<SinkHealth>& sinks) {
  if (sinks.empty()) return;
  using S = const SinkHealth&;
  family(out, "rangekit_sink_up", "gauge", "1 while the historian confirmed the sink's last write.", sinks,
         [](S s) { return sink_count(s.up ? 1 : 0); });
  family(out, "rangekit_sink_rows_written_total", "counter", "Rows the historian confirmed.", sinks,
         [](S s) { return sink_count(s.written); });
  family(out, "rangekit_sink_rows_spooled", "gauge", "Rows waiting in the spool.", sinks,
         [](S s) { return sink_count(s.spooled); });
  family(out, "rangekit_sink_spool_bytes", "gauge", "Size of the rows waiting in the spool.", sinks,
         [](S s) { return sink_count(s.spool_bytes); });
  family(out, "rangekit_sink_oldest_spooled_age_seconds", "gauge",
         "Age of the oldest row waiting in the spool; 0 when none waits.", sinks,
         [](S s) { return seconds(s.oldest_age_s); });
  family(out, "rangekit_sink_rows_dropped_total", "counter", "Rows lost past the spool's cap or the intake's queue.",
         sinks, [](S s) { return sink_count(s.dropped); });
  family(out, "rangekit_sink_rows_rejected_total", "counter", "Rows the historian refused as malformed (HTTP 400).",
         sinks, [](S s) { return sink_count(s.rejected); });
  family(out, "rangekit_sink_write_failures_total", "counter", "Writes that failed and were retried.", sinks,
         [](S s) { return sink_count(s.failures); });
}

}  // namespace rangekit::web
