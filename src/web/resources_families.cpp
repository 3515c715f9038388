// GET /api/families: every registered family as its descriptors tell it, so a client (the
// dashboard) learns titles, channels and settings from the service instead of knowing them.
#include "rangekit/core/family.hpp"
#include "rangekit/hub/service_family.hpp"
#include "web/resources.hpp"

namespace rangekit::web {
namespace {

const char* form_name(ChannelForm form) {
  switch (form) {
    case ChannelForm::number:
      return "number";
    case ChannelForm::flag:
      return "flag";
    case ChannelForm::state:
      return "state";
    case ChannelForm::targets:
      return "targets";
  }
  return "number";
}

nlohmann::json channel_json(const ChannelDescriptor& channel) {
  nlohmann::json out{{"key", channel.key},
                     {"quantity", quantity_name(channel.quantity)},
                     {"unit", unit_symbol(channel.unit)},
                     {"description", channel.description},
                     {"form", form_name(channel.form)},
                     {"decimals", channel.decimals},
                     {"in_stream", channel.in_stream},
                     {"states", nlohmann::json::array()}};
  for (const std::string_view state : channel.states) out["states"].push_back(state);
  return out;
}

// Each kind of sample with the keys its line carries, in order.
nlohmann::json kinds_json(const FamilyDescriptor& family) {
  nlohmann::json kinds = nlohmann::json::array();
  for (const KindDescriptor& kind : family.kinds) {
    nlohmann::json keys = nlohmann::json::array();
    for (const std::uint8_t index : kind.channels) keys.push_back(family.channels[index].key);
    kinds.push_back({{"name", kind.name}, {"channels", keys}});
  }
  return kinds;
}

nlohmann::json family_json(const FamilyDescriptor& family) {
  nlohmann::json channels = nlohmann::json::array();
  for (const ChannelDescriptor& channel : family.channels) channels.push_back(channel_json(channel));
  nlohmann::json out{
      {"name", family.name}, {"title", family.title}, {"channels", channels}, {"kinds", kinds_json(family)}};
  // What the service adds, for a family it runs: the make, whether it shares a bus or is
  // heard over UDP, and its settings schema (as GET /api/sensors/{name}/settings/schema).
  if (const hub::ServiceFamily* service = hub::find_service_family(family.name)) {
    out["manufacturer"] = service->manufacturer;
    out["model"] = service->model;
    out["bus"] = service->bus;
    out["udp"] = service->udp;
    if (service->settings_schema != nullptr) out["settings_schema"] = service->settings_schema();
  }
  // POST /api/sensors/{name}/actions/{action}: what a sensor of the family does, with the
  // arguments each action takes (the dashboard's buttons, MQTT's action topic).
  nlohmann::json actions = nlohmann::json::array();
  for (const hub::ActionDescriptor* action : hub::actions_of(family.name)) {
    nlohmann::json entry{{"name", action->name}, {"description", action->description}};
    entry["arguments"] = nlohmann::json::array();
    for (const std::string_view value : action->arguments) entry["arguments"].push_back(value);
    entry["argument_optional"] = action->argument_optional || action->arguments.empty();
    actions.push_back(entry);
  }
  out["actions"] = actions;
  return out;
}

}  // namespace

void list_families(Exchange& exchange, const Matched& /*matched*/) {
  nlohmann::json list = nlohmann::json::array();
  for (const FamilyDescriptor* family : families()) list.push_back(family_json(*family));
  exchange.respond(http::status::ok,
                   nlohmann::json{{"families", list}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

}  // namespace rangekit::web
