#include "web/json_views.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <variant>

#include "rangekit/core/family.hpp"
#include "rangekit/record/format.hpp"

namespace rangekit::web {
namespace {

// `"reading":{"channel":"distance_m","value":12.34,"unit":"m"}`: the one number the sample's
// family defines (core/family.hpp), rounded to its decimals; nothing for a gap.
void append_reading(std::string& out, const Sample& sample) {
  const auto reading = reading_of(sample);
  if (!reading || reading->channel == nullptr || !std::isfinite(reading->value)) return;
  std::array<char, 64> number{};
  const auto written =
      std::to_chars(number.data(), number.data() + number.size(), rounded_to(reading->value, reading->decimals));
  out += ",\"reading\":{\"channel\":\"";
  out += reading->channel->key;
  out += "\",\"value\":";
  out.append(number.data(), written.ptr);
  out += ",\"unit\":\"";
  out += unit_symbol(reading->channel->unit);
  out += "\"}";
}

}  // namespace

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
  if (const auto* sample = std::get_if<Sample>(&item.item)) append_reading(out, *sample);
  out += '}';
  return out;
}

}  // namespace rangekit::web
