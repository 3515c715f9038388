// The postgres kind: rows COPYed (text format) into a session's staging table, then moved into
// the sink's table in the same transaction, skipping keys it holds; confirmed at COMMIT.
#pragma once

#include <memory>

#include "sinks/writer.hpp"

namespace rangekit::sinks {

// Reads the password (password_file or password_env) and checks the URL here, so a setting
// that cannot work stops the start; the database itself is reached at the first write.
Result<std::unique_ptr<Writer>> open_postgres_writer(const SinkOptions& options);

}  // namespace rangekit::sinks
