// Where samples go: a text stream (JSON lines, CSV, readable text) or a SQLite
// capture. Every sink is written from one thread; flush() makes what was
// written durable (for a capture: the current batch is committed).
#pragma once

#include <memory>
#include <string_view>

#include "rangekit/core/result.hpp"
#include "rangekit/core/sample.hpp"

namespace rangekit::record {

enum class OutputFormat { jsonl, csv, text };

// "jsonl", "csv" or "text"; anything else is Errc::out_of_range naming the choices.
Result<OutputFormat> parse_output_format(std::string_view name);
const char* output_format_name(OutputFormat format) noexcept;

class SampleSink {
 public:
  SampleSink() = default;
  SampleSink(const SampleSink&) = delete;
  SampleSink& operator=(const SampleSink&) = delete;
  virtual ~SampleSink() = default;

  virtual Status write(const Sample& sample) = 0;
  // Events (disconnects, lost records) are recorded where the sink can hold them.
  virtual Status write_event(const StreamEvent& event) = 0;
  virtual Status flush() = 0;
};

using SampleSinkPtr = std::unique_ptr<SampleSink>;

}  // namespace rangekit::record
