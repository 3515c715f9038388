// What a sink kind does with a batch of spooled rows: writes it to its historian, and says
// whether the historian confirmed it, refused it for good, or could not be reached.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/record/spool.hpp"
#include "rangekit/sinks/sink.hpp"
#include "rangekit/sinks/sink_reading.hpp"

namespace rangekit::sinks {

struct WriteOutcome {
  enum class Kind {
    confirmed,  // the historian has the rows: they leave the spool
    refused,    // the historian will never take them (malformed): they leave the spool, counted
    failed,     // not written (down, refused the login, timed out): they wait, retried later
  };
  Kind kind = Kind::failed;
  std::string why;  // for refused and failed, in one line
};

class Writer {
 public:
  virtual ~Writer() = default;
  // Writes the rows, oldest first, each row's line as its kind encoded it. Rows sent before
  // (a crash after the write, before the spool forgot them) must not be doubled.
  virtual WriteOutcome write(const std::vector<record::SpoolRow>& rows) = 0;
};

// One sink kind: its name in [[sink]] kind, how it spools a row, and how it connects.
struct SinkKind {
  std::string_view name;
  RowEncoder encode;
  // A writer for the options' URL; an error for a URL or setting it cannot work with. It
  // must not fail because the historian is down (that is a failed write, later).
  Result<std::unique_ptr<Writer>> (*open)(const SinkOptions& options);
};

// Every kind this build has (sink_kinds.cpp); nullptr for a name none has.
const SinkKind* find_sink_kind(std::string_view name);
std::string sink_kind_names();  // "influx, postgres", for messages

}  // namespace rangekit::sinks
