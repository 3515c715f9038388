// Who may do what (docs/security.md): the document's tables are read here and every route
// walked against a running service, on loopback and beyond it with a token; then the
// limits a hostile client meets.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <regex>
#include <thread>

#include "build_paths.hpp"
#include "rangekit/web/server.hpp"
#include "web/access.hpp"
#include "web/live_service.hpp"

namespace access_test {

using namespace rangekit;
using web_test::ask;
using web_test::error_code;
using web_test::http;
using web_test::Reply;
using web_test::stream_status;
using Service = web_test::LiveService;

using web_test::kToken;

struct Route {
  std::string method;
  std::string target;  // CAPTURE stands for a capture's id
  web::Access kind;
};

std::optional<web::Access> kind_named(const std::string& name) {
  static const std::map<std::string, web::Access> kinds{{"health", web::Access::health},
                                                        {"page", web::Access::page},
                                                        {"read", web::Access::read},
                                                        {"stream", web::Access::stream},
                                                        {"write", web::Access::write}};
  const auto found = kinds.find(name);
  if (found == kinds.end()) return std::nullopt;
  return found->second;
}

// The rows of "The routes" in docs/security.md: | `METHOD TARGET` | kind |.
std::vector<Route> routes_of_the_document() {
  std::ifstream file(std::string(test::source_dir()) + "/docs/security.md");
  std::vector<Route> routes;
  std::string line;
  bool in_table = false;
  const std::regex row(R"(^\| `([A-Z]+) ([^`]+)` \| ([a-z]+) \|$)");
  while (std::getline(file, line)) {
    if (line.rfind("### ", 0) == 0) in_table = line == "### The routes";
    std::smatch match;
    if (!in_table || !std::regex_match(line, match, row)) continue;
    const auto kind = kind_named(match[3]);
    EXPECT_TRUE(kind.has_value()) << line;
    if (kind) routes.push_back(Route{match[1], match[2], *kind});
  }
  return routes;
}

web::http::verb verb_of(const std::string& method) { return web::http::string_to_verb(method); }

TEST(AccessTable, TheDocumentListsEveryKindAndEachRouteIsSortedAsItSays) {
  const auto routes = routes_of_the_document();
  ASSERT_GE(routes.size(), 20u);
  std::set<web::Access> kinds;
  for (const Route& route : routes) {
    kinds.insert(route.kind);
    EXPECT_EQ(web::access_of(web::parse_target(route.target), verb_of(route.method)), route.kind)
        << route.method << " " << route.target;
  }
  EXPECT_EQ(kinds.size(), 5u);
}

// Bound to every address, so the token is needed; reached over 127.0.0.1 as a client elsewhere would.
TEST(AccessTable, BeyondLoopbackEveryRouteButHealthAndPageNeedsTheToken) {
  web::ServerOptions options;
  options.token = kToken;
  Service service("0.0.0.0:0", options);
  const std::string host = "127.0.0.1:" + std::to_string(service.port);
  const std::string bearer = std::string("Authorization: Bearer ") + kToken;
  for (const Route& route : routes_of_the_document()) {
    const std::string target = service.target_of(route.target);
    SCOPED_TRACE(route.method + " " + target);
    const std::string with_query = target + (target.find('?') == std::string::npos ? "?" : "&") + "token=" + kToken;
    switch (route.kind) {
      case web::Access::health: {
        const Reply bare = ask(service.port, route.method, target, host);
        EXPECT_EQ(bare.status, 200);
        EXPECT_EQ(nlohmann::json::parse(bare.body, nullptr, false).size(), 1u) << bare.body;  // the status alone
        EXPECT_TRUE(nlohmann::json::parse(ask(service.port, route.method, target, host, {bearer}).body, nullptr, false)
                        .contains("disconnected"));
        break;
      }
      case web::Access::page:
        EXPECT_NE(ask(service.port, route.method, target, host).status, 401);
        break;
      case web::Access::stream:
        EXPECT_EQ(stream_status(service.port, target), 401);
        EXPECT_EQ(stream_status(service.port, target + "?token=wrong-token-of-the-same-size-000"), 401);
        EXPECT_EQ(stream_status(service.port, with_query), 200);
        EXPECT_EQ(stream_status(service.port, target, {bearer}), 200);
        break;
      case web::Access::read:
      case web::Access::write: {
        const Reply bare = ask(service.port, route.method, target, host);
        EXPECT_EQ(bare.status, 401) << bare.body;
        EXPECT_EQ(error_code(bare), "unauthorized");
        for (const char* name : {"belt", "silo", "bay-"})
          EXPECT_EQ(bare.body.find(name), std::string::npos) << bare.body;
        EXPECT_EQ(ask(service.port, route.method, target, host, {"Authorization: Bearer wrong"}).status, 401);
        const Reply allowed = ask(service.port, route.method, target, host, {bearer});
        EXPECT_NE(allowed.status, 401) << allowed.body;
        EXPECT_NE(allowed.status, 403) << allowed.body;
        EXPECT_NE(allowed.status, 0);
        // ?token= serves a link; a write never takes it (an address lands in logs).
        EXPECT_EQ(ask(service.port, route.method, with_query, host).status == 401, route.kind == web::Access::write);
        break;
      }
    }
  }
}

// On loopback no token is needed, so the Host is what keeps a web page out (DNS rebinding).
TEST(AccessTable, OnLoopbackEveryReadStreamAndWriteNeedsAHostNamingTheService) {
  Service service("127.0.0.1:0");
  const std::string port = std::to_string(service.port);
  for (const Route& route : routes_of_the_document()) {
    const std::string target = service.target_of(route.target);
    SCOPED_TRACE(route.method + " " + target);
    const bool checked = route.kind != web::Access::health && route.kind != web::Access::page;
    const std::vector<std::string> foreign_hosts{
        "127.evil.example:" + port,       "evil.example:" + port, "127.0.0.1", "127.1:" + port,
        "localhost.evil.example:" + port, "127.0.0.1:1" + port,   ""};
    for (const std::string& foreign : foreign_hosts) {
      const Reply reply = ask(service.port, route.method, target, foreign);
      if (checked) {
        EXPECT_EQ(reply.status, 403) << foreign << ": " << reply.body;
        EXPECT_EQ(error_code(reply), "bad_host") << foreign;
      } else {
        EXPECT_NE(reply.status, 403) << foreign;
      }
    }
    if (route.kind == web::Access::write) {
      const Reply foreign_origin =
          ask(service.port, route.method, target, "127.0.0.1:" + port, {"Origin: http://127.evil.example:" + port});
      EXPECT_EQ(error_code(foreign_origin), "bad_origin") << foreign_origin.body;
    }
    if (route.kind == web::Access::read) {
      for (const std::string& own :
           std::vector<std::string>{"127.0.0.1:" + port, "localhost:" + port, "127.0.0.2:" + port}) {
        EXPECT_NE(ask(service.port, route.method, target, own).status, 403) << own;
      }
    }
  }
}

TEST(HostCheck, LoopbackMeansTheLiteralAddressesAndLocalhostOnly) {
  const auto loopback = boost::asio::ip::make_address("127.0.0.1");
  const web::tcp::endpoint local(loopback, 8080);
  EXPECT_TRUE(web::host_names_service("127.0.0.1:8080", local, false));
  EXPECT_TRUE(web::host_names_service("127.0.0.9:8080", local, false));
  EXPECT_TRUE(web::host_names_service("localhost:8080", local, false));
  EXPECT_TRUE(web::host_names_service("[::1]:8080", local, false));
  for (const char* host :
       {"127.evil.example:8080", "127.0.0.1.evil.example:8080", "127.1:8080", "0x7f.0.0.1:8080", "2130706433:8080",
        "localhost.:8080", "[::1]", "127.0.0.1:80", "127.0.0.1:8080x", "127.0.0.1:", ":8080", "", "10.0.0.1:8080"}) {
    EXPECT_FALSE(web::host_names_service(host, local, false)) << host;
  }
  EXPECT_FALSE(web::is_loopback_host("127.evil.example"));
  EXPECT_TRUE(web::is_loopback_host("127.0.0.1"));
}

TEST(HostCheck, AHostWithoutAPortMeansTheSchemesPort) {
  const auto every = boost::asio::ip::make_address("0.0.0.0");
  EXPECT_TRUE(web::host_names_service("gateway.plant", web::tcp::endpoint(every, 443), true));
  EXPECT_FALSE(web::host_names_service("gateway.plant", web::tcp::endpoint(every, 443), false));
  EXPECT_TRUE(web::host_names_service("gateway.plant", web::tcp::endpoint(every, 80), false));
  EXPECT_TRUE(web::host_names_service("gateway.plant:8443", web::tcp::endpoint(every, 8443), true));
  const auto own = boost::asio::ip::make_address("10.1.2.3");
  EXPECT_TRUE(web::host_names_service("10.1.2.3:8080", web::tcp::endpoint(own, 8080), false));
  EXPECT_FALSE(web::host_names_service("gateway.plant:8080", web::tcp::endpoint(own, 8080), false));
  EXPECT_FALSE(web::host_names_service("127.0.0.1:8080", web::tcp::endpoint(own, 8080), false));
}

TEST(HostCheck, TheTokenCompareTakesNoShortcut) {
  EXPECT_TRUE(web::same_secret(kToken, kToken));
  EXPECT_FALSE(web::same_secret("0123456789abcdef0123456789abcdeX", kToken));
  EXPECT_FALSE(web::same_secret("", kToken));
  EXPECT_FALSE(web::same_secret(std::string(kToken) + "0", kToken));
  EXPECT_FALSE(web::same_secret("", ""));  // no token set is not a match
}

}  // namespace access_test
