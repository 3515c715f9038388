// The server's connections over plain TCP.
#include "web/connection.hpp"

namespace rangekit::web {

void serve_plain(tcp::socket socket, Server::Impl& server) { detail::admit(PlainStream(std::move(socket)), server); }

}  // namespace rangekit::web
