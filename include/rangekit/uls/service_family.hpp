// The ULS's part of the sensor service (rangekit::uls_service): its site-file keys, backends
// and settings schema, as the hub reads them.
#pragma once

#include "rangekit/hub/service_family.hpp"

namespace rangekit::uls::service {

const hub::ServiceFamily& service_family() noexcept;

}  // namespace rangekit::uls::service
