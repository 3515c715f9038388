// The server's connections over TLS ([service] tls_certificate / tls_key).
#include "web/connection.hpp"

namespace rangekit::web {

void serve_tls(tcp::socket socket, Server::Impl& server) {
  detail::admit(TlsStream(std::move(socket), *server.tls), server);
}

}  // namespace rangekit::web
