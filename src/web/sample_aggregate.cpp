#include "web/sample_aggregate.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include "rangekit/record/format.hpp"

namespace rangekit::web {
namespace {

std::string number_text(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.6g", value);
  return buffer.data();
}

}  // namespace

std::optional<std::pair<double, const char*>> plotted_value(const Sample& sample) {
  if (sample.distance_m) return std::pair{*sample.distance_m, "m"};
  if (!sample.targets.empty()) return std::pair{sample.targets.front().distance_m, "m"};
  if (sample.distance_mm) return std::pair{*sample.distance_mm, "mm"};
  if (sample.derivative_mm) return std::pair{*sample.derivative_mm, "mm"};
  return std::nullopt;
}

void SampleAggregate::add(const Sample& sample, std::uint64_t id) {
  last_id_ = id;
  time_ = sample.time;
  ++count_;
  const auto value = plotted_value(sample);
  if (!value) {
    ++gaps_;
    return;
  }
  if (sample.suspect) {
    ++suspect_;
    return;
  }
  ++valued_;
  min_ = valued_ == 1 ? value->first : std::min(min_, value->first);
  max_ = valued_ == 1 ? value->first : std::max(max_, value->first);
  last_ = value->first;
  unit_ = value->second;
}

void SampleAggregate::append_event(std::string& out, std::string_view sensor) {
  std::string time;
  record::append_iso_time(time, time_);
  const std::string id = std::to_string(last_id_);
  out += "id: ";
  out += id;
  out += "\nevent: aggregate\ndata: {\"id\":";
  out += id;
  out += ",\"sensor\":\"";
  out += sensor;
  out += "\",\"type\":\"aggregate\",\"data\":{\"time\":\"";
  out += time;
  out += "\",\"count\":";
  out += std::to_string(count_);
  out += ",\"gaps\":";
  out += std::to_string(gaps_);
  out += ",\"suspect\":";
  out += std::to_string(suspect_);
  if (valued_ > 0) {
    out += ",\"min\":" + number_text(min_) + ",\"max\":" + number_text(max_) + ",\"last\":" + number_text(last_) +
           ",\"unit\":\"" + unit_ + "\"";
  }
  out += "}}\n\n";
  *this = SampleAggregate{};
}

}  // namespace rangekit::web
