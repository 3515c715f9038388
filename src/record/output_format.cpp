#include <string>

#include "rangekit/record/sink.hpp"

namespace rangekit::record {

Result<OutputFormat> parse_output_format(std::string_view name) {
  if (name == "jsonl") return OutputFormat::jsonl;
  if (name == "csv") return OutputFormat::csv;
  if (name == "text") return OutputFormat::text;
  return make_error(Errc::out_of_range, "unknown output format '" + std::string(name) + "' (jsonl, csv or text)");
}

const char* output_format_name(OutputFormat format) noexcept {
  switch (format) {
    case OutputFormat::jsonl:
      return "jsonl";
    case OutputFormat::csv:
      return "csv";
    case OutputFormat::text:
      return "text";
  }
  return "unknown";
}

}  // namespace rangekit::record
