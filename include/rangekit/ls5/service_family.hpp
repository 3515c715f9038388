// The LS5's part of the sensor service (rangekit::ls5_service): its site-file keys, backends
// and settings schema, as the hub reads them.
#pragma once

#include "rangekit/hub/service_family.hpp"

namespace rangekit::ls5::service {

const hub::ServiceFamily& service_family() noexcept;

}  // namespace rangekit::ls5::service
