// The dashboard's files served by the web face: ServerOptions::assets at their paths with
// their content type, hashed names immutable and the page revalidated by ETag, GET only, no
// token, no Host check. Without assets "/" says why it is empty.
#include <gtest/gtest.h>

#include <array>

#include "rangekit/hub/hub.hpp"
#include "rangekit/web/server.hpp"
#include "web/http_client.hpp"

namespace {

using namespace rangekit;
using web_test::http;
using web_test::Reply;

constexpr std::array<web::StaticAsset, 2> assets{{
    {"/", "text/html; charset=utf-8", "<!doctype html><title>rangekit</title>", "\"page-1\"", false},
    {"/assets/app-AB12.js", "text/javascript; charset=utf-8", "console.log(1)", "\"script-1\"", true},
}};

struct AssetsService {
  std::unique_ptr<hub::Hub> hub = hub::Hub::start(hub::SiteConfig{});
  std::unique_ptr<web::Server> server;
  std::uint16_t port = 0;
  explicit AssetsService(std::span<const web::StaticAsset> served, std::string token = {}) {
    web::ServerOptions options;
    options.listen = "127.0.0.1:0";
    options.assets = served;
    options.token = std::move(token);
    auto started = web::Server::start(*hub, options);
    EXPECT_TRUE(started.ok()) << (started.ok() ? "" : started.error().message);
    if (started) server = std::move(*started);
    if (server) port = server->local_endpoint().port;
  }
};

TEST(WebDashboard, ThePageIsServedAtTheRootWithItsTypeAndIsRevalidated) {
  AssetsService service(assets);
  const Reply page = http(service.port, "GET", "/");
  ASSERT_EQ(page.status, 200);
  EXPECT_EQ(page.body, "<!doctype html><title>rangekit</title>");
  EXPECT_EQ(page.headers.at("content-type"), "text/html; charset=utf-8");
  EXPECT_EQ(page.headers.at("cache-control"), "no-cache");  // a new build shows at once
  EXPECT_EQ(page.headers.at("etag"), "\"page-1\"");
  EXPECT_EQ(page.headers.at("x-content-type-options"), "nosniff");
  EXPECT_NE(page.headers.at("content-security-policy").find("default-src 'self'"), std::string::npos);
  EXPECT_NE(page.headers.at("content-security-policy").find("frame-ancestors 'none'"), std::string::npos);
  // The query (e.g. ?token= for the page's stream) does not change what is served.
  EXPECT_EQ(http(service.port, "GET", "/?token=abc").status, 200);
  const Reply again = http(service.port, "GET", "/", {}, {"If-None-Match: \"page-1\""});
  EXPECT_EQ(again.status, 304);
  EXPECT_EQ(again.body, "");
  EXPECT_EQ(http(service.port, "GET", "/", {}, {"If-None-Match: \"page-0\""}).status, 200);
}

TEST(WebDashboard, HashedAssetsAreCachedForAYear) {
  AssetsService service(assets);
  const Reply script = http(service.port, "GET", "/assets/app-AB12.js");
  ASSERT_EQ(script.status, 200);
  EXPECT_EQ(script.body, "console.log(1)");
  EXPECT_EQ(script.headers.at("content-type"), "text/javascript; charset=utf-8");
  EXPECT_EQ(script.headers.at("cache-control"), "public, max-age=31536000, immutable");
}

TEST(WebDashboard, OnlyExactPathsAndGetAreAnswered) {
  AssetsService service(assets);
  EXPECT_EQ(http(service.port, "GET", "/assets/app-AB13.js").status, 404);
  EXPECT_EQ(http(service.port, "GET", "/assets").status, 404);
  EXPECT_EQ(http(service.port, "GET", "/index.html").status, 404);
  const Reply post = http(service.port, "POST", "/");
  EXPECT_EQ(post.status, 405);
  EXPECT_EQ(post.headers.at("allow"), "GET");
  // The API is unchanged beside them.
  EXPECT_EQ(http(service.port, "GET", "/api/sensors").status, 200);
  EXPECT_EQ(http(service.port, "GET", "/api/nothing").status, 404);
}

TEST(WebDashboard, FollowsTheApiReadRulesNoTokenForThePageButForItsStream) {
  // docs/api.md: beyond loopback the token is needed "on every write and every stream";
  // reads (GET of the API, and so of the page that holds no sensor data) need none.
  AssetsService service(assets, "secret");
  EXPECT_EQ(http(service.port, "GET", "/").status, 200);
  EXPECT_EQ(http(service.port, "GET", "/api/events").status, 401);
}

TEST(WebDashboard, WithoutAssetsTheRootSaysTheDashboardWasNotBuilt) {
  AssetsService service({});
  const Reply root = http(service.port, "GET", "/");
  EXPECT_EQ(root.status, 404);
  EXPECT_NE(root.body.find("RANGEKIT_DASHBOARD=OFF"), std::string::npos) << root.body;
}

}  // namespace
