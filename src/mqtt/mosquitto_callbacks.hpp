// libmosquitto's callbacks for one sensor's session: they run on the bridge's network
// thread and hand each event to the session's Link and the bridge.
#pragma once

#include <mosquitto.h>

namespace rangekit::mqtt {

// Sets the connect, disconnect, publish, subscribe and message callbacks of `client`,
// whose userdata is its Link.
void set_session_callbacks(mosquitto* client);

}  // namespace rangekit::mqtt
