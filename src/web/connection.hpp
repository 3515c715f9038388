// One HTTP connection of the server, over either stream: the TLS handshake, reading a
// request within its limits, and writing answers, downloads and the hand-over to an SSE
// stream. What a request means is web/routes.cpp's; included by connection_plain/_tls.cpp.
#pragma once

#include "web/exchange.hpp"
#include "web/routes.hpp"

namespace rangekit::web::detail {

template <class Stream>  // PlainStream, or TlsStream when the service has a certificate
class Connection final : public Exchange {
  // Room in the read buffer beside the headers, for the first bytes of a body read with them.
  static constexpr std::size_t kLineSlack = 4096;

 public:
  // The read buffer holds the headers, or one line of a chunked body, and no more: Beast
  // bounds the headers but not a chunk-size line, which could otherwise grow without end.
  Connection(Stream stream, Server::Impl& server)
      : Exchange(server), stream_(std::move(stream)), buffer_(server.options.max_header_bytes + kLineSlack) {
    ++server_.connections;
  }
  ~Connection() override {
    if (ticket_) server_.stop_waiting(*ticket_);
    --server_.connections;
  }
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // TLS: the handshake first (bounded like a read), so that even a refusal is spoken in TLS;
  // then the request, or over the connection limit one answer that says so. A handshake
  // waits like a request does: a client that never finishes one can be closed for a new one.
  void start(bool over_limit) {
    if constexpr (std::is_same_v<Stream, TlsStream>) {
      tcp_of(stream_).expires_after(std::chrono::seconds(30));
      if (!over_limit) ticket_ = server_.wait_for_request(close_when_evicted());
      stream_.async_handshake(net::ssl::stream_base::server, [self = shared(), over_limit](beast::error_code error) {
        self->stop_waiting();
        if (error) return self->close();  // not TLS, or a certificate the client refused
        over_limit ? self->refuse() : self->read();
      });
    } else {
      over_limit ? refuse() : read();
    }
  }

  void read() {
    parser_.emplace();
    parser_->body_limit(server_.options.max_body_bytes);
    parser_->header_limit(static_cast<std::uint32_t>(server_.options.max_header_bytes));
    tcp_of(stream_).expires_after(server_.options.request_timeout);  // an idle or trickling client is closed
    // Over the limit, the service may close the oldest waiting connection for a new client.
    // It is called on the event loop, like this connection's handlers: no read is under way elsewhere.
    ticket_ = server_.wait_for_request(close_when_evicted());
    http::async_read(stream_, buffer_, *parser_,
                     [self = shared()](beast::error_code error, std::size_t) { self->on_read(error); });
  }

  // Over the connection limit: one answer, then closed.
  void refuse() {
    tcp_of(stream_).expires_after(std::chrono::seconds(10));
    respond(http::status::service_unavailable,
            error_json("too_many_connections", "the service has " + std::to_string(server_.options.max_connections) +
                                                   " connections open; try again later"),
            false);
  }

  [[nodiscard]] bool tls() const override { return std::is_same_v<Stream, TlsStream>; }

  void send(std::shared_ptr<Response> response) override {
    http::async_write(stream_, *response, [self = shared(), response](beast::error_code error, std::size_t) {
      if (error || response->need_eof()) return self->close();
      self->read();
    });
  }

  void send_file(std::shared_ptr<http::response<http::file_body>> response) override {
    auto serializer = std::make_shared<http::response_serializer<http::file_body>>(*response);
    bound_send_buffer(tcp_of(stream_));  // the file waits on disk for a slow client, not in the kernel
    write_file_part(std::move(response), std::move(serializer));
  }

  void open_stream(hub::SubscriptionPtr subscription, StreamStart start, const EventStreamOptions& options) override {
    auto stream = std::make_shared<EventStream<Stream>>(std::move(stream_), std::move(subscription), std::move(start),
                                                        options, server_.ticker, server_.streams, server_.frames);
    stream->start();
  }

 private:
  std::shared_ptr<Connection> shared() { return std::static_pointer_cast<Connection>(shared_from_this()); }

  std::function<void()> close_when_evicted() {
    return [weak = std::weak_ptr<Connection>(shared())] {
      if (auto self = weak.lock()) self->close();
    };
  }
  void stop_waiting() {
    if (ticket_) server_.stop_waiting(*ticket_);
    ticket_.reset();
  }

  void on_read(beast::error_code error) {
    stop_waiting();
    if (error == http::error::end_of_stream || error == beast::error::timeout || error == net::error::eof) {
      return close();
    }
    if (error == http::error::body_limit) {
      return respond(http::status::payload_too_large,
                     error_json("body_too_large",
                                "bodies are limited to " + std::to_string(server_.options.max_body_bytes) + " bytes"),
                     false);
    }
    if (error == http::error::buffer_overflow) {
      return respond(http::status::bad_request,
                     error_json("line_too_long", "a chunk-size line is limited to " +
                                                     std::to_string(server_.options.max_header_bytes) + " bytes"),
                     false);
    }
    if (error == http::error::header_limit) {
      return respond(http::status::request_header_fields_too_large,
                     error_json("headers_too_large", "headers are limited to " +
                                                         std::to_string(server_.options.max_header_bytes) + " bytes"),
                     false);
    }
    if (error) {
      return respond(http::status::bad_request, error_json("bad_request", "not an HTTP request: " + error.message()),
                     false);
    }
    ++server_.requests;
    request_ = parser_->release();
    route(*this);
  }

  void close() {
    beast::error_code ignored;
    tcp_of(stream_).socket().shutdown(tcp::socket::shutdown_both, ignored);
    tcp_of(stream_).socket().close(ignored);
  }

  // One piece of a download at a time, the deadline renewed before each: it is cut only when
  // the client takes nothing for a whole request_timeout, however long it runs.
  void write_file_part(std::shared_ptr<http::response<http::file_body>> response,
                       std::shared_ptr<http::response_serializer<http::file_body>> serializer) {
    tcp_of(stream_).expires_after(server_.options.request_timeout);
    http::async_write_some(stream_, *serializer,
                           [self = shared(), response, serializer](beast::error_code failed, std::size_t) {
                             if (failed) return self->close();
                             if (!serializer->is_done()) return self->write_file_part(response, serializer);
                             if (response->need_eof()) return self->close();
                             self->read();
                           });
  }

  Stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::optional<std::uint64_t> ticket_;  // while waiting for a request (Server::Impl::wait_for_request)
};

// A connection over the limit takes the place of the oldest one still waiting for its
// request, or gets one answer and is closed; the others start.
template <class Stream>
void admit(Stream stream, Server::Impl& server) {
  auto connection = std::make_shared<Connection<Stream>>(std::move(stream), server);
  const bool over_limit = server.connections.load() > server.options.max_connections && !server.evict_oldest_waiting();
  if (over_limit) ++server.refused;
  connection->start(over_limit);
}

}  // namespace rangekit::web::detail
