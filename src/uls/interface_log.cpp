#include "rangekit/uls/interface_log.hpp"
#include "rangekit/uls/family.hpp"

#include <array>
#include <cstdio>

namespace rangekit::uls {
namespace {

std::string log_metres(double value) {
  std::array<char, 32> buffer{};
  std::snprintf(buffer.data(), buffer.size(), "%.3f", value);  // the ULS's millimetre resolution (§8)
  return buffer.data();
}

// §2 File Menu: "The content of the capture file varies depending upon the measurement mode".
const char* column_line(SampleKind mode) {
  switch (mode) {
    case kind::binning:
      return "Time (H:M:S:mS), Index value in array, Number of Targets, Distance, Units\n";
    case kind::look_down:
      return "Time (H:M:S:mS), ON/OFF\n";
    default:
      return "Time (H:M:S:mS), Distance, Units, Intensity\n";
  }
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
    return make_error(Errc::unsupported, "the .log layout is the ULS Interface Program's; a " + sample.device +
                                             " capture downloads as sqlite, csv or jsonl");
  }
  // An error keeps the mode's columns; one before any measurement gets the factory mode's
  // (averaging, U35), so that every file starts with its column line (U121).
  const SampleKind mode = sample.kind == kind::error ? columns_.value_or(kind::averaging) : sample.kind;
  if (mode != columns_) {
    columns_ = mode;
    out += column_line(mode);
  }
  const auto start = [&] {
    append_log_time(out, sample.time);
    out += ", ";
  };
  switch (sample.kind) {
    case kind::averaging:
      start();
      out +=
          (sample.get(channel::distance_m) ? log_metres(*sample.get(channel::distance_m)) : std::string()) + ", m, " +
          (sample.get(channel::pulse_width_ps) ? std::to_string(*sample.get(channel::pulse_width_ps)) : std::string()) +
          "\n";
      break;
    case kind::binning:
      // §8 Binning Mode: the targets "always starting with index 0", as the wire numbers them.
      for (std::size_t i = 0; i < sample.targets.size(); ++i) {
        start();
        out += std::to_string(i) + ", " + std::to_string(sample.targets.size()) + ", " +
               log_metres(sample.targets[i].distance_m) + ", m\n";
      }
      break;
    case kind::look_down:
      if (!sample.get(channel::presence)) break;  // a time between events alone has no ON/OFF column (U100)
      start();
      out += *sample.get(channel::presence) ? "ON\n" : "OFF\n";
      break;
    case kind::error:
      start();
      out += "ERROR " + std::to_string(sample.get(channel::error).value_or(0)) + "\n";  // §2 gives no column (U100)
      break;
    default:
      break;
  }
  return ok_status();
}

std::unique_ptr<SampleWriter> make_interface_log_writer() { return std::make_unique<InterfaceLogWriter>(); }

}  // namespace rangekit::uls
