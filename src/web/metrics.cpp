#include "web/metrics.hpp"

#include "web/sink_views.hpp"

namespace rangekit::web {
namespace {

// One metric family: its HELP and TYPE lines, then a value per sensor.
template <class Value>
void family(std::string& out, const char* name, const char* type, const char* help,
            const std::vector<hub::SensorSnapshot>& sensors, Value value) {
  out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  for (const hub::SensorSnapshot& sensor : sensors) {
    // Appended in place: g++ 12 reports a false -Warray-bounds on the chain of temporaries
    // that operator+ builds here (GCC bug 105651).
    out.append(name).append("{sensor=\"").append(sensor.config.name).append("\",family=\"");
    out.append(sensor.config.family).append("\"} ").append(value(sensor)).append("\n");
  }
}

std::string count(std::uint64_t value) { return std::to_string(value); }

}  // namespace

std::string prometheus_text(const hub::Hub& hub, const ServerStats& server, const std::vector<SinkHealth>& sinks) {
  const auto sensors = hub.sensors();
  std::string out;
  using S = const hub::SensorSnapshot&;
  family(out, "rangekit_sensor_connected", "gauge", "1 while the sensor's link is up.", sensors,
         [](S s) { return count(s.health.connected ? 1 : 0); });
  family(out, "rangekit_sensor_rate_hz", "gauge", "Samples a second over the last 2 s.", sensors,
         [](S s) { return std::to_string(s.health.rate_hz); });
  family(out, "rangekit_sensor_records_total", "counter", "Samples received.", sensors,
         [](S s) { return count(s.health.records); });
  family(out, "rangekit_sensor_device_errors_total", "counter", "Samples carrying a device error number.", sensors,
         [](S s) { return count(s.health.errors); });
  family(out, "rangekit_sensor_no_signal_total", "counter", "Samples in which the sensor saw no target (no signal).",
         sensors, [](S s) { return count(s.health.no_signal); });
  family(out, "rangekit_sensor_lost_total", "counter", "Records lost on the way (UDP gaps, full queues).", sensors,
         [](S s) { return count(s.health.lost); });
  family(out, "rangekit_sensor_bad_frames_total", "counter", "Bytes that did not decode, in frames.", sensors,
         [](S s) { return count(s.health.bad_frames); });
  family(out, "rangekit_sensor_disconnects_total", "counter", "Times the link went away.", sensors,
         [](S s) { return count(s.health.disconnects); });
  family(out, "rangekit_sensor_reconnects_total", "counter", "Times the link came back.", sensors,
         [](S s) { return count(s.health.reconnects); });
  out +=
      "# HELP rangekit_sensor_device_errors_by_number_total Device errors by the number the sensor sent.\n"
      "# TYPE rangekit_sensor_device_errors_by_number_total counter\n";
  for (const auto& sensor : sensors) {
    for (const auto& [number, total] : sensor.health.errors_by_number) {
      out += "rangekit_sensor_device_errors_by_number_total{sensor=\"" + sensor.config.name + "\",number=\"" +
             std::to_string(number) + "\"} " + count(total) + "\n";
    }
  }
  const auto server_metric = [&](const char* name, const char* type, const char* help, std::uint64_t value) {
    out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n" + name + " " +
           count(value) + "\n";
  };
  server_metric("rangekit_http_connections", "gauge", "HTTP connections open.", server.connections);
  server_metric("rangekit_http_streams", "gauge", "Server-Sent Events clients.", server.streams);
  server_metric("rangekit_http_requests_total", "counter", "HTTP requests served.", server.requests);
  server_metric("rangekit_http_refused_total", "counter", "Connections refused over the limit.", server.refused);
  server_metric("rangekit_http_streams_cut_off_total", "counter", "Stream clients cut off for falling behind.",
                server.streams_cut_off);
  append_sink_metrics(out, sinks);
  return out;
}

nlohmann::json health_json(const hub::Hub& hub, const std::vector<FaceHealth>& faces,
                           const std::vector<SinkHealth>& sinks) {
  const auto sensors = hub.sensors();
  nlohmann::json down = nlohmann::json::array();
  for (const auto& sensor : sensors) {
    if (!sensor.health.connected) down.push_back(sensor.config.name);
  }
  bool faces_ok = true;
  nlohmann::json out{{"sensors", sensors.size()}, {"connected", sensors.size() - down.size()}, {"disconnected", down}};
  for (const FaceHealth& face : faces) {
    nlohmann::json entry{{"ok", face.ok}, {"error", face.error}, {"connected", face.connected}, {"peer", face.peer}};
    for (const auto& [key, value] : face.counters) entry[key] = value;
    out[face.name] = entry;
    faces_ok = faces_ok && face.ok;
  }
  if (!sinks.empty()) {
    nlohmann::json listed = nlohmann::json::array();
    for (const SinkHealth& sink : sinks) {
      listed.push_back(sink_json(sink));
      faces_ok = faces_ok && !sink_down(sink);
    }
    out["sinks"] = listed;
  }
  out["status"] = down.empty() && faces_ok ? "ok" : "degraded";
  return out;
}

}  // namespace rangekit::web
