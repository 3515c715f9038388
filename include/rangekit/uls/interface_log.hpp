// The ULS Interface Program's capture file (*.log, §2 File Menu), the family's own capture
// layout (FamilyDescriptor::program_log): a column line per mode, then a line per measurement
// (per target in binning). Times are UTC, distances metres. Decisions: U100, U121.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "rangekit/core/sample_writer.hpp"

namespace rangekit::uls {

class InterfaceLogWriter final : public SampleWriter {
 public:
  // Appends the lines of one ULS sample; Errc::unsupported for another family's.
  Status append(std::string& out, const Sample& sample) override;

 private:
  std::optional<SampleKind> columns_;  // the mode whose column line was written last
};

std::unique_ptr<SampleWriter> make_interface_log_writer();

// 13:04:05:123 (UTC), the §2 "H:M:S:mS".
void append_log_time(std::string& out, std::chrono::system_clock::time_point time);

}  // namespace rangekit::uls
