// Issue 13 point 5: "TLS is optional (certificate and key paths)". With both given the
// service speaks HTTPS only: the API and the streams over TLS, a plain request refused.
#include <gtest/gtest.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>

#include <cstdlib>

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

TEST(WebTls, TheApiAndItsStreamsGoOverTlsOnly) {
  Certificate certificate;
  ASSERT_TRUE(certificate.made) << "openssl could not make a certificate";
  // One sensor on a port that does not exist: its "disconnected" event is in the ring at once.
  auto site = rangekit::hub::parse_site_config(
      "[[sensor]]\nname = \"x\"\nfamily = \"ls5\"\nport = \"/nonexistent/rangekit-port\"\n", "site.toml");
  ASSERT_TRUE(site.ok());
  auto hub = rangekit::hub::Hub::start(*site);
  rangekit::web::ServerOptions options;
  options.listen = "127.0.0.1:0";
  options.tls_certificate = certificate.certificate;
  options.tls_key = certificate.key;
  auto server = rangekit::web::Server::start(*hub, options);
  ASSERT_TRUE(server.ok()) << server.error().message;
  const auto port = (*server)->local_endpoint().port;

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

}  // namespace tls_test
