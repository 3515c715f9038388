// The actions a sensor takes: those every family shares, then its family's own.
#include <array>
#include <string>

#include "rangekit/hub/hub.hpp"
#include "rangekit/hub/service_family.hpp"

namespace rangekit::hub {
namespace {

// What the hub and every backend do alike: the stream on or off, the settings read again.
constexpr std::array shared_actions{
    ActionDescriptor{"start", "measure and stream", {}},
    ActionDescriptor{"stop", "stop streaming and measuring", {}},
    ActionDescriptor{"read", "read every setting again", {}},
};

}  // namespace

std::vector<const ActionDescriptor*> actions_of(std::string_view family) {
  const ServiceFamily* service = find_service_family(family);
  std::vector<const ActionDescriptor*> all;
  all.reserve(shared_actions.size() + (service != nullptr ? service->actions.size() : 0));
  for (const ActionDescriptor& action : shared_actions) all.push_back(&action);
  if (service != nullptr) {
    for (const ActionDescriptor& action : service->actions) all.push_back(&action);
  }
  return all;
}

const ActionDescriptor* find_action(std::string_view family, std::string_view name) {
  for (const ActionDescriptor* action : actions_of(family)) {
    if (action->name == name) return action;
  }
  return nullptr;
}

std::string action_names(std::string_view family) {
  std::string names;
  for (const ActionDescriptor* action : actions_of(family)) {
    names += (names.empty() ? "" : ", ") + std::string(action->name);
  }
  return names;
}

std::string not_an_action(std::string_view family, std::string_view sensor, std::string_view action) {
  return "'" + std::string(action) + "' is not an action of " + std::string(family) + " sensor '" +
         std::string(sensor) + "' (" + action_names(family) + ")";
}

Status check_argument(const ActionDescriptor& action, std::string_view argument) {
  if (argument.empty() && (action.arguments.empty() || action.argument_optional)) return ok_status();
  std::string takes;
  for (const std::string_view value : action.arguments) {
    if (value == argument) return ok_status();
    takes += (takes.empty() ? "" : " or ") + std::string(value);
  }
  if (action.arguments.empty()) {
    return make_error(Errc::out_of_range,
                      std::string(action.name) + " takes no argument, not '" + std::string(argument) + "'");
  }
  if (argument.empty())
    return make_error(Errc::out_of_range, std::string(action.name) + " needs an argument: " + takes);
  if (action.argument_optional) takes = "none or " + takes;
  return make_error(Errc::out_of_range,
                    std::string(action.name) + " takes " + takes + ", not '" + std::string(argument) + "'");
}

}  // namespace rangekit::hub
