#include "web/json_views.hpp"

#include <variant>

#include "rangekit/record/format.hpp"

namespace rangekit::web {

nlohmann::json capture_json(const hub::CaptureInfo& capture) {
  std::string started;
  record::append_iso_time(started, capture.started);
  nlohmann::json out{{"id", capture.id},     {"sensors", capture.sensors}, {"active", capture.active},
                     {"started", started},   {"samples", capture.samples}, {"events", capture.events},
                     {"lost", capture.lost}, {"error", capture.error},     {"stopped", nullptr}};
  if (capture.stopped) {
    std::string stopped;
    record::append_iso_time(stopped, *capture.stopped);
    out["stopped"] = stopped;
  }
  nlohmann::json links = nlohmann::json::object();
  for (const char* format : {"sqlite", "csv", "jsonl", "log"}) {
    links[format] = "/api/captures/" + capture.id + "/download?format=" + format;
  }
  out["download"] = links;
  return out;
}

const char* item_type(const hub::HubItem& item) {
  return std::holds_alternative<Sample>(item.item) ? "sample" : "event";
}

std::string item_json(const hub::HubItem& item) {
  std::string data;
  std::visit([&](const auto& value) { record::append_jsonl(data, value); }, item.item);
  if (!data.empty() && data.back() == '\n') data.pop_back();
  std::string out = "{\"id\":" + std::to_string(item.sequence) + ",\"sensor\":\"" + item.sensor + "\",\"type\":\"" +
                    item_type(item) + "\",\"data\":";
  out += data;
  out += '}';
  return out;
}

}  // namespace rangekit::web
