// Beast/asio names the web face shares, and one request's parsed target.
#pragma once

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace rangekit::web {

namespace beast = boost::beast;
namespace http = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

using PlainStream = beast::tcp_stream;
using TlsStream = beast::ssl_stream<beast::tcp_stream>;  // [service] tls_certificate / tls_key

// The TCP stream under either kind: timeouts, socket options, closing.
inline beast::tcp_stream& tcp_of(PlainStream& stream) { return stream; }
inline beast::tcp_stream& tcp_of(TlsStream& stream) { return stream.next_layer(); }

// A bounded kernel buffer for a client that takes a stream or a download: a client that stops
// reading fills it and then waits, instead of the system holding megabytes for it (on loopback,
// Linux starts a socket's buffer at over a megabyte).
inline void bound_send_buffer(beast::tcp_stream& stream) {
  beast::error_code ignored;
  stream.socket().set_option(net::socket_base::send_buffer_size(64 * 1024), ignored);
}

using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;

// "/api/sensors/belt/events?after=12" -> {"api","sensors","belt","events"}, {{"after","12"}}.
struct Target {
  std::vector<std::string> segments;
  std::map<std::string, std::string, std::less<>> query;
  bool valid = true;  // false: a segment or value that does not decode
};
Target parse_target(std::string_view target);

}  // namespace rangekit::web
