// The settings a ULS or an LS5 takes, for a page that checks values before it sends them.
#pragma once

#include <nlohmann/json.hpp>

namespace rangekit::hub {

// Every setting of §8's command table (the CLI's registry) under the name `get` prints,
// with the range a value must keep in the unit of that name, the §10 number a unit
// answers outside it, and the named values; plus §10's table of errors.
nlohmann::json uls_settings_schema();

// Every setting of LS5 table 9.2 under the name `rangekit ls5 get` prints (the host catalog,
// one row per value, not per byte): its parameter addresses, the range in the unit of that
// name and the step (period 0.1 ms, median points odd), the named values with table 9.2's
// meaning and the firmware each needs, whether it needs Ethernet, and whether it changes how
// the service reaches the sensor (address, baud rate, byte format: not written by the API).
nlohmann::json ls5_settings_schema();

}  // namespace rangekit::hub
