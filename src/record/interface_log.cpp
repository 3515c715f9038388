#include "rangekit/record/interface_log.hpp"

#include <array>
#include <cstdio>

namespace rangekit::record {
namespace {

std::string metres(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.3f", value);  // the ULS's millimetre resolution (§8)
  return buffer.data();
}

}  // namespace

void append_log_time(std::string& out, std::chrono::system_clock::time_point time) {
  const auto since_midnight = time.time_since_epoch() % std::chrono::hours(24);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(since_midnight).count();
  std::array<char, 24> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%02lld:%02lld:%02lld:%03lld", static_cast<long long>(ms / 3600000),
                static_cast<long long>(ms / 60000 % 60), static_cast<long long>(ms / 1000 % 60),
                static_cast<long long>(ms % 1000));
  out += buffer.data();
}

Status InterfaceLogWriter::append(std::string& out, const Sample& sample) {
  if (sample.device != "uls") {
    return make_error(Errc::unsupported,
                      "the .log layout is the ULS Interface Program's; an LS5 capture downloads as sqlite, csv "
                      "or jsonl");
  }
  const int mode = static_cast<int>(sample.kind);
  if (mode != mode_ && sample.kind != SampleKind::uls_error) {
    mode_ = mode;
    switch (sample.kind) {
      case SampleKind::uls_binning:
        out += "Time (H:M:S:mS), Index value in array, Number of Targets, Distance, Units\n";
        break;
      case SampleKind::uls_look_down:
        out += "Time (H:M:S:mS), ON/OFF\n";
        break;
      default:
        out += "Time (H:M:S:mS), Distance, Units, Intensity\n";
        break;
    }
  }
  const auto start = [&] {
    append_log_time(out, sample.time);
    out += ", ";
  };
  switch (sample.kind) {
    case SampleKind::uls_averaging:
      start();
      out += (sample.distance_m ? metres(*sample.distance_m) : std::string()) + ", m, " +
             (sample.pulse_width ? std::to_string(*sample.pulse_width) : std::string()) + "\n";
      break;
    case SampleKind::uls_binning:
      for (std::size_t i = 0; i < sample.targets.size(); ++i) {
        start();
        out += std::to_string(i + 1) + ", " + std::to_string(sample.targets.size()) + ", " +
               metres(sample.targets[i].distance_m) + ", m\n";
      }
      break;
    case SampleKind::uls_look_down:
      if (!sample.presence) break;  // a time between events alone has no ON/OFF column (U100)
      start();
      out += *sample.presence ? "ON\n" : "OFF\n";
      break;
    case SampleKind::uls_error:
      start();
      out +=
          "ERROR " + std::to_string(sample.device_error.value_or(0)) + "\n";  // U100: §2 gives no column; kept, marked
      break;
    default:
      break;
  }
  return ok_status();
}

}  // namespace rangekit::record
