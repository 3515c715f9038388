// The soft limit of open descriptors raised to the hard one.
#pragma once

namespace rangekit {

// Every client, stream, sensor port, capture and broker session holds a descriptor, and the
// soft limit is often 1024: raised to the hard one, so that the service's own limits run out
// first. False when the limits could not be read or set.
bool raise_descriptor_limit() noexcept;

}  // namespace rangekit
