// Stream sinks that write JSON lines, CSV or readable text to a file or to
// standard output. Lines are buffered and written with write(2) on flush() or
// when the buffer fills, so a failure (disk full, closed pipe) is reported as
// Errc::io naming the file, and everything written before it stays written.
#pragma once

#include <string>

#include "rangekit/record/sink.hpp"

namespace rangekit::record {

// Opens (truncates) `path` for the stream; "" or "-" means standard output.
Result<SampleSinkPtr> open_text_sink(OutputFormat format, const std::string& path);

// A sink on an open descriptor it does not own; `name` is used in error messages.
SampleSinkPtr make_text_sink(OutputFormat format, int fd, std::string name);

}  // namespace rangekit::record
