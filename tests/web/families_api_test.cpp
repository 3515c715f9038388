// GET /api/families against the registries it reads (core/family.hpp, hub/service_family.hpp),
// and each sample item's reading against core's reading_of: the dashboard's only source of both.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hub/site_fixture.hpp"
#include "rangekit/core/family.hpp"
#include "rangekit/hub/service_family.hpp"
#include "rangekit/ls5/family.hpp"
#include "rangekit/web/server.hpp"
#include "web/http_client.hpp"
#include "web/json_views.hpp"

namespace {

using namespace rangekit;

TEST(WebFamilies, ListsEveryRegisteredFamilyAsItsDescriptorsSay) {
  // A hub with one sensor whose port does not exist: the families do not depend on the site.
  auto site = hub::parse_site_config(
      "[[sensor]]\nname = \"x\"\nfamily = \"ls5\"\nport = \"/nonexistent/rangekit-port\"\n", "site.toml");
  ASSERT_TRUE(site.ok());
  auto hub = hub::Hub::start(*site);
  web::ServerOptions options;
  options.listen = "127.0.0.1:0";
  auto server = web::Server::start(*hub, options);
  ASSERT_TRUE(server.ok());
  const auto reply = web_test::http((*server)->local_endpoint().port, "GET", "/api/families");
  ASSERT_EQ(reply.status, 200) << reply.body;
  const auto listed = nlohmann::json::parse(reply.body)["families"];

  const auto registered = families();
  ASSERT_EQ(listed.size(), registered.size());
  ASSERT_GE(registered.size(), 2U);
  for (std::size_t i = 0; i < registered.size(); ++i) {
    const FamilyDescriptor& family = *registered[i];
    const auto& json = listed[i];
    EXPECT_EQ(json["name"], family.name);
    EXPECT_EQ(json["title"], family.title);
    ASSERT_EQ(json["channels"].size(), family.channels.size()) << family.name;
    for (std::size_t c = 0; c < family.channels.size(); ++c) {
      const ChannelDescriptor& channel = family.channels[c];
      const auto& row = json["channels"][c];
      EXPECT_EQ(row["key"], channel.key);
      EXPECT_EQ(row["quantity"], quantity_name(channel.quantity));
      EXPECT_EQ(row["unit"], unit_symbol(channel.unit));
      EXPECT_EQ(row["description"], channel.description);
      EXPECT_EQ(row["in_stream"], channel.in_stream);
      EXPECT_EQ(row["states"].size(), channel.states.size()) << channel.key;
    }
    // Each kind with the keys its line carries: what a client reads a sample's line by.
    ASSERT_EQ(json["kinds"].size(), family.kinds.size()) << family.name;
    for (std::size_t k = 0; k < family.kinds.size(); ++k) {
      EXPECT_EQ(json["kinds"][k]["name"], family.kinds[k].name);
      ASSERT_EQ(json["kinds"][k]["channels"].size(), family.kinds[k].channels.size());
      for (std::size_t c = 0; c < family.kinds[k].channels.size(); ++c) {
        EXPECT_EQ(json["kinds"][k]["channels"][c], family.channels[family.kinds[k].channels[c]].key);
      }
    }
    const hub::ServiceFamily* service = hub::find_service_family(family.name);
    ASSERT_NE(service, nullptr) << family.name;
    EXPECT_EQ(json["model"], service->model);
    EXPECT_EQ(json["bus"], service->bus);
    EXPECT_EQ(json["settings_schema"], service->settings_schema()) << family.name;
    // The shared actions first, then the family's own, each with the arguments it takes.
    const auto actions = hub::actions_of(family.name);
    ASSERT_EQ(json["actions"].size(), actions.size()) << family.name;
    ASSERT_EQ(actions.size(), 3 + service->actions.size());
    for (std::size_t a = 0; a < actions.size(); ++a) {
      const auto& row = json["actions"][a];
      EXPECT_EQ(row["name"], actions[a]->name);
      EXPECT_EQ(row["description"], actions[a]->description);
      ASSERT_EQ(row["arguments"].size(), actions[a]->arguments.size());
      for (std::size_t v = 0; v < actions[a]->arguments.size(); ++v) {
        EXPECT_EQ(row["arguments"][v], actions[a]->arguments[v]);
      }
    }
    EXPECT_EQ(json["actions"][0]["name"], "start");
  }
}

// What each family's table says, typed in from the documents' commands: the ULS has a pointer
// (uls-interface-spec PT), the LS5 a latch (ls5-manual table 9.1 FX/FR); neither has the other.
TEST(WebFamilies, EachFamilyDeclaresItsOwnActions) {
  const auto names = [](std::string_view family) {
    std::vector<std::string> out;
    for (const hub::ActionDescriptor* action : hub::actions_of(family)) out.emplace_back(action->name);
    return out;
  };
  EXPECT_EQ(names("uls"), (std::vector<std::string>{"start", "stop", "read", "single", "pointer", "save", "reset"}));
  EXPECT_EQ(names("ls5"), (std::vector<std::string>{"start", "stop", "read", "single", "save", "reset", "latch"}));
  EXPECT_EQ(names("no-such-family"), (std::vector<std::string>{"start", "stop", "read"}));
  EXPECT_EQ(hub::find_action("ls5", "pointer"), nullptr);

  const hub::ActionDescriptor& pointer = *hub::find_action("uls", "pointer");
  EXPECT_TRUE(hub::check_argument(pointer, "on").ok());
  EXPECT_EQ(hub::check_argument(pointer, "").error().message, "pointer needs an argument: on or off");
  EXPECT_EQ(hub::check_argument(pointer, "maybe").error().message, "pointer takes on or off, not 'maybe'");
  const hub::ActionDescriptor& latch = *hub::find_action("ls5", "latch");
  EXPECT_TRUE(hub::check_argument(latch, "").ok());
  EXPECT_TRUE(hub::check_argument(latch, "read").ok());
  EXPECT_EQ(hub::check_argument(latch, "now").error().message, "latch takes none or read, not 'now'");
  EXPECT_EQ(hub::check_argument(*hub::find_action("uls", "single"), "now").error().message,
            "single takes no argument, not 'now'");
}

// A sample item carries the reading reading_of gives (channel, value, unit) beside its
// unchanged `data`; a gap carries none.
TEST(WebFamilies, ASampleItemCarriesItsReading) {
  hub::HubItem item;
  item.sequence = 7;
  item.sensor = "belt";
  Sample sample;
  sample.device = "ls5";
  sample.kind = ls5::kind::result;
  sample.set(ls5::channel::distance_mm, 12.3456);
  sample.set(ls5::channel::resolution_mm, 0.001);
  item.item = sample;
  const auto json = nlohmann::json::parse(web::item_json(item));
  const auto reading = reading_of(sample);
  ASSERT_TRUE(reading.has_value());
  EXPECT_EQ(json["reading"]["channel"], reading->channel->key);
  EXPECT_EQ(json["reading"]["unit"], unit_symbol(reading->channel->unit));
  EXPECT_DOUBLE_EQ(json["reading"]["value"].get<double>(), 12.346);  // the 3 decimals of a 0.001 mm step
  EXPECT_EQ(json["data"]["device"], "ls5");

  sample.set(ls5::channel::distance_mm, std::nullopt);
  sample.set(ls5::channel::signal, ls5::SignalState::lost);
  item.item = sample;
  const auto gap = nlohmann::json::parse(web::item_json(item));
  EXPECT_FALSE(gap.contains("reading")) << gap.dump();
  EXPECT_EQ(gap["type"], "sample");
}

}  // namespace
