// The state one running server shares between its acceptor and its connections.
#pragma once

#include <boost/asio/thread_pool.hpp>

#include <atomic>
#include <optional>
#include <thread>

#include "rangekit/web/server.hpp"
#include "web/event_stream.hpp"
#include "web/flush_ticker.hpp"
#include "web/http.hpp"

namespace rangekit::web {

struct Server::Impl {
  hub::Hub& hub;
  ServerOptions options;
  // Declared before the event loop: destroying the loop destroys the connections still
  // queued in it, and their destructors count themselves out here.
  std::atomic<std::uint64_t> connections{0};
  std::atomic<std::uint64_t> requests{0};
  std::atomic<std::uint64_t> refused{0};
  EventStreamCounters streams;
  EventCache frames;                     // before the loop too: the streams it holds use it until they go
  std::optional<net::ssl::context> tls;  // the certificate and key, when the service has them
  net::io_context context{1};
  tcp::acceptor acceptor{context};
  std::shared_ptr<Poster> poster = std::make_shared<Poster>(context);
  std::shared_ptr<FlushTicker> ticker = std::make_shared<FlushTicker>(context, poster, options.stream_tick);
  net::thread_pool commands;
  std::thread thread;
  std::atomic<bool> stopped{false};

  Impl(hub::Hub& h, ServerOptions o) : hub(h), options(std::move(o)), commands(options.command_threads) {}
  void accept();
};

// One accepted client, served until it closes: the plain and the TLS connection are
// compiled in a file each (connection_plain.cpp, connection_tls.cpp), so the two
// instantiations of the connection build in parallel.
void serve_plain(tcp::socket socket, Server::Impl& server);
void serve_tls(tcp::socket socket, Server::Impl& server);

}  // namespace rangekit::web
