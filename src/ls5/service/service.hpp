// The LS5's parts of the sensor service, private to its service library: the backends of a
// serial port and of a UDP listener, and the settings schema.
#pragma once

#include <memory>
#include <vector>

#include "rangekit/hub/service_family.hpp"

namespace rangekit::ls5::service {

std::unique_ptr<hub::Backend> make_port_backend(std::vector<hub::Session*> sessions, hub::Publisher& publisher,
                                                const hub::PortOpener& open);
std::unique_ptr<hub::Backend> make_udp_backend(hub::Session& session, hub::Publisher& publisher);
nlohmann::json settings_schema();

}  // namespace rangekit::ls5::service
