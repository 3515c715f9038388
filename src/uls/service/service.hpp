// The ULS's parts of the sensor service, private to its service library: the backends that
// run a port (one unit, or an RS-485 bus of them) and the settings schema.
#pragma once

#include <memory>
#include <vector>

#include "rangekit/hub/service_family.hpp"

namespace rangekit::uls::service {

std::unique_ptr<hub::Backend> make_port_backend(std::vector<hub::Session*> sessions, hub::Publisher& publisher,
                                                const hub::PortOpener& open);
nlohmann::json settings_schema();

}  // namespace rangekit::uls::service
