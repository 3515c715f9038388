// The ULS Interface Program's capture file (*.log, §2 File Menu): "The content of
// the capture file varies depending upon the measurement mode":
//   Averaging Mode: Time (H:M:S:mS), Distance, Units, Intensity.
//   Binning Mode: Time (H:M:S:mS), Index value in array, Number of Targets, Distance, Units.
//   Look Down Mode: (H:M:S:mS), ON/OFF.
// One comma-separated line per measurement (per target in binning), a column line
// whenever the mode changes. Times are UTC, distances metres. Decisions: U100.
#pragma once

#include <string>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"

namespace rangekit::record {

class InterfaceLogWriter {
 public:
  // Appends the lines of one ULS sample; Errc::unsupported for an LS5 sample (the
  // layout is the ULS program's).
  Status append(std::string& out, const Sample& sample);

 private:
  int mode_ = -1;  // the SampleKind whose column line was written last
};

// 13:04:05:123 (UTC), the §2 "H:M:S:mS".
void append_log_time(std::string& out, std::chrono::system_clock::time_point time);

}  // namespace rangekit::record
