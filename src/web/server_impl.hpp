// The state one running server shares between its acceptor and its connections.
#pragma once

#include <boost/asio/thread_pool.hpp>

#include <atomic>
#include <functional>
#include <map>
#include <mutex>
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
  // The connections waiting for a request (wait_for_request below), before the loop too.
  std::mutex waiting_mutex;
  std::uint64_t next_ticket = 0;
  std::map<std::uint64_t, std::pair<std::chrono::steady_clock::time_point, std::function<void()>>> waiting;
  EventCache frames;                     // before the loop too: the streams it holds use it until they go
  std::optional<net::ssl::context> tls;  // the certificate and key, when the service has them
  net::io_context context{1};
  tcp::acceptor acceptor{context};
  // Where it listens, kept from the start: the acceptor's own answer throws once it is closed.
  tcp::endpoint local;
  std::string local_text;              // "127.0.0.1:8080", for messages
  net::steady_timer backoff{context};  // out of descriptors: accept again a little later
  std::shared_ptr<Poster> poster = std::make_shared<Poster>(context);
  std::shared_ptr<FlushTicker> ticker = std::make_shared<FlushTicker>(context, poster, options.stream_tick);
  net::thread_pool commands;
  std::thread thread;
  std::atomic<bool> stopped{false};

  Impl(hub::Hub& h, ServerOptions o) : hub(h), options(std::move(o)), commands(options.command_threads) {}
  void accept();

  // Connections waiting for a request (kept alive and idle, or with one still arriving),
  // oldest first. At the limit a new client takes the place of the oldest that has waited
  // longer than kEvictAfter, so clients that trickle (slowloris) cannot keep others out; a
  // client on a plant's network sends its request within milliseconds.
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::milliseconds kEvictAfter{500};
  std::uint64_t wait_for_request(std::function<void()> close);
  void stop_waiting(std::uint64_t ticket);
  bool evict_oldest_waiting();
};

// One accepted client, served until it closes: the plain and the TLS connection are
// compiled in a file each (connection_plain.cpp, connection_tls.cpp), so the two
// instantiations of the connection build in parallel.
void serve_plain(tcp::socket socket, Server::Impl& server);
void serve_tls(tcp::socket socket, Server::Impl& server);

}  // namespace rangekit::web
