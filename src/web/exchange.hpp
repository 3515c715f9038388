// One request a connection has read and the ways to answer it, whatever the stream: the
// route table and its handlers see a connection only through this, so they compile once
// instead of once per stream (web/connection.hpp implements it for plain and TLS).
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "web/event_stream.hpp"
#include "web/json_views.hpp"
#include "web/server_impl.hpp"

namespace rangekit::web {

class Exchange : public std::enable_shared_from_this<Exchange> {
 public:
  explicit Exchange(Server::Impl& server) : server_(server) {}
  Exchange(const Exchange&) = delete;
  Exchange& operator=(const Exchange&) = delete;
  virtual ~Exchange() = default;

  [[nodiscard]] Server::Impl& server() const { return server_; }
  [[nodiscard]] const Request& request() const { return request_; }
  [[nodiscard]] virtual bool tls() const = 0;

  // A JSON (or content_type) answer; the connection then reads the next request, or closes
  // when keep_alive is false or the client asked for it.
  void respond(http::status status, std::string body, bool keep_alive = true,
               std::string_view content_type = "application/json", std::string_view allow = {});
  void fail(const Error& error, const hub::SettingValues& values = {});
  void not_found(const std::string& what);
  void wrong_method(std::string_view allow);

  // A finished answer, written as it is, then as respond().
  virtual void send(std::shared_ptr<Response> response) = 0;
  // A download, written a piece at a time as the client takes it.
  virtual void send_file(std::shared_ptr<http::response<http::file_body>> response) = 0;
  // The connection becomes an SSE stream (web/event_stream.hpp) and answers no more requests.
  virtual void open_stream(hub::SubscriptionPtr subscription, StreamStart start, const EventStreamOptions& options) = 0;

  // Runs a call that waits for the sensor on the command pool; answers on the loop.
  template <class Call, class Answer>
  void off_loop(Call call, Answer answer) {
    net::post(
        server_.commands, [self = shared_from_this(), call = std::move(call), answer = std::move(answer)]() mutable {
          auto result = call();
          self->server_.poster->post(
              [self, answer = std::move(answer), result = std::move(result)]() mutable { answer(std::move(result)); });
        });
  }

 protected:
  Server::Impl& server_;
  Request request_;
};

}  // namespace rangekit::web
