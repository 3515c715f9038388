// The influx kind: Influx line protocol POSTed to InfluxDB 1.x /write, 2.x /api/v2/write or
// VictoriaMetrics; each row is idempotent there (same series and time: the same point).
#pragma once

#include <memory>

#include "sinks/writer.hpp"

namespace rangekit::sinks {

Result<std::unique_ptr<Writer>> open_influx_writer(const SinkOptions& options);

}  // namespace rangekit::sinks
