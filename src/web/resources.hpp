// The handlers the route table (web/routes.cpp) names, one group of resources per file:
// resources_health.cpp, resources_families.cpp, resources_sensors.cpp, resources_captures.cpp,
// resources_events.cpp, and static_files.cpp for the dashboard's files.
#pragma once

#include "web/exchange.hpp"
#include "web/routes.hpp"

namespace rangekit::web {

// GET /healthz, GET /metrics, GET /api/sinks.
void get_health(Exchange& exchange, const Matched& matched);
void get_metrics(Exchange& exchange, const Matched& matched);
void list_sinks(Exchange& exchange, const Matched& matched);

// GET /api/families: the registered families' descriptors.
void list_families(Exchange& exchange, const Matched& matched);

// /api/sensors and what lies under one sensor, but for its samples and events.
void list_sensors(Exchange& exchange, const Matched& matched);
void get_sensor(Exchange& exchange, const Matched& matched);
void get_settings(Exchange& exchange, const Matched& matched);
void patch_settings(Exchange& exchange, const Matched& matched);
void get_settings_schema(Exchange& exchange, const Matched& matched);
void post_action(Exchange& exchange, const Matched& matched);
void export_config(Exchange& exchange, const Matched& matched);
void import_config(Exchange& exchange, const Matched& matched);
void scan_bus(Exchange& exchange, const Matched& matched);
void assign_address(Exchange& exchange, const Matched& matched);
void no_such_bus_call(Exchange& exchange, const Matched& matched);

// /api/captures.
void list_captures(Exchange& exchange, const Matched& matched);
void start_capture(Exchange& exchange, const Matched& matched);
void get_capture(Exchange& exchange, const Matched& matched);
void stop_capture(Exchange& exchange, const Matched& matched);
void download_capture(Exchange& exchange, const Matched& matched);

// The sensors' items: a page of the ring, and the SSE streams of one sensor or of all.
void get_samples(Exchange& exchange, const Matched& matched);
void get_sensor_events(Exchange& exchange, const Matched& matched);
void get_all_events(Exchange& exchange, const Matched& matched);

// Any other path outside /api: the dashboard's page and files.
void get_static_file(Exchange& exchange, const Matched& matched);

}  // namespace rangekit::web
