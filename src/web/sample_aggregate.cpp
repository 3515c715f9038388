#include "web/sample_aggregate.hpp"

#include <array>
#include <cstdio>

#include "rangekit/core/family.hpp"
#include "rangekit/record/format.hpp"

namespace rangekit::web {
namespace {

std::string number_text(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.6g", value);
  return buffer.data();
}

}  // namespace

void SampleAggregate::add(const Sample& sample, std::uint64_t id) {
  last_id_ = id;
  time_ = sample.time;
  ++count_;
  const auto reading = reading_of(sample);
  if (!reading) {
    ++gaps_;
  } else if (sample.suspect) {
    ++suspect_;
  } else {
    readings_.add(*reading);
  }
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
  if (!readings_.empty()) {
    out += ",\"min\":" + number_text(readings_.min()) + ",\"max\":" + number_text(readings_.max()) +
           ",\"last\":" + number_text(readings_.last()) + ",\"unit\":\"" + readings_.unit() + "\",\"channel\":\"";
    out += readings_.channel()->key;
    out += '"';
  }
  out += "}}\n\n";
  *this = SampleAggregate{};
}

}  // namespace rangekit::web
