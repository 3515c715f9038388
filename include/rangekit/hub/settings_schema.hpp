// The settings a ULS takes, for a page that checks values before it sends them.
#pragma once

#include <nlohmann/json.hpp>

namespace rangekit::hub {

// Every setting of §8's command table (the CLI's registry) under the name `get` prints,
// with the range a value must keep in the unit of that name, the §10 number a unit
// answers outside it, and the named values; plus §10's table of errors.
nlohmann::json uls_settings_schema();

}  // namespace rangekit::hub
