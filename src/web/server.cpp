// The HTTP server: an acceptor and one connection per client on one asio event loop
// (web/connection.hpp reads and writes, web/routes.cpp answers by its table after
// web/auth.cpp's Host, Origin and token checks). Limits: connections, header and body size.
#include "rangekit/web/server.hpp"

#include "web/access.hpp"
#include "web/server_impl.hpp"

namespace rangekit::web {

void Server::Impl::accept() {
  acceptor.async_accept(net::make_strand(context), [this](beast::error_code error, tcp::socket socket) {
    if (error == net::error::no_descriptors || error == boost::system::errc::too_many_files_open_in_system) {
      // Accepting again at once would spin while the descriptors stay gone; the client waits in the backlog.
      if (stopped) return;
      backoff.expires_after(std::chrono::milliseconds(100));
      backoff.async_wait([this](beast::error_code waited) {
        if (!waited) accept();
      });
      return;
    }
    if (error) {
      if (!stopped && error != net::error::operation_aborted) accept();
      return;
    }
    // Every write goes out at once: with Nagle on, an event written while the previous one
    // is not yet acknowledged waits for the client's delayed ACK (40 ms on Linux), which
    // made the p99 of record-to-SSE latency 40 ms while the median was 5.
    beast::error_code ignored;
    socket.set_option(tcp::no_delay(true), ignored);
    if (tls) {
      serve_tls(std::move(socket), *this);
    } else {
      serve_plain(std::move(socket), *this);
    }
    accept();
  });
}

std::uint64_t Server::Impl::wait_for_request(std::function<void()> close) {
  std::lock_guard lock(waiting_mutex);
  waiting.emplace(next_ticket, std::make_pair(Clock::now(), std::move(close)));
  return next_ticket++;
}

void Server::Impl::stop_waiting(std::uint64_t ticket) {
  std::lock_guard lock(waiting_mutex);
  waiting.erase(ticket);
}

bool Server::Impl::evict_oldest_waiting() {
  std::function<void()> close;
  {
    std::lock_guard lock(waiting_mutex);
    if (waiting.empty() || Clock::now() - waiting.begin()->second.first < kEvictAfter) return false;
    close = std::move(waiting.begin()->second.second);
    waiting.erase(waiting.begin());
  }
  close();  // outside the lock: closing ends the connection's read, which stops waiting itself
  return true;
}

Server::Server(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Server::~Server() {
  try {
    stop();
  } catch (...) {  // NOLINT(bugprone-empty-catch): a destructor must not throw; stop() only joins
  }
}

Result<std::unique_ptr<Server>> Server::start(hub::Hub& hub, ServerOptions options) {
  auto endpoint = parse_endpoint(options.listen);
  if (!endpoint) return make_error(Errc::out_of_range, "listen '" + options.listen + "': " + endpoint.error().message);
  auto impl = std::make_unique<Impl>(hub, std::move(options));
  beast::error_code error;
  const auto address = net::ip::make_address(endpoint->host == "localhost" ? "127.0.0.1" : endpoint->host, error);
  if (error) return make_error(Errc::out_of_range, "listen: '" + endpoint->host + "' is not an IP address");
  const tcp::endpoint local{address, endpoint->port};
  if (!impl->options.tls_certificate.empty() || !impl->options.tls_key.empty()) {
    if (impl->options.tls_certificate.empty() || impl->options.tls_key.empty()) {
      return make_error(Errc::wrong_form, "TLS needs both a certificate and a key");
    }
    impl->tls.emplace(net::ssl::context::tls_server);
    impl->tls->set_options(net::ssl::context::default_workarounds | net::ssl::context::no_sslv2 |
                           net::ssl::context::no_sslv3 | net::ssl::context::no_tlsv1 | net::ssl::context::no_tlsv1_1);
    impl->tls->use_certificate_chain_file(impl->options.tls_certificate, error);
    if (error) return make_error(Errc::io, "TLS certificate " + impl->options.tls_certificate + ": " + error.message());
    impl->tls->use_private_key_file(impl->options.tls_key, net::ssl::context::pem, error);
    if (error) return make_error(Errc::io, "TLS key " + impl->options.tls_key + ": " + error.message());
  }
  impl->acceptor.open(local.protocol(), error);
  if (!error) impl->acceptor.set_option(net::socket_base::reuse_address(true), error);
  if (!error) impl->acceptor.bind(local, error);
  if (!error) impl->acceptor.listen(net::socket_base::max_listen_connections, error);
  if (!error) impl->local = impl->acceptor.local_endpoint(error);
  if (error) return make_error(Errc::io, "cannot listen on " + impl->options.listen + ": " + error.message());
  impl->local_text = host_text(impl->local.address()) + ":" + std::to_string(impl->local.port());
  impl->accept();
  Impl* raw = impl.get();
  impl->thread = std::thread([raw] { raw->context.run(); });
  return std::unique_ptr<Server>(new Server(std::move(impl)));
}

void Server::stop() {
  if (!impl_ || impl_->stopped.exchange(true)) return;
  net::post(impl_->context, [impl = impl_.get()] {
    beast::error_code ignored;
    impl->acceptor.close(ignored);
    impl->backoff.cancel();
  });
  impl_->commands.join();  // settings and actions in progress finish (within the hub's command timeout)
  impl_->poster->shut();
  impl_->context.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

Endpoint Server::local_endpoint() const { return Endpoint{impl_->local.address().to_string(), impl_->local.port()}; }

ServerStats Server::stats() const {
  return ServerStats{impl_->connections.load(), impl_->streams.open.load(), impl_->requests.load(),
                     impl_->refused.load(), impl_->streams.cut_off.load()};
}

}  // namespace rangekit::web
