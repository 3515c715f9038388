// The HTTP face of the sensor hub (docs/api.md): JSON API, resumable Server-Sent Events,
// Prometheus metrics and a health check on Boost.Beast over one asio event loop. It reaches
// the sensors only through rangekit::hub::Hub.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rangekit/core/result.hpp"
#include "rangekit/core/udp.hpp"
#include "rangekit/hub/captures.hpp"
#include "rangekit/hub/hub.hpp"

namespace rangekit::web {

// One file of the browser dashboard (web/, docs/dashboard.md), embedded in the CLI at build time.
struct StaticAsset {
  std::string_view path;          // "/" for index.html, "/assets/app-3F2A.js"
  std::string_view content_type;  // "text/html; charset=utf-8"
  std::string_view body;
  std::string_view etag;   // "\"<sha256 prefix>\"": a browser revalidates with If-None-Match
  bool immutable = false;  // a name with its content hash in it: cached for a year
};

// Another face of the same service (the MQTT bridge), as GET /healthz reports it. The
// service fills it in; the server knows nothing of what it describes.
struct FaceHealth {
  std::string name;   // "mqtt"
  bool ok = true;     // false: /healthz says "degraded"
  std::string error;  // why not ok, in one sentence
  bool connected = false;
  std::string peer;                               // what it connects to ("mqtt://127.0.0.1:1883")
  std::map<std::string, std::uint64_t> counters;  // "published", "dropped", ...
};

// A historian sink of the same service (docs/sinks.md), as GET /api/sinks, GET /metrics and
// GET /healthz report it. The service fills it in; the server knows no historian.
struct SinkHealth {
  std::string kind;               // "influx"
  std::string url;                // as it may be shown: any password already replaced by ***
  bool up = false;                // the historian confirmed the last write
  std::string error;              // why the last write failed; not empty: /healthz says "degraded"
  std::uint64_t written = 0;      // rows confirmed, since the start
  std::uint64_t spooled = 0;      // rows waiting in the spool now
  std::uint64_t spool_bytes = 0;  // their size
  std::uint64_t dropped = 0;      // rows lost past the spool's cap or the intake's queue
  std::uint64_t rejected = 0;     // rows the historian refused as malformed
  std::uint64_t failures = 0;     // writes that failed, to be retried
  double oldest_age_s = 0;        // of the oldest spooled row; 0 when none waits
};

struct ServerOptions {
  std::string listen = "127.0.0.1:8080";  // HOST:PORT; port 0 picks a free one
  // Required (Authorization: Bearer, or ?token= for EventSource) on every write and
  // every stream when not empty. The service sets it whenever it listens beyond loopback.
  std::string token;
  // Connections serving requests, and open streams: each limit its own, so that streams
  // cannot keep requests (/healthz among them) out, and both bound the descriptors held.
  std::size_t max_connections = 256;
  std::size_t max_streams = 256;
  std::size_t max_body_bytes = std::size_t{64} * 1024;
  std::size_t max_header_bytes = std::size_t{8} * 1024;
  // How long one request may take to arrive, and how long a download may go without the
  // client taking any of it (a download that keeps moving is never cut).
  std::chrono::milliseconds request_timeout{60000};
  // Items a stream client may fall behind before it is cut off (it resumes with Last-Event-ID).
  std::size_t stream_queue = 4096;
  // How long the SSE streams gather items before they write (one wake-up and one write per
  // client per tick): the latency it adds against the CPU of many small writes. Each write is
  // a loopback/TCP send whose kernel cost dominates the service (perf); 8 ms keeps p99 from
  // the pty to the browser near 13 ms (goal 20 ms) and is below one 60 Hz frame.
  std::chrono::milliseconds stream_tick{8};
  std::size_t command_threads = 4;          // settings and actions wait for the sensor here, not in the event loop
  hub::CaptureManager* captures = nullptr;  // /api/captures; none: those paths answer 404
  // HTTPS and TLS streams when both are given (PEM files): [service] tls_certificate, tls_key.
  std::string tls_certificate;
  std::string tls_key;
  // The dashboard's files, answered to GET like the API's reads (no token, no Host check:
  // they hold no sensor data). Empty: every path outside /api is 404.
  std::span<const StaticAsset> assets;
  // The other faces' health, asked on each GET /healthz (called on the event loop: keep it quick).
  std::function<std::vector<FaceHealth>()> faces;
  // The historian sinks, asked on each GET /api/sinks, /metrics and /healthz (on the event
  // loop too). None: /api/sinks answers [].
  std::function<std::vector<SinkHealth>()> sinks;
};

struct ServerStats {
  std::uint64_t connections = 0;      // open now
  std::uint64_t streams = 0;          // SSE clients now
  std::uint64_t requests = 0;         // since the start
  std::uint64_t refused = 0;          // over the connection limit
  std::uint64_t streams_cut_off = 0;  // clients that fell behind
};

class Server {
 public:
  // Binds and starts serving on a thread of its own.
  static Result<std::unique_ptr<Server>> start(hub::Hub& hub, ServerOptions options);
  ~Server();  // stop()
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;
  // Closes the listener and every connection, joins the threads. Idempotent.
  void stop();
  [[nodiscard]] Endpoint local_endpoint() const;
  [[nodiscard]] ServerStats stats() const;

  struct Impl;  // opaque: the event loop and its connections

 private:
  explicit Server(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// True for "localhost" and the literal loopback addresses (127.0.0.0/8 dotted, ::1, [::1]);
// not for a name that merely starts with "127.".
bool is_loopback_host(const std::string& host);

// The token of a service listening beyond loopback: read from `path`, or made (32
// random bytes as hex) and written there with mode 0600 when the file does not exist.
struct Token {
  std::string value;
  bool created = false;  // print it once, when made
};
Result<Token> load_or_create_token(const std::string& path);

}  // namespace rangekit::web
