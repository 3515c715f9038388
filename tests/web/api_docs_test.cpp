// docs/openapi.yaml, docs/api.md and the server agree on the paths (no drift).
#include <gtest/gtest.h>
#include "build_paths.hpp"

#include <fstream>
#include <regex>
#include <sstream>

#include "hub/site_fixture.hpp"
#include "rangekit/web/server.hpp"
#include "web/http_client.hpp"

namespace {

std::string read(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

TEST(WebApiDocs, EveryDocumentedPathIsServedAndDescribed) {
  const std::string openapi = read(std::string(rangekit::test::source_dir()) + "/docs/openapi.yaml");
  const std::string api = read(std::string(rangekit::test::source_dir()) + "/docs/api.md");
  // A hub with one sensor whose port does not exist: enough to route every path.
  auto site = rangekit::hub::parse_site_config(
      "[[sensor]]\nname = \"x\"\nfamily = \"ls5\"\nport = \"/nonexistent/rangekit-port\"\n", "site.toml");
  ASSERT_TRUE(site.ok());
  auto hub = rangekit::hub::Hub::start(*site);
  hub_test::TempDir dir;
  rangekit::hub::CaptureManager captures(*hub, dir.path.string());
  rangekit::web::ServerOptions options;
  options.listen = "127.0.0.1:0";
  options.captures = &captures;
  auto server = rangekit::web::Server::start(*hub, options);
  ASSERT_TRUE(server.ok());
  const auto port = (*server)->local_endpoint().port;
  const std::regex path_line(R"(^  (/[^:]*):\s*$)");
  std::istringstream lines(openapi);
  int paths = 0;
  for (std::string line; std::getline(lines, line);) {
    std::smatch match;
    if (!std::regex_match(line, match, path_line)) continue;
    ++paths;
    const std::string path = match[1];
    EXPECT_NE(api.find(path), std::string::npos) << "docs/api.md does not describe " << path;
    const std::string concrete = std::regex_replace(std::regex_replace(path, std::regex(R"(\{action\})"), "read"),
                                                    std::regex(R"(\{[a-z]+\})"), "x");
    if (concrete.size() >= 6 && concrete.compare(concrete.size() - 6, 6, "events") == 0) {
      web_test::EventReader stream(port, concrete);  // a stream never ends: its head is enough
      stream.read_until([](const web_test::Event&) { return true; }, std::chrono::seconds(2));
      EXPECT_EQ(stream.status(), 200) << concrete;
      continue;
    }
    for (const char* method : {"GET", "POST"}) {
      const auto reply = web_test::http(port, method, concrete, method == std::string("POST") ? "{}" : "");
      EXPECT_EQ(reply.body.find("no such path"), std::string::npos) << method << " " << concrete << ": " << reply.body;
    }
  }
  EXPECT_GE(paths, 14);
}

}  // namespace
