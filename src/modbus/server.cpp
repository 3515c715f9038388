#include "modbus/server.hpp"

#include <algorithm>
#include <array>
#include <boost/asio.hpp>
#include <list>

namespace rangekit::modbus {
namespace {

namespace net = boost::asio;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

// Loopback always; beyond it, an address the site file's allow list names.
bool allowed(const net::ip::address& peer, const std::vector<AddressRange>& allow) {
  if (peer.is_loopback()) return true;
  net::ip::address_v4 v4;
  if (peer.is_v4()) {
    v4 = peer.to_v4();
  } else if (peer.is_v6() && peer.to_v6().is_v4_mapped()) {
    v4 = net::ip::make_address_v4(net::ip::v4_mapped, peer.to_v6());
  } else {
    return false;
  }
  const std::uint32_t address = v4.to_uint();
  return std::any_of(allow.begin(), allow.end(), [&](const AddressRange& range) { return range.contains(address); });
}

// The 1st, 2nd, 4th, 8th... of a kind of refusal: a client that repeats itself cannot flood the log.
bool worth_logging(std::uint64_t count) { return (count & (count - 1)) == 0; }

}  // namespace

struct Server::Impl {
  struct Connection {
    explicit Connection(net::io_context& context) : socket(context), idle(context) {}
    tcp::socket socket;
    net::steady_timer idle;
    std::array<std::uint8_t, 2 * max_adu_size> buffer{};
    std::size_t held = 0;  // bytes of buffer not yet a whole request
    std::vector<std::uint8_t> out;
    Clock::time_point last_request = Clock::now();
  };
  using ConnectionPtr = std::shared_ptr<Connection>;

  Impl(ServerSettings s, UnitTable& u, ServerCounters& c) : settings(std::move(s)), units(u), counters(c) {}

  void log(const std::string& line) const {
    if (settings.log) settings.log(line);
  }

  void accept() {
    acceptor.async_accept([this](boost::system::error_code error, tcp::socket socket) {
      if (error == net::error::operation_aborted || !acceptor.is_open()) return;
      if (!error) {
        admit(std::move(socket));
        accept();
        return;
      }
      // Out of descriptors (EMFILE) or the like: accept again a little later, not in a busy loop.
      backoff.expires_after(std::chrono::milliseconds(100));
      backoff.async_wait([this](boost::system::error_code waited) {
        if (!waited && acceptor.is_open()) accept();
      });
    });
  }

  void admit(tcp::socket socket) {
    boost::system::error_code ignored;
    const auto peer = socket.remote_endpoint(ignored);
    const bool stranger = !ignored && !allowed(peer.address(), settings.allow);
    if (ignored || stranger || connections.size() >= settings.max_clients) {
      const std::uint64_t refused = ++counters.refused;
      if (stranger && worth_logging(refused)) {
        log("modbus: refused " + peer.address().to_string() + ": not in [modbus] allow (" + std::to_string(refused) +
            " refused so far)");
      } else if (!stranger && worth_logging(refused)) {
        log("modbus: refused a connection: " + std::to_string(settings.max_clients) + " clients are connected (" +
            std::to_string(refused) + " refused so far)");
      }
      socket.close(ignored);
      return;
    }
    socket.set_option(tcp::no_delay(true), ignored);
    auto connection = std::make_shared<Connection>(context);
    connection->socket = std::move(socket);
    connections.push_back(connection);
    counters.clients = connections.size();
    watch_idle(connection);
    read(connection);
  }

  void close(const ConnectionPtr& connection) {
    boost::system::error_code ignored;
    connection->socket.close(ignored);
    connection->idle.cancel();
    connections.remove(connection);
    counters.clients = connections.size();
  }

  // A connection that asks nothing for idle_timeout is closed: one timer per connection
  // looks at its last request, so a request costs no timer operation.
  void watch_idle(const ConnectionPtr& connection) {
    connection->idle.expires_after(settings.idle_timeout / 2);
    connection->idle.async_wait([this, connection](boost::system::error_code error) {
      if (error || !connection->socket.is_open()) return;
      if (Clock::now() - connection->last_request >= settings.idle_timeout) {
        close(connection);
        return;
      }
      watch_idle(connection);
    });
  }

  void read(const ConnectionPtr& connection) {
    auto room = net::buffer(connection->buffer.data() + connection->held, connection->buffer.size() - connection->held);
    connection->socket.async_read_some(room, [this, connection](boost::system::error_code error, std::size_t got) {
      if (error) {
        if (error != net::error::operation_aborted) close(connection);
        return;
      }
      connection->held += got;
      connection->last_request = Clock::now();
      answer(connection);
    });
  }

  // Every whole request in the buffer is answered, in order, with one write.
  void answer(const ConnectionPtr& connection) {
    connection->out.clear();
    std::size_t used = 0;
    while (true) {
      const Bytes rest(connection->buffer.data() + used, connection->held - used);
      const FrameScan scan = scan_mbap_frame(rest);
      if (scan.status == FrameStatus::need_more) break;
      if (scan.status == FrameStatus::invalid) {
        const std::uint64_t malformed = ++counters.malformed;
        if (worth_logging(malformed)) {
          log(std::string("modbus: closed a connection: ") + (scan.reason != nullptr ? scan.reason : "not Modbus") +
              " (" + std::to_string(malformed) + " so far)");
        }
        close(connection);
        return;
      }
      ++counters.requests;
      if (answer_request(scan.frame, units, connection->out) != 0) ++counters.exceptions;
      used += scan.consumed;
    }
    std::copy(connection->buffer.begin() + static_cast<std::ptrdiff_t>(used),
              connection->buffer.begin() + static_cast<std::ptrdiff_t>(connection->held), connection->buffer.begin());
    connection->held -= used;
    if (connection->out.empty()) {
      read(connection);
      return;
    }
    net::async_write(connection->socket, net::buffer(connection->out),
                     [this, connection](boost::system::error_code error, std::size_t) {
                       if (error) {
                         if (error != net::error::operation_aborted) close(connection);
                         return;
                       }
                       read(connection);
                     });
  }

  ServerSettings settings;
  UnitTable& units;
  ServerCounters& counters;
  net::io_context context{1};
  tcp::acceptor acceptor{context};
  net::steady_timer backoff{context};
  std::list<ConnectionPtr> connections;
  Endpoint local;  // as bound, read from any thread
};

Server::Server(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Server::~Server() = default;

Result<std::unique_ptr<Server>> Server::bind(ServerSettings settings, UnitTable& units, ServerCounters& counters) {
  auto impl = std::make_unique<Impl>(std::move(settings), units, counters);
  boost::system::error_code error;
  const std::string host = impl->settings.listen.host == "localhost" ? "127.0.0.1" : impl->settings.listen.host;
  const auto address = net::ip::make_address(host, error);
  if (error) return make_error(Errc::out_of_range, "modbus listen '" + host + "' is not an IP address");
  // Modbus has no authentication: beyond loopback the site file names who may connect.
  if (!address.is_loopback() && impl->settings.allow.empty()) {
    return make_error(Errc::out_of_range, "modbus listen " + impl->settings.listen.to_string() +
                                              " is beyond loopback: name who may connect with [modbus] allow = "
                                              "[\"10.0.0.0/8\"] (Modbus has no authentication)");
  }
  const tcp::endpoint endpoint(address, impl->settings.listen.port);
  impl->acceptor.open(endpoint.protocol(), error);
  if (!error) impl->acceptor.set_option(tcp::acceptor::reuse_address(true), error);
  if (!error) impl->acceptor.bind(endpoint, error);
  if (!error) impl->acceptor.listen(net::socket_base::max_listen_connections, error);
  if (error) {
    return make_error(Errc::io,
                      "modbus: cannot listen on " + impl->settings.listen.to_string() + ": " + error.message());
  }
  const auto bound = impl->acceptor.local_endpoint(error);
  impl->local = Endpoint{bound.address().to_string(), bound.port()};
  impl->accept();
  return std::unique_ptr<Server>(new Server(std::move(impl)));
}

void Server::run() { impl_->context.run(); }

void Server::stop() {
  net::post(impl_->context, [impl = impl_.get()] {
    boost::system::error_code ignored;
    impl->acceptor.close(ignored);
    impl->backoff.cancel();
    while (!impl->connections.empty()) impl->close(impl->connections.front());
    impl->context.stop();
  });
}

Endpoint Server::local_endpoint() const { return impl_->local; }

}  // namespace rangekit::modbus
