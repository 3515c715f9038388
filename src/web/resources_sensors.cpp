// The sensors: their state, settings and schema, actions, configuration files and the
// RS-485 bus. Calls that wait for a sensor run off the loop (Exchange::off_loop).
#include <optional>
#include <string>

#include "web/resources.hpp"

namespace rangekit::web {

void list_sensors(Exchange& exchange, const Matched& /*matched*/) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& sensor : exchange.server().hub.sensors()) list.push_back(sensor_json(sensor));
  exchange.respond(http::status::ok,
                   nlohmann::json{{"sensors", list}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

void get_sensor(Exchange& exchange, const Matched& matched) {
  exchange.respond(http::status::ok,
                   sensor_json(*matched.sensor).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

void get_settings(Exchange& exchange, const Matched& matched) {
  nlohmann::json settings = sensor_json(*matched.sensor)["settings"];
  exchange.respond(http::status::ok, settings.dump());
}

void patch_settings(Exchange& exchange, const Matched& matched) {
  const SettingsBody body = settings_from_body(exchange.request().body());
  if (body.error) {
    return exchange.respond(http::status::bad_request, error_json("bad_body", body.error->message, body.error->field));
  }
  exchange.off_loop(
      [&hub = exchange.server().hub, name = matched.name, values = body.values] { return hub.set(name, values); },
      [self = exchange.shared_from_this(), name = matched.name,
       values = body.values](const Result<std::vector<hub::Field>>& result) {
        if (!result) return self->fail(result.error(), values);
        auto sensor = self->server().hub.sensor(name);
        self->respond(http::status::ok, sensor ? sensor_json(*sensor)["settings"].dump() : "{}");
      });
}

void get_settings_schema(Exchange& exchange, const Matched& matched) {
  const hub::ServiceFamily* family = hub::find_service_family(matched.sensor->config.family);
  if (family == nullptr || family->settings_schema == nullptr) {
    return exchange.respond(http::status::not_found, error_json("unsupported", "a " + matched.sensor->config.family +
                                                                                   " sensor has no settings schema"));
  }
  exchange.respond(http::status::ok, family->settings_schema().dump());
}

void post_action(Exchange& exchange, const Matched& matched) {
  const std::string& family = matched.sensor->config.family;
  if (hub::find_action(family, matched.action) == nullptr) {
    return exchange.respond(
        http::status::bad_request,
        error_json("unknown_action", hub::not_an_action(family, matched.name, matched.action), "action"));
  }
  std::string argument;
  if (const auto found = matched.target.query.find("argument"); found != matched.target.query.end()) {
    argument = found->second;
  }
  const std::string& body = exchange.request().body();
  if (!body.empty()) {
    const auto json = nlohmann::json::parse(body, nullptr, false);
    if (json.is_discarded() || !json.is_object() || (json.contains("argument") && !json["argument"].is_string())) {
      return exchange.respond(
          http::status::bad_request,
          error_json("bad_body", "an action's body is empty or {\"argument\": \"on\"}", "argument"));
    }
    argument = json.value("argument", argument);
  }
  exchange.off_loop([&hub = exchange.server().hub, name = matched.name, action = matched.action,
                     argument] { return hub.act(name, action, argument); },
                    [self = exchange.shared_from_this()](const Result<hub::ActionResult>& result) {
                      if (!result) return self->fail(result.error());
                      self->respond(http::status::ok, hub::action_json(*result).dump(
                                                          -1, ' ', false, nlohmann::json::error_handler_t::replace));
                    });
}

void export_config(Exchange& exchange, const Matched& matched) {
  exchange.off_loop([&hub = exchange.server().hub, name = matched.name] { return hub.export_config(name); },
                    [self = exchange.shared_from_this()](Result<std::string> result) {
                      if (!result) return self->fail(result.error());
                      self->respond(http::status::ok, std::move(*result), true, "application/toml");
                    });
}

void import_config(Exchange& exchange, const Matched& matched) {
  exchange.off_loop(
      [&hub = exchange.server().hub, name = matched.name, text = exchange.request().body()] {
        return hub.import_config(name, text);
      },
      [self = exchange.shared_from_this(), name = matched.name](const Result<std::vector<hub::Field>>& result) {
        if (!result) return self->fail(result.error());
        auto uploaded = self->server().hub.sensor(name);
        self->respond(http::status::ok, uploaded ? sensor_json(*uploaded)["settings"].dump() : "{}");
      });
}

// The RS-485 network (§7): who answers on the sensor's bus, and the site file's units there.
void scan_bus(Exchange& exchange, const Matched& matched) {
  exchange.off_loop(
      [&hub = exchange.server().hub, name = matched.name] { return hub.scan_bus(name); },
      [self = exchange.shared_from_this()](const Result<hub::BusScan>& result) {
        if (!result) return self->fail(result.error());
        nlohmann::json units = nlohmann::json::array();
        for (const hub::BusUnitFound& unit : result->found) {
          nlohmann::json entry{{"address", hub::bus_address_text(result->family, unit.address)},
                               {"code", unit.address},
                               {"version", unit.version},
                               {"duplicate", unit.duplicate},
                               {"problem", unit.problem},
                               {"sensor", nullptr}};
          for (const auto& [address, sensor] : result->site) {
            if (address == unit.address) entry["sensor"] = sensor;
          }
          units.push_back(std::move(entry));
        }
        nlohmann::json site = nlohmann::json::array();
        for (const auto& [address, sensor] : result->site) {
          site.push_back(
              {{"address", hub::bus_address_text(result->family, address)}, {"code", address}, {"sensor", sensor}});
        }
        self->respond(
            http::status::ok,
            nlohmann::json{{"port", result->port}, {"asked", result->asked}, {"units", units}, {"site", site}}.dump(
                -1, ' ', false, nlohmann::json::error_handler_t::replace));
      });
}

// Body {"to": "E"} or {"from": "C", "to": "E"} (a character, "0x45" or 69; `from` defaults to
// the sensor's address): UA, as `rangekit uls bus assign --from C --to E`.
void assign_address(Exchange& exchange, const Matched& matched) {
  const auto json = nlohmann::json::parse(exchange.request().body(), nullptr, false);
  const auto address_field = [&json](const char* key) {
    return json[key].is_string() || json[key].is_number_unsigned();
  };
  if (json.is_discarded() || !json.is_object() || !json.contains("to") || !address_field("to") ||
      (json.contains("from") && !address_field("from"))) {
    return exchange.respond(http::status::bad_request,
                            error_json("bad_body",
                                       "the body is {\"from\": \"C\", \"to\": \"E\"}: the unit's address now "
                                       "(default: the sensor's) and the new one",
                                       "to"));
  }
  const std::string& family = matched.sensor->config.family;
  std::optional<std::uint8_t> from;
  std::uint8_t to = 0;
  for (const char* key : {"from", "to"}) {
    if (!json.contains(key)) continue;
    const std::string text =
        json[key].is_string() ? json[key].get<std::string>() : std::to_string(json[key].get<std::uint64_t>());
    const auto address = hub::parse_bus_address(family, text);
    if (!address) {
      return exchange.respond(
          http::status::bad_request,
          error_json("out_of_range",
                     std::string(key) + ": '" + text + "' is not a unit address: " + hub::bus_address_help(family),
                     key));
    }
    if (std::string_view(key) == "to") {
      to = *address;
    } else {
      from = *address;
    }
  }
  exchange.off_loop(
      [&hub = exchange.server().hub, name = matched.name, from, to] { return hub.assign_address(name, from, to); },
      [self = exchange.shared_from_this(), to, family](const Status& result) {
        if (!result) return self->fail(result.error());
        const std::string address = hub::bus_address_text(family, to);
        self->respond(http::status::ok, nlohmann::json{{"result", "assigned " + address}, {"address", address}}.dump());
      });
}

void no_such_bus_call(Exchange& exchange, const Matched& /*matched*/) {
  exchange.not_found("no such path: /bus/scan or /bus/assign (see docs/api.md)");
}

}  // namespace rangekit::web
