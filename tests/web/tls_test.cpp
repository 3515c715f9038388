// TLS is optional (certificate and key paths). With both given the
// service speaks HTTPS only: the API and the streams over TLS, a plain request refused.
#include <gtest/gtest.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>

#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>

#include "hub/site_fixture.hpp"
#include "rangekit/web/server.hpp"
#include "web/http_client.hpp"

namespace tls_test {  // named: beside the other web tests in a unity batch, its Beast aliases stay its own

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

struct Certificate {
  hub_test::TempDir dir;
  std::string certificate = (dir.path / "cert.pem").string();
  std::string key = (dir.path / "key.pem").string();
  bool made = false;
  Certificate() {
    const std::string command = "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost -keyout " + key +
                                " -out " + certificate + " 2>/dev/null";
    made = std::system(command.c_str()) == 0;
  }
};

// A TLS client that trusts exactly the service's own certificate.
struct TlsClient {
  net::io_context context;
  net::ssl::context tls{net::ssl::context::tls_client};
  beast::ssl_stream<beast::tcp_stream> stream{context, tls};
  TlsClient(std::uint16_t port, const std::string& certificate) {
    tls.load_verify_file(certificate);
    stream.set_verify_mode(net::ssl::verify_peer);
    stream.next_layer().connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    stream.next_layer().expires_after(std::chrono::seconds(30));
    stream.handshake(net::ssl::stream_base::client);
  }
  void send(const std::string& target, std::uint16_t port, const std::string& extra = {}) {
    const std::string request = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n" +
                                extra + "Connection: close\r\n\r\n";
    net::write(stream, net::buffer(request));
  }
};

// The service over TLS, on one sensor at a port that does not exist: its "disconnected"
// event is in the ring at once.
struct TlsService {
  Certificate certificate;
  std::unique_ptr<rangekit::hub::Hub> hub;
  rangekit::web::ServerOptions options;
  std::unique_ptr<rangekit::web::Server> server;
  std::uint16_t port = 0;
  explicit TlsService(std::size_t max_connections = 256) {
    EXPECT_TRUE(certificate.made) << "openssl could not make a certificate";
    auto site = rangekit::hub::parse_site_config(
        "[[sensor]]\nname = \"x\"\nfamily = \"ls5\"\nport = \"/nonexistent/rangekit-port\"\n", "site.toml");
    EXPECT_TRUE(site.ok());
    if (!site) return;
    hub = rangekit::hub::Hub::start(*site);
    options.listen = "127.0.0.1:0";
    options.tls_certificate = certificate.certificate;
    options.tls_key = certificate.key;
    options.max_connections = max_connections;
    auto started = rangekit::web::Server::start(*hub, options);
    EXPECT_TRUE(started.ok()) << (started ? "" : started.error().message);
    if (!started) return;
    server = std::move(*started);
    port = server->local_endpoint().port;
  }
};

std::string read_all(TlsClient& client) {
  std::string received;
  std::array<char, 4096> chunk{};
  beast::error_code error;
  while (!error) received.append(chunk.data(), client.stream.read_some(net::buffer(chunk), error));
  return received;
}

TEST(WebTls, TheApiAndItsStreamsGoOverTlsOnly) {
  TlsService service;
  ASSERT_TRUE(service.server);
  const auto port = service.port;
  const Certificate& certificate = service.certificate;
  auto& hub = service.hub;
  const auto& options = service.options;

  TlsClient api(port, certificate.certificate);
  api.send("/healthz", port);
  beast::flat_buffer buffer;
  http::response<http::string_body> health;
  http::read(api.stream, buffer, health);
  EXPECT_EQ(health.result_int(), 200);
  EXPECT_NE(health.body().find("\"sensors\":1"), std::string::npos) << health.body();

  TlsClient events(port, certificate.certificate);
  events.send("/api/events", port, "Last-Event-ID: 0\r\n");  // resume from the start of the ring
  std::string received;
  std::array<char, 4096> chunk{};
  while (received.find("event: event") == std::string::npos) {
    const std::size_t got = events.stream.read_some(net::buffer(chunk));
    received.append(chunk.data(), got);
  }
  EXPECT_NE(received.find("text/event-stream"), std::string::npos);
  EXPECT_NE(received.find("disconnected"), std::string::npos) << received;

  // Plain HTTP to the TLS port gets no HTTP answer.
  const auto plain = web_test::http(port, "GET", "/healthz");
  EXPECT_EQ(plain.status, 0);
  EXPECT_EQ(plain.body.find("sensors"), std::string::npos);

  // Half a pair is refused at start.
  rangekit::web::ServerOptions half;
  half.listen = "127.0.0.1:0";
  half.tls_certificate = certificate.certificate;
  EXPECT_FALSE(rangekit::web::Server::start(*hub, half).ok());
  rangekit::web::ServerOptions missing = options;
  missing.tls_key = (certificate.dir.path / "absent.pem").string();
  const auto refused = rangekit::web::Server::start(*hub, missing);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("absent.pem"), std::string::npos) << refused.error().message;
}

// Over the connection limit the one answer is spoken in TLS, after the handshake: a plain
// HTTP refusal would be garbage to a TLS client.
TEST(WebTls, OverTheConnectionLimitTheRefusalIsSpokenInTls) {
  TlsService service(0);  // every client is over the limit
  ASSERT_TRUE(service.server);
  TlsClient client(service.port, service.certificate.certificate);
  client.send("/healthz", service.port);
  const std::string answer = read_all(client);
  EXPECT_EQ(answer.rfind("HTTP/1.1 503", 0), 0u) << answer;
  EXPECT_NE(answer.find("too_many_connections"), std::string::npos) << answer;
}

// Clients that connect and never begin the handshake (slowloris on TLS) wait like a request
// that never comes: past half a second the oldest gives its place to a new client.
TEST(WebTls, ClientsThatNeverShakeHandsCannotKeepOthersOut) {
  TlsService service(2);
  ASSERT_TRUE(service.server);
  const int first = web_test::connect_to(service.port);
  const int second = web_test::connect_to(service.port);
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // past the 500 ms a waiting client keeps its place
  TlsClient client(service.port, service.certificate.certificate);
  client.send("/healthz", service.port);
  const std::string answer = read_all(client);
  EXPECT_EQ(answer.rfind("HTTP/1.1 200", 0), 0u) << answer;
  ::close(first);
  ::close(second);
}

}  // namespace tls_test
