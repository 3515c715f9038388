// A service on a loopback port over the test site's emulators (hub/site_fixture.hpp), with
// a capture of the LS5 running, and requests with any Host: for the access and hostile-client tests.
#pragma once

#include <nlohmann/json.hpp>

#include <fstream>
#include <optional>
#include <regex>
#include <string>
#include <thread>

#include "hub/site_fixture.hpp"
#include "rangekit/core/descriptor_limit.hpp"
#include "rangekit/web/server.hpp"
#include "sqlite_query.hpp"
#include "web/http_client.hpp"

namespace web_test {

inline constexpr const char* kToken = "0123456789abcdef0123456789abcdef";

// The most memory this process has held (the service and its hostile clients together), in
// MiB; none under a sanitizer, whose shadow memory says nothing of the service's.
inline std::optional<double> peak_rss_mib() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return std::nullopt;
#else
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return std::nullopt;
#endif
}

struct LiveService {
  bool descriptors_raised = rangekit::raise_descriptor_limit();  // as `rangekit serve` does, before the site
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
  // What a hostile client must leave as it was (docs/security.md, "Limits"): /healthz answered
  // within 1 s, no record lost by a sensor or the capture, the capture intact, and this
  // process's peak memory under 128 MiB.
  void expect_unharmed() {
    // The LS5 streams into the capture all along: its first records are there within seconds.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (captures.info(capture).ok() && captures.info(capture)->samples == 0 &&
           std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));  // polls a count, with a deadline
    }
    const auto asked = std::chrono::steady_clock::now();
    const Reply health = http(port, "GET", "/healthz");
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - asked).count();
    EXPECT_EQ(health.status, 200) << health.body;
    EXPECT_LT(took, 1.0) << "/healthz took " << took << " s";
    for (const auto& sensor : hub->sensors()) EXPECT_EQ(sensor.health.lost, 0u) << sensor.config.name;
    (void)captures.stop(capture);  // a running capture downloads as csv, jsonl or log only
    const auto info = captures.info(capture);
    ASSERT_TRUE(info.ok());
    EXPECT_EQ(info->lost, 0u);
    EXPECT_GT(info->samples, 0u);
    const auto file = captures.export_file(capture, rangekit::hub::DownloadFormat::sqlite);
    ASSERT_TRUE(file.ok()) << file.error().message;
    EXPECT_EQ(sqlite_test::query(*file, "PRAGMA integrity_check"), "ok");
    if (const auto peak = peak_rss_mib()) {
      EXPECT_LT(*peak, 128.0) << "peak RSS " << *peak << " MiB";
    }
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
