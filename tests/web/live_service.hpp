// A service on a loopback port over the test site's emulators (hub/site_fixture.hpp), with
// a capture of the LS5 running, and requests with any Host: for the access and hostile-client tests.
#pragma once

#include <nlohmann/json.hpp>

#include <regex>

#include "hub/site_fixture.hpp"
#include "rangekit/web/server.hpp"
#include "web/http_client.hpp"

namespace web_test {

inline constexpr const char* kToken = "0123456789abcdef0123456789abcdef";

struct LiveService {
  hub_test::Site site;
  std::unique_ptr<rangekit::hub::Hub> hub = rangekit::hub::Hub::start(site.config);
  rangekit::hub::CaptureManager captures{*hub, (site.temp.path / "captures").string()};
  std::unique_ptr<rangekit::web::Server> server;
  std::uint16_t port = 0;
  std::string capture;
  explicit LiveService(const std::string& listen, rangekit::web::ServerOptions options = {}) {
    options.listen = listen;
    options.captures = &captures;
    auto started = rangekit::web::Server::start(*hub, options);
    EXPECT_TRUE(started.ok()) << (started.ok() ? "" : started.error().message);
    if (started) server = std::move(*started);
    if (server) port = server->local_endpoint().port;
    auto made = captures.start({"belt"});
    EXPECT_TRUE(made.ok());
    if (made) capture = made->id;
  }
  // A path of docs/security.md with this service's capture for CAPTURE.
  std::string target_of(const std::string& path) const {
    return std::regex_replace(path, std::regex("CAPTURE"), capture);
  }
};

inline std::string error_code(const Reply& reply) {
  const auto json = nlohmann::json::parse(reply.body, nullptr, false);
  return json.is_object() && json.contains("error") ? json["error"].value("code", "") : "";
}

// A request with the Host (and any other headers) as given, on its own connection.
inline Reply ask(std::uint16_t port, const std::string& method, const std::string& target, const std::string& host,
                 const std::vector<std::string>& headers = {}) {
  std::string text = method + " " + target + " HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n";
  for (const auto& header : headers) text += header + "\r\n";
  if (method != "GET") text += "Content-Length: 0\r\n";
  return http(port, method, target, {}, {}, text + "\r\n");
}

// A stream's status line, read as soon as it is there (an open stream never ends by itself).
inline int stream_status(std::uint16_t port, const std::string& target, const std::vector<std::string>& headers = {}) {
  web_test::EventReader reader(port, target, headers);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (reader.status() == 0 && std::chrono::steady_clock::now() < deadline)
    reader.pump(std::chrono::milliseconds(100));
  return reader.status();
}

}  // namespace web_test
