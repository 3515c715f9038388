// A file layout that samples are written into one after another, keeping what it needs between
// them (a column line when the mode changes): a family's own capture file, as the ULS's .log.
#pragma once

#include <string>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"

namespace rangekit {

class SampleWriter {
 public:
  SampleWriter() = default;
  SampleWriter(const SampleWriter&) = delete;
  SampleWriter& operator=(const SampleWriter&) = delete;
  virtual ~SampleWriter() = default;
  // Appends the sample's lines; an error names what the layout cannot hold.
  virtual Status append(std::string& out, const Sample& sample) = 0;
};

}  // namespace rangekit
